//! Interference (gouge) check of tool radius compensation: after a programmed element has been offset
//! and both of its compensated end points are known (the start from the joint with the element before,
//! the end from the joint with the element after — the compensator's one element of look-ahead), the
//! compensated element is compared with the programmed one.
//!
//! A compensated line that runs against its programmed direction (dot product of the two directions
//! ≤ 0) or has collapsed to a point, and a compensated arc whose sweep has changed sign or vanished,
//! would cut into the contour: the tool travels backwards along a wall it has just cut, or across the
//! material beside a step narrower than its diameter. This is what Fanuc controls call the
//! "interference check" and MEFI controls the "bottleneck"; the NC-xxx and HAAS manuals do not state the
//! rule, so the criterion here is a project rule (`partprogram/DIAGNOSTICS.md`, code 2512).
//!
//! Only adjacent elements are compared: a gouge between non-adjacent elements (a contour that comes
//! back within a tool radius of an earlier part of itself) is not detected.

use super::offset::{Geo, V2};
use detmath::Det as _;

/// Length (mm) at or below which a compensated element counts as collapsed.
pub const COLLAPSE: f64 = 1e-9;

/// Why a compensated element would gouge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Gouge {
    /// The compensated line runs against the programmed direction.
    Reversed,
    /// The compensated line or arc has (nearly) zero length.
    Collapsed,
    /// The compensated arc sweeps the other way (its end lies before its start).
    ArcReversed {
        /// Programmed sweep (radians, > 0, in the direction of rotation).
        programmed: f64,
        /// Compensated sweep (radians, in the programmed direction of rotation).
        sweep: f64,
    },
}

impl std::fmt::Display for Gouge {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Gouge::Reversed => write!(f, "runs against its programmed direction"),
            Gouge::Collapsed => write!(f, "has no length left"),
            Gouge::ArcReversed { programmed, sweep } => write!(
                f,
                "sweeps {:.3}° instead of the programmed {:.3}°",
                sweep.to_degrees(),
                programmed.to_degrees()
            ),
        }
    }
}

/// Signed angle (radians, in (−π, π]) from `u` to `v`, positive counter-clockwise.
fn angle(u: V2, v: V2) -> f64 {
    u.cross(v).datan2(u.dot(v))
}

/// The programmed sweep of an arc in its direction of rotation, in (0, 2π] (a closed arc is a full
/// circle).
pub fn sweep(a: V2, b: V2, c: V2, ccw: bool) -> f64 {
    let s = angle(a - c, b - c);
    let s = if ccw { s } else { -s };
    if s <= 1e-12 {
        s + std::f64::consts::TAU
    } else {
        s
    }
}

/// Checks the compensated element of `geo` running from `from` to `to` (both on its equidistant).
pub fn check(geo: &Geo, from: V2, to: V2) -> Option<Gouge> {
    match *geo {
        Geo::Line { a, b } => {
            let w = to - from;
            if w.len() <= COLLAPSE {
                Some(Gouge::Collapsed)
            } else if w.dot(b - a) <= 0.0 {
                Some(Gouge::Reversed)
            } else {
                None
            }
        }
        Geo::Arc { a, b, c, ccw } => {
            let programmed = sweep(a, b, c, ccw);
            // Angular shift of each end along the direction of rotation; the compensated sweep is the
            // programmed one plus the shift of the end less the shift of the start.
            let dir = if ccw { 1.0 } else { -1.0 };
            let ds = dir * angle(a - c, from - c);
            let de = dir * angle(b - c, to - c);
            let swept = programmed + de - ds;
            let radius = (from - c).len();
            if swept.abs() * radius <= COLLAPSE || radius <= COLLAPSE {
                Some(Gouge::Collapsed)
            } else if swept < 0.0 {
                Some(Gouge::ArcReversed {
                    programmed,
                    sweep: swept,
                })
            } else {
                None
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(ax: f64, ay: f64, bx: f64, by: f64) -> Geo {
        Geo::Line {
            a: V2::new(ax, ay),
            b: V2::new(bx, by),
        }
    }

    #[test]
    fn lines_forward_backward_and_collapsed() {
        let g = line(10.0, 0.0, 10.0, 2.0);
        assert_eq!(check(&g, V2::new(5.0, 5.0), V2::new(5.0, 7.0)), None);
        assert_eq!(
            check(&g, V2::new(5.0, 5.0), V2::new(5.0, 2.0)),
            Some(Gouge::Reversed)
        );
        assert_eq!(
            check(&g, V2::new(5.0, 5.0), V2::new(5.0, 5.0)),
            Some(Gouge::Collapsed)
        );
        // Perpendicular to the programmed direction counts as reversed (dot product 0).
        assert_eq!(
            check(&g, V2::new(5.0, 5.0), V2::new(6.0, 5.0)),
            Some(Gouge::Reversed)
        );
    }

    #[test]
    fn arc_sweep_shrinks_grows_and_reverses() {
        // Quarter circle G03 about the origin, radius 10, from (10, 0) to (0, 10); offset radius 5.2.
        let g = Geo::Arc {
            a: V2::new(10.0, 0.0),
            b: V2::new(0.0, 10.0),
            c: V2::new(0.0, 0.0),
            ccw: true,
        };
        assert_eq!(
            check(&g, V2::new(5.2, 0.0), V2::new(0.0, 5.2)),
            None,
            "perpendicular ends"
        );
        // Both ends pulled past each other: from 67.38° back to 22.62°, i.e. −44.76°.
        let Some(Gouge::ArcReversed { programmed, sweep }) =
            check(&g, V2::new(2.0, 4.8), V2::new(4.8, 2.0))
        else {
            panic!("not reversed")
        };
        assert!((programmed - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let expected = (2.0f64 / 4.8).datan() - (4.8f64 / 2.0).datan();
        assert!((sweep - expected).abs() < 1e-12, "{sweep}");
        assert_eq!(
            check(&g, V2::new(3.6769, 3.6769), V2::new(3.6769, 3.6769)),
            Some(Gouge::Collapsed)
        );
        // The same arc clockwise is a three-quarter circle: shrinking it by 90° leaves 180°.
        let cw = Geo::Arc {
            a: V2::new(10.0, 0.0),
            b: V2::new(0.0, 10.0),
            c: V2::new(0.0, 0.0),
            ccw: false,
        };
        assert_eq!(check(&cw, V2::new(0.0, -5.0), V2::new(0.0, 5.0)), None);
    }

    #[test]
    fn full_circle_sweep_is_two_pi() {
        let a = V2::new(1.0, 0.0);
        assert_eq!(sweep(a, a, V2::new(0.0, 0.0), true), std::f64::consts::TAU);
        assert_eq!(sweep(a, a, V2::new(0.0, 0.0), false), std::f64::consts::TAU);
    }
}
