//! `broadband-transmission`: the transmissibility of the unit and of the 5-cell chain under
//! band-limited random base motion at three levels, beside the linear structure's exact
//! response and the lattice's stop bands (the broadband study, [`BroadbandStudy`]).

use crate::figures::plot::{axes, err, legend, text, Figure};
use crate::study::broadband::{BroadbandCase, BroadbandStudy, BROADBAND_BAND};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Colours of the levels, below first contact to strong.
const LEVELS: [RGBColor; 3] = [
    RGBColor(0, 114, 178),
    RGBColor(230, 159, 0),
    RGBColor(213, 94, 0),
];
/// Colour of the exact linear response.
const LINEAR: RGBColor = RGBColor(90, 90, 90);
/// Shade of the lattice's stop bands.
const STOP_BAND: RGBColor = RGBColor(225, 225, 235);

/// `broadband-transmission`: one panel per structure.
#[derive(Debug, Clone)]
pub struct BroadbandTransmission<'a>(pub &'a BroadbandStudy);

impl Figure for BroadbandTransmission<'_> {
    fn name(&self) -> &str {
        "broadband-transmission"
    }

    fn size(&self) -> (u32, u32) {
        (1500, 1300)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let s = self.0;
        let (title, body) = root.split_vertically(44);
        title
            .draw(&Text::new(
                format!(
                    "Transmissibility under random base motion, {}–{} rad/s, scene '{}' with \
                     light damping: three levels against the linear structure",
                    BROADBAND_BAND[0], BROADBAND_BAND[1], s.scene_name
                ),
                (20, 12),
                text(22),
            ))
            .map_err(err)?;
        let panels = body.split_evenly((s.cases.len().max(1), 1));
        for (area, case) in panels.iter().zip(&s.cases) {
            panel(area, case)?;
        }
        Ok(())
    }
}

/// `20 log10 x`, clipped to `[lo, hi]`.
fn decibels(x: f64, (lo, hi): (f64, f64)) -> f64 {
    (20.0 * x.log10()).clamp(lo, hi)
}

/// One structure's panel.
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    case: &BroadbandCase,
) -> Result<(), String> {
    let finite = |x: &f64| x.is_finite();
    let values = case
        .linear_curve
        .iter()
        .map(|p| 20.0 * p.1.log10())
        .chain(case.record.levels.iter().flat_map(|l| {
            l.rows
                .iter()
                .filter_map(|r| r.transmissibility.map(|t| 20.0 * t.log10()))
        }))
        .filter(finite);
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    let range = if hi > lo {
        ((lo - 3.0).floor().max(-60.0), (hi + 3.0).ceil())
    } else {
        (-40.0, 40.0)
    };
    let s = &case.record.settings;
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!(
                "{} (observed body {}): {} s per level, segments {:.1} s, n = {:.1} averages",
                case.label,
                case.record.observe,
                s.duration,
                s.segment_duration,
                s.effective_averages
            ),
            text(19),
        )
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(70)
        .build_cartesian_2d(BROADBAND_BAND[0]..BROADBAND_BAND[1], range.0..range.1)
        .map_err(err)?;
    axes(
        &mut chart,
        "ω (rad/s)",
        "transmissibility √(S_yy/S_xx) (dB)",
        15,
    )?;
    for (k, band) in case.stop_bands.iter().enumerate() {
        let series = chart
            .draw_series([Rectangle::new(
                [
                    (band.lower, range.0),
                    (band.upper.min(BROADBAND_BAND[1]), range.1),
                ],
                STOP_BAND.filled(),
            )])
            .map_err(err)?;
        if k == 0 {
            series
                .label("stop band of the linear lattice")
                .legend(|(x, y)| Rectangle::new([(x, y - 6), (x + 16, y + 6)], STOP_BAND.filled()));
        }
    }
    chart
        .draw_series(LineSeries::new(
            case.linear_curve
                .iter()
                .filter(|p| p.1.is_finite())
                .map(|&(w, h)| (w, decibels(h, range))),
            LINEAR.stroke_width(2),
        ))
        .map_err(err)?
        .label("linear structure (stops removed), exact |H|")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], LINEAR.stroke_width(2)));
    for ((table, level), colour) in case.record.levels.iter().zip(&case.levels).zip(LEVELS) {
        let points: Vec<(f64, f64)> = table
            .rows
            .iter()
            .filter_map(|r| r.transmissibility.map(|t| (r.omega, decibels(t, range))))
            .collect();
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                colour.stroke_width(2),
            ))
            .map_err(err)?
            .label(format!(
                "{}: RMS {:.4} m, {} impacts",
                level.name, level.level, level.impacts
            ))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(3))
            });
        chart
            .draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled())))
            .map_err(err)?;
    }
    legend(&mut chart, SeriesLabelPosition::LowerLeft, 14)
}
