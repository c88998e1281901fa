//! Impact signatures: which stops are hit, in time order, over one least period of the motion.
//!
//! A signature is a string of `+` (side 1, `r = +Δ`) and `-` (side 2, `r = −Δ`) with the
//! number `p` of forcing periods in the cycle. A cycle and any of its rotations are the same
//! motion (the first impact is a matter of where the clock starts), so every output uses the
//! canonical form: the rotation smallest in ASCII order (`+` before `-`).

use std::fmt;
use thiserror::Error;

/// Largest number of forcing periods in a cycle that [`Signature::parse`] and
/// [`Signature::from_sides`] accept: the multi-start search of [`crate::signature_orbits`]
/// grows with the cycle's length, and subharmonics beyond period 8 are beyond what a search
/// over impact phases can afford. A cycle read from a simulation has its own cap,
/// [`MAX_CYCLE_PERIOD`].
pub const MAX_PERIOD: u32 = 8;

/// Largest number of impacts in a signature that [`Signature::parse`] and
/// [`Signature::from_sides`] accept: the multi-start grid grows like the number of ordered
/// impact-phase tuples, `C(N, n − 1)`, and is coarsened to no fewer than 16 intervals, so 16
/// impacts is the most a systematic search over impact phases can hold.
/// A cycle read from a simulation has its own cap, [`MAX_CYCLE_IMPACTS`].
pub const MAX_IMPACTS: usize = 16;

/// Largest number of impacts in a signature read from a simulated cycle
/// ([`Signature::from_cycle`]). Such a signature is solved by Newton from the cycle's own
/// impact phases, with no search: its cost grows like `n` flights and one `n × n` solve per
/// iteration, so the cap only bounds the work on absurd input; it is at least 128, so that the long
/// cycles simulations settle on are compared rather than refused.
pub const MAX_CYCLE_IMPACTS: usize = 256;

/// Largest number of forcing periods of a signature read from a simulated cycle
/// ([`Signature::from_cycle`]): the simulator reports least periods up to its
/// `max_period_multiplicity` (16 by default); a cycle is solved from its own phases, so
/// its period costs nothing but the length of its flights.
pub const MAX_CYCLE_PERIOD: u32 = 64;

/// A signature that cannot be used, with the field it came from.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum SignatureError {
    /// The signature text is empty.
    #[error("--signature is empty: must be a non-empty string of '+' (side 1) and '-' (side 2)")]
    Empty,
    /// The signature text holds a character other than `+` and `-`.
    #[error(
        "--signature = {text:?} holds {found:?}: only '+' (side 1) and '-' (side 2) are allowed"
    )]
    BadCharacter {
        /// The rejected text.
        text: String,
        /// The first character that is neither `+` nor `-`.
        found: char,
    },
    /// The signature has more impacts than [`MAX_IMPACTS`] (or, read from a simulated cycle,
    /// than [`MAX_CYCLE_IMPACTS`]).
    #[error(
        "--signature has {impacts} impacts: at most {max} are allowed{}",
        if *max == MAX_IMPACTS { SEARCH_REASON } else { "" }
    )]
    TooManyImpacts {
        /// Number of impacts given.
        impacts: usize,
        /// The cap, [`MAX_IMPACTS`] or [`MAX_CYCLE_IMPACTS`].
        max: usize,
    },
    /// The period is zero or above [`MAX_PERIOD`].
    #[error("--period = {period} is out of range: must be an integer in 1..={max}")]
    Period {
        /// The rejected period.
        period: u32,
        /// The cap, [`MAX_PERIOD`].
        max: u32,
    },
    /// A side given to [`Signature::from_sides`] is neither `+1` nor `−1`.
    #[error("--signature side {side} is not allowed: sides are +1 (side 1) or -1 (side 2)")]
    BadSide {
        /// The rejected side.
        side: i8,
    },
}

/// Why a signature given to search for is capped, as the error says it.
const SEARCH_REASON: &str = ": the multi-start search tries every ordering of impact phases \
     on a grid, C(N, n − 1) of them; a longer signature read from a simulated cycle is solved \
     from the cycle's own phases (`rattle compare`, `rattle sweep --solver both`)";

/// The sequence of stops hit over one cycle of `period` forcing periods, in canonical form.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Signature {
    sides: Vec<i8>,
    period: u32,
}

impl Signature {
    /// Parses a signature such as `"++--"` with its period in forcing periods. Any rotation
    /// is accepted; the result is canonical.
    ///
    /// # Errors
    /// [`SignatureError`] naming `--signature` (empty, a character other than `+`/`-`, more
    /// than [`MAX_IMPACTS`] impacts) or `--period` (0 or above [`MAX_PERIOD`]).
    pub fn parse(text: &str, period: u32) -> Result<Self, SignatureError> {
        let text = text.trim();
        if text.is_empty() {
            return Err(SignatureError::Empty);
        }
        let sides = text
            .chars()
            .map(|c| match c {
                '+' => Ok(1),
                '-' => Ok(-1),
                found => Err(SignatureError::BadCharacter {
                    text: text.to_string(),
                    found,
                }),
            })
            .collect::<Result<Vec<i8>, _>>()?;
        Self::from_sides(&sides, period)
    }

    /// The signature of a sequence of sides (`+1` side 1, `−1` side 2) to search for, with the
    /// caps of the multi-start search ([`MAX_IMPACTS`], [`MAX_PERIOD`]).
    ///
    /// # Errors
    /// As [`Signature::parse`], and [`SignatureError::BadSide`] for a side other than `±1`.
    pub fn from_sides(sides: &[i8], period: u32) -> Result<Self, SignatureError> {
        Self::with_caps(sides, period, MAX_IMPACTS, MAX_PERIOD)
    }

    /// The signature of the impacts of a simulated cycle over `period` forcing periods, to
    /// be solved from the cycle's own impact phases: up to [`MAX_CYCLE_IMPACTS`] impacts and
    /// [`MAX_CYCLE_PERIOD`] periods. Such a signature may be longer than the multi-start
    /// search takes ([`Signature::is_searchable`]).
    ///
    /// # Errors
    /// [`SignatureError`] for an empty cycle, a side other than `±1`, or more impacts or
    /// periods than those caps.
    pub fn from_cycle(sides: &[i8], period: u32) -> Result<Self, SignatureError> {
        Self::with_caps(sides, period, MAX_CYCLE_IMPACTS, MAX_CYCLE_PERIOD)
    }

    /// Whether the multi-start search takes this signature: at most [`MAX_IMPACTS`] impacts
    /// and [`MAX_PERIOD`] periods (always so for one from [`Signature::parse`] or
    /// [`Signature::from_sides`]).
    pub fn is_searchable(&self) -> bool {
        self.sides.len() <= MAX_IMPACTS && self.period <= MAX_PERIOD
    }

    fn with_caps(
        sides: &[i8],
        period: u32,
        max_impacts: usize,
        max_period: u32,
    ) -> Result<Self, SignatureError> {
        if sides.is_empty() {
            return Err(SignatureError::Empty);
        }
        if let Some(&side) = sides.iter().find(|&&s| s != 1 && s != -1) {
            return Err(SignatureError::BadSide { side });
        }
        if sides.len() > max_impacts {
            return Err(SignatureError::TooManyImpacts {
                impacts: sides.len(),
                max: max_impacts,
            });
        }
        if period == 0 || period > max_period {
            return Err(SignatureError::Period {
                period,
                max: max_period,
            });
        }
        let shift = canonical_shift(sides);
        let n = sides.len();
        Ok(Self {
            sides: (0..n).map(|k| sides[(k + shift) % n]).collect(),
            period,
        })
    }

    /// The sides in canonical order: `+1` for side 1, `−1` for side 2.
    pub fn sides(&self) -> &[i8] {
        &self.sides
    }

    /// Number of forcing periods in the cycle.
    pub fn period(&self) -> u32 {
        self.period
    }

    /// Number of impacts in the cycle.
    pub fn impacts(&self) -> usize {
        self.sides.len()
    }

    /// The rotations `k` (`0 ≤ k < n`) that map the canonical string onto itself: starting the
    /// cycle at impact `k` gives the same signature. Always contains 0.
    pub fn symmetries(&self) -> Vec<usize> {
        let n = self.sides.len();
        (0..n)
            .filter(|&k| (0..n).all(|j| self.sides[(j + k) % n] == self.sides[j]))
            .collect()
    }
}

/// The rotation `k` for which `sides[k..] ++ sides[..k]` is smallest in ASCII order
/// (`+` = 43 before `-` = 45, i.e. side `+1` before `−1`); the first such `k`.
fn canonical_shift(sides: &[i8]) -> usize {
    let n = sides.len();
    // ASCII order of '+' < '-' is the reverse of the numeric order of +1 > −1.
    let key = |k: usize| (0..n).map(move |j| -sides[(j + k) % n]);
    (0..n)
        .min_by(|&a, &b| key(a).cmp(key(b)).then(a.cmp(&b)))
        .unwrap_or(0)
}

impl fmt::Display for Signature {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for &s in &self.sides {
            f.write_str(if s > 0 { "+" } else { "-" })?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotations_share_one_canonical_form() {
        for text in ["++--", "+--+", "--++", "-++-"] {
            assert_eq!(Signature::parse(text, 1).unwrap().to_string(), "++--");
        }
        assert_eq!(Signature::parse("-+", 1).unwrap().to_string(), "+-");
        assert_eq!(Signature::parse("+", 3).unwrap().to_string(), "+");
        assert_eq!(Signature::parse("-+-+-", 2).unwrap().to_string(), "+-+--");
        assert_eq!(
            Signature::parse("-+-+", 2).unwrap().symmetries(),
            vec![0, 2]
        );
        let s = Signature::from_sides(&[-1, -1, 1], 2).unwrap();
        assert_eq!((s.to_string(), s.period()), ("+--".to_string(), 2));
    }

    #[test]
    fn bad_signatures_are_refused_with_the_field_named() {
        let message = |r: Result<Signature, SignatureError>| r.unwrap_err().to_string();
        assert!(message(Signature::parse("", 1)).contains("--signature"));
        let m = message(Signature::parse("+x-", 1));
        assert!(
            m.contains("--signature") && m.contains("'+'") && m.contains("'-'"),
            "{m}"
        );
        let m = message(Signature::parse("+-", 0));
        assert!(m.contains("--period") && m.contains("1..=8"), "{m}");
        assert!(message(Signature::parse("+-", 9)).contains("--period"));
        assert!(message(Signature::parse(&"+".repeat(17), 1)).contains("--signature"));
        assert!(message(Signature::from_sides(&[1, 0], 1)).contains("--signature"));
        assert!(message(Signature::from_sides(&[], 1)).contains("--signature"));
    }

    /// A simulated cycle of 17–40 impacts is a signature, not refused by the search's cap:
    /// a cycle's signature is capped only by [`MAX_CYCLE_IMPACTS`] (≥ 128), a
    /// searched one by the search's [`MAX_IMPACTS`], whose message says why.
    #[test]
    fn a_simulated_cycle_is_capped_apart_from_the_search() {
        let message = |r: Result<Signature, SignatureError>| r.unwrap_err().to_string();
        let long: Vec<i8> = (0..128).map(|k| if k % 4 < 2 { 1 } else { -1 }).collect();
        let cycle = Signature::from_cycle(&long, 16).unwrap();
        assert_eq!((cycle.impacts(), cycle.period()), (128, 16));
        assert!(!cycle.is_searchable());
        assert!(Signature::from_cycle(&long[..16], 8)
            .unwrap()
            .is_searchable());
        let searched = message(Signature::from_sides(&long[..17], 1));
        assert!(searched.starts_with(
            "--signature has 17 impacts: at most 16 are allowed: the multi-start search"
        ));
        let too_long = message(Signature::from_cycle(&vec![1; MAX_CYCLE_IMPACTS + 1], 1));
        assert_eq!(
            too_long,
            "--signature has 257 impacts: at most 256 are allowed"
        );
        assert!(message(Signature::from_cycle(&long, MAX_CYCLE_PERIOD + 1)).contains("--period"));
    }
}
