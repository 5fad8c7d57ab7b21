//! The active soft limits of a process: the operating zone LO1 or LO2 that the PLC's ZONE2
//! (U10N1) selects, and the CUB protected box that the PLC's CUB (U10N0) switches on
//! (characterization-system-axes.md §10.20 and §10.23).
//!
//! - A block is checked when it enters the look-ahead, from where the previous block ends: every
//!   axis's extreme coordinate along the path (exact for arcs, `motion::geom::Seg::bounds`)
//!   against the active zone, and the path against the CUB box. A block that leaves the zone or
//!   enters the box is refused before any motion, naming the block, the axis and the limit.
//! - The CUB box is the open box `(neg + space, pos − space)` on every axis that has a CUB record
//!   (`space` is how far an axis may enter the zone). Lines are checked exactly; arcs along
//!   [`ARC_CHORDS`] chords (their points lie on the arc).
//! - Jogs and handwheel moves of one axis are clipped to the zone and stop at the box's face.
//! - An axis without a record of the selected zone has no limit in it (LO2 absent: no check).

use motion::geom::{Seg, vector};
use partprogram::Canon;

use crate::process::Process;

/// The number of chords an arc is checked along against the CUB box.
pub const ARC_CHORDS: usize = 256;

/// Why a block is refused by the active limits.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ZoneError {
    /// The path leaves the operating zone.
    #[error("axis {axis} would reach {reach:.4} mm, beyond the {zone} limit {limit:.4} mm")]
    Outside {
        /// Axis letter.
        axis: char,
        /// `LO1` or `LO2`.
        zone: &'static str,
        /// The limit crossed.
        limit: f64,
        /// The farthest coordinate the path reaches.
        reach: f64,
    },
    /// The path enters the CUB protected box.
    #[error("the path enters the CUB protected box ({boxed}) at {at}")]
    IntoCube {
        /// The box, `X -119.5..-50.5 Y …`.
        boxed: String,
        /// The first point inside, `X -60 Y -70 Z -30`.
        at: String,
    },
    /// The block's geometry could not be built (the interpolator reports it too).
    #[error("{0}")]
    Geometry(String),
}

/// Where a straight line from `a` to `b` is strictly inside the box `lo < x < hi` (per listed
/// axis): the parameter interval in [0, 1], or None.
fn line_in_box(a: &[f64], b: &[f64], boxed: &[(usize, f64, f64)]) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for &(i, lo, hi) in boxed {
        let d = b[i] - a[i];
        if d == 0.0 {
            if !(a[i] > lo && a[i] < hi) {
                return None;
            }
            continue;
        }
        let (u, v) = ((lo - a[i]) / d, (hi - a[i]) / d);
        t0 = t0.max(u.min(v));
        t1 = t1.min(u.max(v));
    }
    (t0 < t1).then_some((t0, t1))
}

impl Process {
    /// The active zone: 0 for LO1, 1 for LO2.
    fn zone_index(&self) -> usize {
        usize::from(self.zone2)
    }

    /// The active soft limits (−, +) of axis `i`.
    pub(crate) fn active_limits(&self, i: usize) -> (Option<f64>, Option<f64>) {
        let a = &self.cfg.axes[i];
        if self.zone2 { a.soft2 } else { a.soft }
    }

    /// The CUB box (axis index, open low, open high) while CUB is on; empty when off.
    fn cube(&self) -> Vec<(usize, f64, f64)> {
        if !self.cub_on {
            return Vec::new();
        }
        self.cfg
            .axes
            .iter()
            .enumerate()
            .filter_map(|(i, a)| {
                let (neg, pos, space) = a.cub?;
                Some((i, neg.min(pos) + space, neg.max(pos) - space))
            })
            .collect()
    }

    /// A move of axis `i` alone from `here` towards `target`, clipped to the active zone and
    /// stopped at the face of the CUB box.
    pub(crate) fn clip_single_axis(&self, i: usize, here: f64, target: f64) -> f64 {
        let (lo, hi) = self.active_limits(i);
        let mut t = target;
        if let Some(hi) = hi {
            t = t.min(hi.max(here));
        }
        if let Some(lo) = lo {
            t = t.max(lo.min(here));
        }
        let cube = self.cube();
        let Some(&(_, blo, bhi)) = cube.iter().find(|(k, _, _)| *k == i) else {
            return t;
        };
        let pos = self.interp.position();
        let others_inside = cube
            .iter()
            .filter(|(k, _, _)| *k != i)
            .all(|&(k, l, h)| pos.get(k).is_some_and(|p| *p > l && *p < h));
        if !others_inside || (here > blo && here < bhi) {
            return t;
        }
        if here <= blo && t > blo {
            blo
        } else if here >= bhi && t < bhi {
            bhi
        } else {
            t
        }
    }

    /// Checks the motion of block `b` from `start` against the active zone and the CUB box.
    pub(crate) fn check_zones(&self, start: &[f64], b: &Canon) -> Result<(), ZoneError> {
        let names = self.cfg.axis_names();
        // As the interpolator does: coordinates of axes the process does not interpolate (the
        // Fanuc lathe's C) are not part of the path.
        let mut b = b.clone();
        b.end.retain(|(a, _)| names.contains(a));
        let m = motion::Move::from_canon(0, &b, &names)
            .map_err(|e| ZoneError::Geometry(e.to_string()))?;
        let seg = motion::plan::segment(&m, &vector(start), &vector(&m.end))
            .map_err(|e| ZoneError::Geometry(e.to_string()))?;
        let Some(seg) = seg else {
            return Ok(());
        };
        let (lo, hi) = seg.bounds();
        let zone = ["LO1", "LO2"][self.zone_index()];
        for (i, a) in self.cfg.axes.iter().enumerate() {
            let (min, max) = self.active_limits(i);
            if let Some(max) = max
                && hi[i] > max
            {
                return Err(ZoneError::Outside {
                    axis: a.name,
                    zone,
                    limit: max,
                    reach: hi[i],
                });
            }
            if let Some(min) = min
                && lo[i] < min
            {
                return Err(ZoneError::Outside {
                    axis: a.name,
                    zone,
                    limit: min,
                    reach: lo[i],
                });
            }
        }
        self.check_cube(&seg)
    }

    fn check_cube(&self, seg: &Seg) -> Result<(), ZoneError> {
        let cube = self.cube();
        if cube.is_empty() {
            return Ok(());
        }
        let n = self.cfg.axes.len();
        let chords = match seg.shape {
            motion::geom::Shape::Line { .. } => 1,
            motion::geom::Shape::Arc { .. } => ARC_CHORDS,
        };
        let point = |k: usize| -> Vec<f64> {
            let p = seg.at(seg.len * k as f64 / chords as f64);
            (0..n).map(|i| p[i]).collect()
        };
        let mut a = point(0);
        for k in 1..=chords {
            let b = point(k);
            if let Some((t, _)) = line_in_box(&a, &b, &cube) {
                let names = self.cfg.axis_names();
                let fmt = |v: f64| partprogram::canon::num(v);
                let boxed: Vec<String> = cube
                    .iter()
                    .map(|&(i, l, h)| format!("{} {}..{}", names[i], fmt(l), fmt(h)))
                    .collect();
                let at: Vec<String> = cube
                    .iter()
                    .map(|&(i, _, _)| format!("{} {}", names[i], fmt(a[i] + t * (b[i] - a[i]))))
                    .collect();
                return Err(ZoneError::IntoCube {
                    boxed: boxed.join(" "),
                    at: at.join(" "),
                });
            }
            a = b;
        }
        Ok(())
    }
}
