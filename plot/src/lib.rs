//! Plots from the CLI (`ncplc plot trace`, `ncplc nc plot`): SVG or PNG by the output's extension,
//! drawn with plotters and the embedded DejaVu Sans (registered from bytes, so no system font is
//! looked up and a PNG comes out the same on every machine).
//!
//! A chart implements [`Chart`] once for any plotters backend; [`write`] picks the backend.
//!
//! | module | concept |
//! |---|---|
//! | [`timing`] | timing diagrams of a trace's signals |
//! | [`toolpath`] | a plan's tool path (also the web HMI's pieces, through the controller) |
//!
//! **Invariants:** the same input gives the same bytes (embedded font, `detmath` geometry); a file
//! is replaced atomically (`runtime::atomic_file`). Below the controller and the CLI, above
//! `trace` and `runtime`.

pub mod timing;
pub mod toolpath;

use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;

/// DejaVu Sans (Bitstream Vera licence, `plot/assets/DejaVuSans.LICENSE`).
static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// The font family every chart uses.
pub const FAMILY: &str = "sans-serif";

/// Why a plot could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The output name ends in neither `.svg` nor `.png`.
    #[error("{0}: the output must end in .svg or .png")]
    Format(String),
    /// Drawing or writing failed.
    #[error("{path}: {message}")]
    Draw {
        /// The output file.
        path: String,
        /// What failed.
        message: String,
    },
}

/// Something that draws itself on any plotters backend.
pub trait Chart {
    /// The picture's size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws onto `root`.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a valid TTF compiled in; a failure would only drop text, never panic.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

/// Renders `chart` as SVG text.
pub fn to_svg<C: Chart>(chart: &C) -> Result<String, String> {
    register_font();
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, chart.size()).into_drawing_area();
        chart.draw(&root)?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// Writes `chart` to `path` (`.svg` or `.png`).
pub fn write<C: Chart>(chart: &C, path: &Path) -> Result<(), PlotError> {
    let shown = path.display().to_string();
    let fail = |message: String| PlotError::Draw {
        path: shown.clone(),
        message,
    };
    match path.extension().and_then(|e| e.to_str()) {
        Some("svg") => {
            let svg = to_svg(chart).map_err(fail)?;
            runtime::atomic_file::write(path, svg.as_bytes()).map_err(|e| fail(e.to_string()))
        }
        Some("png") => {
            register_font();
            // Drawn into a temporary file beside `path`, renamed over it once complete.
            runtime::atomic_file::write_with(path, |tmp| {
                let root = BitMapBackend::new(tmp, chart.size()).into_drawing_area();
                chart
                    .draw(&root)
                    .and_then(|()| root.present().map_err(|e| e.to_string()))
                    .map_err(std::io::Error::other)
            })
            .map_err(|e| fail(e.to_string()))
        }
        _ => Err(PlotError::Format(shown)),
    }
}
