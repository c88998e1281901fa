//! The paper's Figure 4: the linear response with the walls ignored (left) beside the impacting
//! steady state (right) — the analytic orbit as curves with simulated points on it, or the
//! simulated motion where no viable orbit exists.

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::plots::{ImpactTimeResponse, Samples};
use plotters::coord::Shift;
use plotters::prelude::*;

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    gap: f64,
    curves: &Samples,
    points: &Samples,
) -> Result<(), String> {
    let tmax = curves
        .iter()
        .chain(points)
        .map(|p| p.0)
        .fold(0.0, f64::max)
        .max(1e-9);
    let tmin = curves
        .iter()
        .chain(points)
        .map(|p| p.0)
        .fold(f64::INFINITY, f64::min)
        .min(tmax - 1e-9);
    let ymax = curves
        .iter()
        .chain(points)
        .map(|p| p.1.abs().max(p.2.abs()) + gap)
        .fold(0.1, f64::max)
        * 1.1;
    let mut chart = ChartBuilder::on(area)
        .caption(title, text(20))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(tmin..tmax, -ymax..ymax)
        .map_err(err)?;
    axes(&mut chart, "time t (s)", "displacement (m)", 14)?;
    let blue = RGBColor(30, 90, 220);
    let red = RGBColor(220, 40, 40);
    let grey = RGBColor(110, 110, 110);
    let source = if curves.is_empty() { points } else { curves };
    // Walls follow the outer mass.
    for sign in [1.0, -1.0] {
        let walls = chart
            .draw_series(DashedLineSeries::new(
                source.iter().map(|p| (p.0, p.1 + sign * gap)),
                5,
                4,
                grey.stroke_width(1),
            ))
            .map_err(err)?;
        if sign > 0.0 {
            walls.label("walls u_o ± Δ").legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], grey.stroke_width(1))
            });
        }
    }
    if !curves.is_empty() {
        chart
            .draw_series(LineSeries::new(
                curves.iter().map(|p| (p.0, p.1)),
                blue.stroke_width(2),
            ))
            .map_err(err)?
            .label("outer mass u_o")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], blue.stroke_width(2))
            });
        chart
            .draw_series(LineSeries::new(
                curves.iter().map(|p| (p.0, p.2)),
                red.stroke_width(2),
            ))
            .map_err(err)?
            .label("inner mass u_i")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], red.stroke_width(2)));
    }
    if !points.is_empty() {
        let step = (points.len() / 60).max(1);
        chart
            .draw_series(
                points
                    .iter()
                    .step_by(step)
                    .map(|p| Circle::new((p.0, p.1), 3, blue.filled())),
            )
            .map_err(err)?
            .label("simulated u_o")
            .legend(move |(x, y)| Circle::new((x + 9, y), 3, blue.filled()));
        chart
            .draw_series(
                points
                    .iter()
                    .step_by(step)
                    .map(|p| Circle::new((p.0, p.2), 3, red.filled())),
            )
            .map_err(err)?
            .label("simulated u_i")
            .legend(move |(x, y)| Circle::new((x + 9, y), 3, red.filled()));
    }
    legend(&mut chart, SeriesLabelPosition::LowerRight, 12)?;
    Ok(())
}

impl Figure for ImpactTimeResponse {
    fn name(&self) -> &str {
        "impact-time-response"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 500 * self.rows.len().max(1) as u32 + 50)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let (title, body) = root.split_vertically(50);
        title
            .draw_text(
                &format!(
                    "Linear (walls ignored) vs impacting steady state, scene '{}', Δ = {}",
                    self.scene_name, self.gap
                ),
                &text(24),
                (20, 12),
            )
            .map_err(err)?;
        let rows = body.split_evenly((self.rows.len().max(1), 2));
        for (i, row) in self.rows.iter().enumerate() {
            panel(
                &rows[2 * i],
                &format!("ω = {} rad/s: linear, walls ignored", row.omega),
                self.gap,
                &row.linear,
                &Vec::new(),
            )?;
            panel(
                &rows[2 * i + 1],
                &format!("ω = {} rad/s: {}", row.omega, row.note),
                self.gap,
                row.orbit.as_ref().unwrap_or(&Vec::new()),
                &row.simulated,
            )?;
        }
        Ok(())
    }
}
