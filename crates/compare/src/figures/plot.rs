//! Rendering: one font shipped in the build, registered once; every figure drawn to PNG and SVG
//! from the same code, so both render on a machine without system fonts.

use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::{CoordTranslate, Shift};
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;
use thiserror::Error;

/// A figure could not be written.
#[derive(Debug, Error)]
#[error("cannot draw {path}: {message}")]
pub struct PlotError {
    /// The file being written.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

/// The font family every figure uses (DejaVu Sans, shipped by the `dejavu` crate).
pub const FONT: &str = "sans-serif";

/// Registers DejaVu Sans (regular and bold) under [`FONT`], once per process.
pub fn register_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // Registration can only fail on a malformed font, and these are fixed bytes.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
        let _ = plotters::style::register_font(FONT, FontStyle::Bold, dejavu::sans::bold());
    });
}

/// Something that draws itself on any plotters backend.
pub trait Figure {
    /// File stem, e.g. `transmittance`.
    fn name(&self) -> &str;
    /// Size in pixels.
    fn size(&self) -> (u32, u32) {
        (1200, 800)
    }
    /// Draws on `root`.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// Converts a plotters error into a message.
pub fn err<E: std::fmt::Debug>(e: E) -> String {
    format!("{e:?}")
}

/// Writes `figure` as `dir/NAME.png` and `dir/NAME.svg`; returns both paths.
pub fn save(figure: &impl Figure, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    register_fonts();
    std::fs::create_dir_all(dir).map_err(|e| PlotError {
        path: dir.to_owned(),
        message: e.to_string(),
    })?;
    let size = figure.size();
    let png = dir.join(format!("{}.png", figure.name()));
    let svg = dir.join(format!("{}.svg", figure.name()));
    let fail = |path: &Path| {
        let path = path.to_owned();
        move |message: String| PlotError { path, message }
    };
    {
        let root = BitMapBackend::new(&png, size).into_drawing_area();
        root.fill(&WHITE).map_err(err).map_err(fail(&png))?;
        figure.draw(&root).map_err(fail(&png))?;
        root.present().map_err(err).map_err(fail(&png))?;
    }
    {
        let root = SVGBackend::new(&svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err).map_err(fail(&svg))?;
        figure.draw(&root).map_err(fail(&svg))?;
        root.present().map_err(err).map_err(fail(&svg))?;
    }
    Ok(vec![png, svg])
}

/// Text style in the shipped font.
pub fn text(size: u32) -> TextStyle<'static> {
    (FONT, size).into_font().into()
}

/// Axes of a chart in the house style: descriptions, label sizes, no minor grid.
pub fn axes<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    x_desc: &str,
    y_desc: &str,
    label_size: u32,
) -> Result<(), String>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(text(label_size))
        .axis_desc_style(text(label_size + 2))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(err)
}

/// The legend of a chart in the house style.
pub fn legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    size: u32,
) -> Result<(), String>
where
    DB: DrawingBackend + 'a,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .label_font(text(size))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .position(position)
        .draw()
        .map_err(err)
}
