//! Siconos as a peer: what `crates/compare/peers/siconos_unit.py` measured with Siconos's
//! event-driven scheme (Lsodar between events) and its Moreau–Jean time stepping on the same
//! unit, read back from the JSON it writes (committed as [`SICONOS_DATA`], so that the figures
//! and the report show it without Siconos installed; `cargo xtask peers` rewrites it).
//!
//! Nothing here runs Siconos or a solver: the numbers are the script's. A Siconos run that
//! failed is a result (its `failure` says how), not an error of this module.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// The committed Siconos results, relative to the repository's root.
pub const SICONOS_DATA: &str = "data/peers/siconos.json";

/// Why the Siconos results could not be read.
#[derive(Debug, Error)]
pub enum SiconosDataError {
    /// The file exists but could not be read.
    #[error("{path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// The file is not the script's JSON; `field` is the JSON path where it differs.
    #[error("{path}: at {field}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// JSON path of the offending value (`.` for the document).
        field: String,
        /// What is wrong there.
        message: String,
    },
}

/// One Siconos run at one setting of its accuracy knob.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SiconosRun {
    /// The knob: Lsodar's relative (and absolute) tolerance for the event-driven scheme, the
    /// time step (s) for Moreau–Jean.
    pub knob: f64,
    /// CPU time (user + system) of the simulation loop (model built, Python driving it event
    /// by event or step by step), seconds; the minimum of the repeats.
    pub seconds: Option<f64>,
    /// Impacts over the run (Moreau–Jean: steps that open a contact with a positive impulse).
    pub impacts: Option<u64>,
    /// The outer amplitude `max|u_o|` over the last cycle; absent when the run failed.
    #[serde(default)]
    pub outer_amplitude: Option<f64>,
    /// Moreau–Jean only: the deepest penetration of a stop over the run, `max(|r| − Δ, 0)`, m.
    #[serde(default)]
    pub penetration: Option<f64>,
    /// How Siconos failed, in its own words, with the time it reached; `None` when it ran.
    #[serde(default)]
    pub failure: Option<String>,
}

impl SiconosRun {
    /// `|X − reference| / |reference|` of the outer amplitude, when the run gave one.
    pub fn relative_error(&self, reference: f64) -> Option<f64> {
        let x = self.outer_amplitude.filter(|_| self.failure.is_none())?;
        Some((x - reference).abs() / reference.abs())
    }

    /// Seconds per impact, when the run had impacts.
    pub fn seconds_per_impact(&self) -> Option<f64> {
        match (self.seconds, self.impacts) {
            (Some(s), Some(n)) if n > 0 => Some(s / n as f64),
            _ => None,
        }
    }
}

/// The work-precision case (the figure's scene, frequency and periods from rest), each scheme
/// over its knob.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SiconosWorkPrecision {
    /// Scene file, relative to the repository's root.
    pub scene: String,
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// Periods run from rest.
    pub periods: u64,
    /// The event-driven scheme over Lsodar's tolerance.
    pub event_driven: Vec<SiconosRun>,
    /// Moreau–Jean over its time step.
    pub moreau_jean: Vec<SiconosRun>,
}

/// `rattle simulate` on the same case, as the script ran it (whole process).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RattleRun {
    /// `status` of the run.
    pub status: String,
    /// Canonical signature of the steady state, when periodic.
    #[serde(default)]
    pub signature: Option<String>,
    /// Outer amplitude of the steady state, m.
    pub outer_amplitude: Option<f64>,
    /// Outer amplitude after the fixed number of periods the Siconos runs take, m.
    #[serde(default)]
    pub fixed_periods_outer_amplitude: Option<f64>,
    /// Impacts over the fixed number of periods.
    pub impacts: u64,
    /// CPU time (user + system) of the whole process over the fixed number of periods,
    /// seconds (minimum of the repeats).
    pub seconds: f64,
}

impl RattleRun {
    /// Seconds per impact, when the run had impacts.
    pub fn seconds_per_impact(&self) -> Option<f64> {
        (self.impacts > 0).then(|| self.seconds / self.impacts as f64)
    }
}

/// rattle's steady state beside Siconos's at one frequency, all run the same periods from rest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteadyStateRow {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// Periods run from rest by every solver.
    pub periods: u64,
    /// Periods of the steady cycle (the amplitude is taken over the last cycle).
    pub cycle_periods: u64,
    /// rattle.
    pub rattle: RattleRun,
    /// Siconos's event-driven scheme.
    pub event_driven: SiconosRun,
    /// Siconos's Moreau–Jean scheme.
    pub moreau_jean: SiconosRun,
}

/// A hard case (grazing, sticking): what each solver does.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HardCaseRow {
    /// `grazing` or `sticking`.
    pub case: String,
    /// Scene file, relative to the repository's root.
    pub scene: String,
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// Periods run from rest.
    pub periods: u64,
    /// rattle.
    pub rattle: RattleRun,
    /// Siconos's event-driven scheme.
    pub event_driven: SiconosRun,
    /// Siconos's Moreau–Jean scheme.
    pub moreau_jean: SiconosRun,
}

/// The script's settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SiconosSettings {
    /// `EventDriven::setToleranceED`.
    pub tolerance_ed: f64,
    /// Output points per period of the event-driven scheme.
    pub ed_outputs_per_period: u64,
    /// Moreau–Jean's θ.
    pub theta: f64,
    /// Lsodar's tolerance in the steady-state and hard-case runs.
    pub steady_tolerance: f64,
    /// Moreau–Jean's time step in the steady-state and hard-case runs, s.
    pub steady_time_step: f64,
}

/// Everything the script measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SiconosPeer {
    /// Version of Debian's `python3-siconos`.
    pub siconos: String,
    /// Python's version.
    pub python: String,
    /// The machine, as the script saw it.
    pub machine: String,
    /// The script's settings.
    pub settings: SiconosSettings,
    /// The work-precision case.
    pub work_precision: SiconosWorkPrecision,
    /// Steady states at a few frequencies.
    pub steady_states: Vec<SteadyStateRow>,
    /// The grazing and sticking cases.
    pub hard_cases: Vec<HardCaseRow>,
}

impl SiconosPeer {
    /// Parses the script's JSON; `origin` names it in errors.
    ///
    /// # Errors
    /// [`SiconosDataError::Parse`] with the JSON path of the first value that does not fit.
    pub fn parse(text: &str, origin: &Path) -> Result<SiconosPeer, SiconosDataError> {
        let mut de = serde_json::Deserializer::from_str(text);
        serde_path_to_error::deserialize(&mut de).map_err(|e| SiconosDataError::Parse {
            path: origin.to_owned(),
            field: e.path().to_string(),
            message: e.inner().to_string(),
        })
    }

    /// Reads `path`: `Ok(None)` when there is no such file (Siconos never ran here).
    ///
    /// # Errors
    /// [`SiconosDataError::Read`] when the file exists but cannot be read,
    /// [`SiconosDataError::Parse`] when it is not the script's JSON.
    pub fn load(path: &Path) -> Result<Option<SiconosPeer>, SiconosDataError> {
        match std::fs::read_to_string(path) {
            Ok(text) => Self::parse(&text, path).map(Some),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(source) => Err(SiconosDataError::Read {
                path: path.to_owned(),
                source,
            }),
        }
    }

    /// The work-precision runs when they are of the case of scene file `scene` (as given to
    /// the script, relative to the repository's root) at `omega` over `periods` periods (the
    /// figure's), else `None`.
    pub fn work_precision_for(
        &self,
        scene: &str,
        omega: f64,
        periods: u64,
    ) -> Option<&SiconosWorkPrecision> {
        let wp = &self.work_precision;
        (wp.scene == scene && wp.omega == omega && wp.periods == periods).then_some(wp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(amplitude: Option<f64>, failure: Option<&str>) -> SiconosRun {
        SiconosRun {
            knob: 1e-8,
            seconds: Some(2.0),
            impacts: Some(400),
            outer_amplitude: amplitude,
            penetration: None,
            failure: failure.map(str::to_owned),
        }
    }

    #[test]
    fn errors_and_costs_of_a_run() {
        assert_eq!(
            run(Some(1.1), None).relative_error(1.0),
            Some(0.10000000000000009)
        );
        assert_eq!(
            run(Some(1.1), Some("std::exception")).relative_error(1.0),
            None
        );
        assert_eq!(run(None, None).relative_error(1.0), None);
        assert_eq!(run(None, None).seconds_per_impact(), Some(0.005));
    }

    #[test]
    fn a_wrong_document_is_refused_with_its_json_path() {
        let err = SiconosPeer::parse(r#"{"siconos": 4}"#, Path::new("s.json"))
            .expect_err("not the script's JSON");
        let text = err.to_string();
        assert!(
            text.contains("s.json") && text.contains("siconos"),
            "{text}"
        );
    }

    #[test]
    fn a_missing_file_is_no_data() {
        let path = Path::new("/no/such/dir/siconos.json");
        assert!(matches!(SiconosPeer::load(path), Ok(None)));
    }
}
