//! The tool path of a planned partprogram in one view (XY, ZX or YZ): rapids dashed, feeds solid,
//! arcs drawn through their centres, optionally with a motion trajectory (issue 10's JSON Lines)
//! on top. The scale is the same on both axes.

use detmath::Det as _;
use plotters::coord::Shift;
use plotters::prelude::*;

use partprogram::canon::{Canon, Kind};

use super::{Chart, FAMILY};

/// A view: the (horizontal, vertical) axis letters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum View {
    /// X right, Y up.
    Xy,
    /// Z right, X up (the lathe's view).
    Zx,
    /// Y right, Z up.
    Yz,
}

impl View {
    /// The axis letters (horizontal, vertical).
    pub fn axes(self) -> (char, char) {
        match self {
            View::Xy => ('X', 'Y'),
            View::Zx => ('Z', 'X'),
            View::Yz => ('Y', 'Z'),
        }
    }
}

/// One drawn piece of path.
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    /// Rapid traverse (dashed) or feed (solid).
    pub rapid: bool,
    /// Points in the view's coordinates.
    pub points: Vec<(f64, f64)>,
}

/// A tool path picture.
#[derive(Debug, Clone, PartialEq)]
pub struct Toolpath {
    /// Title line.
    pub title: String,
    /// The view.
    pub view: View,
    /// The programmed path.
    pub pieces: Vec<Piece>,
    /// A trajectory's set points, when given.
    pub trajectory: Vec<(f64, f64)>,
}

/// Largest angle of one chord of a drawn arc (5°).
const ARC_STEP: f64 = std::f64::consts::PI / 36.0;

fn coord(pos: &[(char, f64)], axis: char) -> f64 {
    pos.iter()
        .find(|(a, _)| *a == axis)
        .map_or(0.0, |(_, v)| *v)
}

/// The pieces of `blocks` in `view`. The path starts at the first motion block's end point.
pub fn pieces(blocks: &[Canon], view: View) -> Vec<Piece> {
    let (h, v) = view.axes();
    let mut out = Vec::new();
    let mut pos: Option<Vec<(char, f64)>> = None;
    for b in blocks {
        if !matches!(
            b.kind,
            Kind::Rapid | Kind::Linear | Kind::ArcCw | Kind::ArcCcw
        ) {
            continue;
        }
        let Some(start) = pos.replace(b.end.clone()) else {
            continue;
        };
        let points: Vec<(f64, f64)> = match b.kind {
            Kind::ArcCw | Kind::ArcCcw => arc_points(&start, b, b.kind == Kind::ArcCw)
                .iter()
                .map(|p| (coord(p, h), coord(p, v)))
                .collect(),
            _ => vec![
                (coord(&start, h), coord(&start, v)),
                (coord(&b.end, h), coord(&b.end, v)),
            ],
        };
        out.push(Piece {
            rapid: b.kind == Kind::Rapid,
            points,
        });
    }
    out
}

/// Points along an arc from `start` to `b.end` around `b.center` in `b.plane`; the other axes
/// move linearly (a helix).
fn arc_points(start: &[(char, f64)], b: &Canon, cw: bool) -> Vec<Vec<(char, f64)>> {
    let (pa, pb) = b.plane.axes();
    let (ca, cb) = (coord(&b.center, pa), coord(&b.center, pb));
    let a0 = (coord(start, pb) - cb).datan2(coord(start, pa) - ca);
    let a1 = (coord(&b.end, pb) - cb).datan2(coord(&b.end, pa) - ca);
    let r = (coord(start, pa) - ca).dhypot(coord(start, pb) - cb);
    let tau = std::f64::consts::TAU;
    let mut sweep = if cw { a0 - a1 } else { a1 - a0 };
    sweep = sweep.rem_euclid(tau);
    if sweep < 1e-12 {
        sweep = tau; // a full circle
    }
    let n = ((sweep / ARC_STEP).ceil() as usize).max(2);
    (0..=n)
        .map(|i| {
            let f = i as f64 / n as f64;
            let ang = if cw { a0 - sweep * f } else { a0 + sweep * f };
            b.end
                .iter()
                .map(|&(axis, e)| {
                    let s = coord(start, axis);
                    let val = if i == n {
                        e
                    } else if axis == pa {
                        ca + r * ang.dcos()
                    } else if axis == pb {
                        cb + r * ang.dsin()
                    } else {
                        s + (e - s) * f
                    };
                    (axis, val)
                })
                .collect()
        })
        .collect()
}

/// Why a trajectory file could not be read.
#[derive(Debug, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct TrajectoryError {
    /// 1-based line.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// The set points of a trajectory (issue 10 item 7: a header with `axes`, then `{"t","p",…}`
/// lines) in `view`.
pub fn trajectory(text: &str, view: View) -> Result<Vec<(f64, f64)>, TrajectoryError> {
    let err = |line: usize, message: String| TrajectoryError { line, message };
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (n, first) = lines
        .next()
        .ok_or_else(|| err(1, "empty file: the header line is missing".into()))?;
    let header: serde_json::Value =
        serde_json::from_str(first).map_err(|e| err(n + 1, e.to_string()))?;
    let axes: Vec<String> = header
        .get("axes")
        .and_then(|a| a.as_array())
        .map(|a| {
            a.iter()
                .filter_map(|x| x.as_str().map(str::to_string))
                .collect()
        })
        .ok_or_else(|| err(n + 1, "the header needs \"axes\": [\"X\", …]".into()))?;
    let (h, v) = view.axes();
    let index = |c: char| {
        axes.iter()
            .position(|a| a.eq_ignore_ascii_case(&c.to_string()))
            .ok_or_else(|| {
                err(
                    n + 1,
                    format!("the trajectory has no axis {c} (axes {axes:?}) for this view"),
                )
            })
    };
    let (ih, iv) = (index(h)?, index(v)?);
    let mut out = Vec::new();
    for (n, line) in lines {
        let rec: serde_json::Value =
            serde_json::from_str(line).map_err(|e| err(n + 1, e.to_string()))?;
        let p = rec
            .get("p")
            .and_then(|p| p.as_array())
            .ok_or_else(|| err(n + 1, "a set point line needs \"p\": [..]".into()))?;
        if p.len() != axes.len() {
            return Err(err(
                n + 1,
                format!("\"p\" has {} values for {} axes", p.len(), axes.len()),
            ));
        }
        let get = |i: usize| {
            p[i].as_f64()
                .ok_or_else(|| err(n + 1, format!("\"p\"[{i}] is not a number")))
        };
        out.push((get(ih)?, get(iv)?));
    }
    Ok(out)
}

impl Chart for Toolpath {
    fn size(&self) -> (u32, u32) {
        (800, 600)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let all = self
            .pieces
            .iter()
            .flat_map(|p| p.points.iter())
            .chain(&self.trajectory);
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &(x, y) in all {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        if x0 > x1 {
            (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
        }
        // Same scale on both axes: widen the narrower range around its middle (plot area ~ 4:3).
        let (w, hgt) = ((x1 - x0).max(1e-3), (y1 - y0).max(1e-3));
        let (w, hgt) = if w / hgt > 4.0 / 3.0 {
            (w, w * 0.75)
        } else {
            (hgt * 4.0 / 3.0, hgt)
        };
        let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let (w, hgt) = (w * 1.1, hgt * 1.1);
        let (h, v) = self.view.axes();
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, (FAMILY, 16))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(55)
            .build_cartesian_2d(cx - w / 2.0..cx + w / 2.0, cy - hgt / 2.0..cy + hgt / 2.0)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(format!("{h} (mm)"))
            .y_desc(format!("{v} (mm)"))
            .label_style((FAMILY, 12))
            .draw()
            .map_err(err)?;
        let rapid = RGBColor(150, 150, 150);
        let feed = RGBColor(20, 90, 200);
        for p in &self.pieces {
            if p.rapid {
                chart
                    .draw_series(DashedLineSeries::new(
                        p.points.clone(),
                        6,
                        4,
                        rapid.stroke_width(1),
                    ))
                    .map_err(err)?;
            } else {
                chart
                    .draw_series(LineSeries::new(p.points.clone(), feed.stroke_width(2)))
                    .map_err(err)?;
            }
        }
        if !self.trajectory.is_empty() {
            chart
                .draw_series(LineSeries::new(
                    self.trajectory.clone(),
                    RED.stroke_width(1),
                ))
                .map_err(err)?;
        }
        Ok(())
    }
}
