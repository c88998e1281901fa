//! `tone-burst`: a Hann tone burst through a short chain, one panel per frequency (a pass band
//! and a stop band of the lattice): the base motion and each cell's outer displacement as
//! traces offset row by row against time, all at one scale per panel, impacts marked.

use crate::figures::plot::{err, text, Figure};
use crate::study::signals::{BurstPanel, ToneBurstStudy};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Colour of the traces.
const TRACE: RGBColor = RGBColor(30, 80, 160);
/// Colour of the base motion's trace.
const BASE: RGBColor = RGBColor(90, 90, 90);
/// Colour of the impact marks.
const IMPACT: RGBColor = RGBColor(210, 40, 40);
/// Half the height a trace may take of its row at its panel's largest displacement.
const ROW_FILL: f64 = 0.45;

/// `tone-burst`.
#[derive(Debug, Clone)]
pub struct ToneBurst<'a>(pub &'a ToneBurstStudy);

/// The value of `series` at `t` on the sample times `times` (linear between samples).
fn at(times: &[f64], series: &[f64], t: f64) -> f64 {
    let k = times.partition_point(|&s| s < t);
    match (k.checked_sub(1), times.get(k)) {
        (Some(i), Some(&t1)) if t1 > times[i] => {
            let w = (t - times[i]) / (t1 - times[i]);
            series[i] + w * (series[k] - series[i])
        }
        (_, Some(_)) => series[k],
        (Some(i), None) => series[i],
        (None, None) => 0.0,
    }
}

/// One panel: the rows (base, then the cells from the base) of `p` over `[0, duration]`.
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    study: &ToneBurstStudy,
    p: &BurstPanel,
) -> Result<(), String> {
    let largest = p
        .outer
        .iter()
        .flatten()
        .chain(&p.base)
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    let scale = if largest > 0.0 {
        ROW_FILL / largest
    } else {
        1.0
    };
    let cells = p.outer.len();
    let band = if p.in_stop_band {
        "in the stop band"
    } else {
        "in the pass band"
    };
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!(
                "ω = {} rad/s ({band}; lattice |Im q| = {:.2} per cell), {} cycles, A = {} m: \
                 last/first cell peak {:.1} dB, {} impacts",
                p.omega,
                p.lattice_attenuation,
                p.cycles,
                p.amplitude,
                p.first_to_last_db(),
                p.impacts.len()
            ),
            text(17),
        )
        .margin(14)
        .x_label_area_size(42)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..study.duration, -0.6..cells as f64 + 0.6)
        .map_err(err)?;
    chart
        .configure_mesh()
        .y_labels(cells + 1)
        .y_label_formatter(&|y| match y.round() as i64 {
            0 => "base u_g".to_owned(),
            j => format!("cell {j}"),
        })
        .x_desc("time t (s)")
        .y_desc(format!("u_o,j (one row = {:.2} m)", 1.0 / scale))
        .label_style(text(14))
        .axis_desc_style(text(15))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(err)?;
    chart
        .draw_series(DashedLineSeries::new(
            [
                (p.burst_duration, -0.6),
                (p.burst_duration, cells as f64 + 0.6),
            ],
            6,
            4,
            BLACK.mix(0.5).stroke_width(1),
        ))
        .map_err(err)?
        .label(format!("end of the burst, {:.1} s", p.burst_duration))
        .legend(|(x, y)| {
            PathElement::new(vec![(x, y), (x + 16, y)], BLACK.mix(0.5).stroke_width(1))
        });
    chart
        .draw_series(LineSeries::new(
            p.times.iter().zip(&p.base).map(|(&t, &u)| (t, u * scale)),
            BASE.stroke_width(1),
        ))
        .map_err(err)?;
    for (j, series) in p.outer.iter().enumerate() {
        let row = j as f64 + 1.0;
        chart
            .draw_series(LineSeries::new(
                p.times
                    .iter()
                    .zip(series)
                    .map(|(&t, &u)| (t, row + u * scale)),
                TRACE.stroke_width(1),
            ))
            .map_err(err)?;
    }
    chart
        .draw_series(p.impacts.iter().filter_map(|&(t, cell)| {
            let series = p.outer.get(cell)?;
            let y = cell as f64 + 1.0 + at(&p.times, series, t) * scale;
            Some(Circle::new((t, y), 3, IMPACT.filled()))
        }))
        .map_err(err)?
        .label("impact on a stop")
        .legend(|(x, y)| Circle::new((x + 8, y), 4, IMPACT.filled()));
    chart
        .configure_series_labels()
        .label_font(text(13))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .position(SeriesLabelPosition::LowerRight)
        .draw()
        .map_err(err)
}

impl Figure for ToneBurst<'_> {
    fn name(&self) -> &str {
        "tone-burst"
    }

    fn size(&self) -> (u32, u32) {
        (1400, 1100)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let s = self.0;
        let (title, body) = root.split_vertically(40);
        title
            .draw(&Text::new(
                format!(
                    "Hann tone burst from rest through {} cells of scene '{}' (exact response, \
                     rattle respond): outer displacement of each cell from the base",
                    s.cells, s.scene_name
                ),
                (20, 10),
                text(19),
            ))
            .map_err(err)?;
        let panels = body.split_evenly((s.panels.len().max(1), 1));
        for (area, p) in panels.iter().zip(&s.panels) {
            panel(area, s, p)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::at;

    #[test]
    fn a_trace_is_read_between_its_samples_and_held_beyond_them() {
        let times = [0.0, 1.0, 2.0];
        let series = [0.0, 2.0, 4.0];
        assert_eq!(at(&times, &series, 0.5), 1.0);
        assert_eq!(at(&times, &series, 2.0), 4.0);
        assert_eq!(at(&times, &series, 3.0), 4.0);
        assert_eq!(at(&times, &series, -1.0), 0.0);
    }
}
