//! Offset geometry of tool radius compensation: programmed elements (lines and arcs) in the compensation
//! plane, their tangents and left normals, their equidistants at a signed distance, and the corner
//! between two consecutive elements (perpendicular point, inserted arc, or intersection of equidistants).
//!
//! Distances are signed: `d > 0` puts the tool centre to the left of the programmed direction, `d < 0`
//! to the right. All coordinates are true millimetres in the plane (the caller halves a diameter X).

use detmath::Det as _;
use std::ops::{Add, Mul, Sub};

/// Angle (radians) below which two tangents count as one direction: the corner point is then the
/// perpendicular point, without intersecting (the role of machine constant R234).
pub const TANGENT_TOL: f64 = 1e-6;

/// A point or vector in the compensation plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct V2 {
    /// First plane axis.
    pub x: f64,
    /// Second plane axis.
    pub y: f64,
}

impl Add for V2 {
    type Output = V2;
    fn add(self, o: V2) -> V2 {
        V2 {
            x: self.x + o.x,
            y: self.y + o.y,
        }
    }
}

impl Sub for V2 {
    type Output = V2;
    fn sub(self, o: V2) -> V2 {
        V2 {
            x: self.x - o.x,
            y: self.y - o.y,
        }
    }
}

impl Mul<f64> for V2 {
    type Output = V2;
    fn mul(self, k: f64) -> V2 {
        V2 {
            x: self.x * k,
            y: self.y * k,
        }
    }
}

impl V2 {
    /// A point from its two coordinates.
    pub fn new(x: f64, y: f64) -> Self {
        V2 { x, y }
    }

    /// Dot product.
    pub fn dot(self, o: V2) -> f64 {
        self.x * o.x + self.y * o.y
    }

    /// z component of the cross product (positive: `o` turns counter-clockwise from `self`).
    pub fn cross(self, o: V2) -> f64 {
        self.x * o.y - self.y * o.x
    }

    /// Length.
    pub fn len(self) -> f64 {
        self.x.dhypot(self.y)
    }

    /// The vector turned 90° counter-clockwise (the left normal of a direction).
    pub fn left(self) -> V2 {
        V2 {
            x: -self.y,
            y: self.x,
        }
    }

    /// The unit vector in the same direction (the zero vector stays zero).
    pub fn unit(self) -> V2 {
        let l = self.len();
        if l > 0.0 { self * (1.0 / l) } else { self }
    }
}

/// A programmed element in the compensation plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Geo {
    /// A straight line from `a` to `b` (`a != b`).
    Line {
        /// Start.
        a: V2,
        /// End.
        b: V2,
    },
    /// An arc from `a` to `b` about `c`.
    Arc {
        /// Start.
        a: V2,
        /// End.
        b: V2,
        /// Centre.
        c: V2,
        /// Counter-clockwise (G03 in the machine frame).
        ccw: bool,
    },
}

/// The equidistant of an element: a line through `p` along unit `t`, or a circle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Equi {
    /// Offset line.
    Line {
        /// A point of the line.
        p: V2,
        /// Unit direction.
        t: V2,
    },
    /// Offset circle.
    Circle {
        /// Centre.
        c: V2,
        /// Radius (> 0).
        r: f64,
    },
}

/// How the corner between two compensated elements is joined.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Joint {
    /// Both elements meet in one point.
    Point(V2),
    /// The first element ends at `a`, an arc about the programmed corner leads to `b`.
    Arc {
        /// End of the first element.
        a: V2,
        /// Start of the second element.
        b: V2,
        /// Direction of the inserted arc.
        ccw: bool,
    },
}

/// Why a corner cannot be joined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum CornerError {
    /// The equidistants of the two elements have no common point.
    #[error("intersection of equidistants not found")]
    NoIntersection,
    /// An arc's radius is smaller than the tool radius on its inside: it has no equidistant.
    #[error("the arc radius is smaller than the tool radius on its inside")]
    ArcTooSmall,
}

impl Geo {
    /// Start point.
    pub fn start(&self) -> V2 {
        match *self {
            Geo::Line { a, .. } | Geo::Arc { a, .. } => a,
        }
    }

    /// End point.
    pub fn end(&self) -> V2 {
        match *self {
            Geo::Line { b, .. } | Geo::Arc { b, .. } => b,
        }
    }

    /// Unit tangent (direction of motion) at point `q` of the element.
    fn tangent_at(&self, q: V2) -> V2 {
        match *self {
            Geo::Line { a, b } => (b - a).unit(),
            Geo::Arc { c, ccw, .. } => {
                let u = (q - c).unit().left();
                if ccw { u } else { u * -1.0 }
            }
        }
    }

    /// Unit tangent at the start.
    pub fn start_tangent(&self) -> V2 {
        self.tangent_at(self.start())
    }

    /// Unit tangent at the end.
    pub fn end_tangent(&self) -> V2 {
        self.tangent_at(self.end())
    }

    /// The compensated start point: on the perpendicular at the start, at signed distance `d`.
    pub fn start_offset(&self, d: f64) -> V2 {
        self.start() + self.start_tangent().left() * d
    }

    /// The compensated end point: on the perpendicular at the end, at signed distance `d`.
    pub fn end_offset(&self, d: f64) -> V2 {
        self.end() + self.end_tangent().left() * d
    }

    /// Radius of an arc's equidistant at signed distance `d` (the programmed radius for a line: None).
    /// Counter-clockwise arcs have their centre on the left, so the left equidistant is smaller.
    pub fn offset_radius(&self, d: f64) -> Option<(f64, f64)> {
        match *self {
            Geo::Line { .. } => None,
            Geo::Arc { a, c, ccw, .. } => {
                let r = (a - c).len();
                Some((r, if ccw { r - d } else { r + d }))
            }
        }
    }

    /// The equidistant at signed distance `d`.
    pub fn equi(&self, d: f64) -> Result<Equi, CornerError> {
        match *self {
            Geo::Line { a, b } => {
                let t = (b - a).unit();
                Ok(Equi::Line {
                    p: a + t.left() * d,
                    t,
                })
            }
            Geo::Arc { c, .. } => match self.offset_radius(d) {
                Some((_, r)) if r > 1e-9 => Ok(Equi::Circle { c, r }),
                _ => Err(CornerError::ArcTooSmall),
            },
        }
    }
}

/// Tolerance on the squared half chord (mm²) under which a nearly tangent line or circle still meets.
const TOUCH: f64 = 1e-9;

/// The common point of two equidistants nearest to `near`, if any.
pub fn intersect(e1: &Equi, e2: &Equi, near: V2) -> Option<V2> {
    let pick = |p: V2, q: V2| {
        if (p - near).len() <= (q - near).len() {
            p
        } else {
            q
        }
    };
    match (*e1, *e2) {
        (Equi::Line { p: p1, t: t1 }, Equi::Line { p: p2, t: t2 }) => {
            let den = t1.cross(t2);
            if den.abs() < 1e-12 {
                return None;
            }
            let s = (p2 - p1).cross(t2) / den;
            Some(p1 + t1 * s)
        }
        (Equi::Line { p, t }, Equi::Circle { c, r })
        | (Equi::Circle { c, r }, Equi::Line { p, t }) => {
            let w = p - c;
            let b = w.dot(t);
            let mut disc = b * b - (w.dot(w) - r * r);
            if disc < 0.0 {
                if disc < -TOUCH {
                    return None;
                }
                disc = 0.0;
            }
            let h = disc.sqrt();
            Some(pick(p + t * (-b - h), p + t * (-b + h)))
        }
        (Equi::Circle { c: c1, r: r1 }, Equi::Circle { c: c2, r: r2 }) => {
            let v = c2 - c1;
            let dist = v.len();
            if dist < 1e-12 {
                return None;
            }
            let u = v * (1.0 / dist);
            let a = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist);
            let mut h2 = r1 * r1 - a * a;
            if h2 < 0.0 {
                if h2 < -TOUCH {
                    return None;
                }
                h2 = 0.0;
            }
            let h = h2.sqrt();
            let m = c1 + u * a;
            Some(pick(m + u.left() * h, m - u.left() * h))
        }
    }
}

/// The joint between `e1` and the following `e2` (which starts where `e1` ends) at signed distance `d`.
///
/// Tangent joins (within [`TANGENT_TOL`]) take the perpendicular point. An outside corner (the path
/// turns away from the tool) gets an arc about the programmed corner when `insert_arcs` is set and the
/// deviation between the directions exceeds `limit` radians; every other corner is the intersection of
/// the equidistants nearest to the programmed corner.
pub fn corner(
    e1: &Geo,
    e2: &Geo,
    d: f64,
    insert_arcs: bool,
    limit: f64,
) -> Result<Joint, CornerError> {
    let p = e1.end();
    let (t1, t2) = (e1.end_tangent(), e2.start_tangent());
    let a = p + t1.left() * d;
    let b = p + t2.left() * d;
    if d == 0.0 {
        return Ok(Joint::Point(p));
    }
    let angle = t1.cross(t2).datan2(t1.dot(t2));
    if angle.abs() <= TANGENT_TOL {
        return Ok(Joint::Point(a));
    }
    let reversal = angle.abs() >= std::f64::consts::PI - TANGENT_TOL;
    let outside = reversal || angle * d < 0.0;
    if outside && insert_arcs && angle.abs() > limit {
        let ccw = if reversal { d < 0.0 } else { angle > 0.0 };
        return Ok(Joint::Arc { a, b, ccw });
    }
    let (q1, q2) = (e1.equi(d)?, e2.equi(d)?);
    intersect(&q1, &q2, p)
        .map(Joint::Point)
        .ok_or(CornerError::NoIntersection)
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
    fn square_corner_left_is_an_arc_or_the_diagonal_point() {
        let (e1, e2) = (line(0.0, 0.0, 10.0, 0.0), line(10.0, 0.0, 10.0, -10.0));
        assert_eq!(
            corner(&e1, &e2, 5.0, true, 0.0),
            Ok(Joint::Arc {
                a: V2::new(10.0, 5.0),
                b: V2::new(15.0, 0.0),
                ccw: false
            })
        );
        assert_eq!(
            corner(&e1, &e2, 5.0, false, 0.0),
            Ok(Joint::Point(V2::new(15.0, 5.0)))
        );
        // On the right the same corner is inside.
        assert_eq!(
            corner(&e1, &e2, -5.0, true, 0.0),
            Ok(Joint::Point(V2::new(5.0, -5.0)))
        );
    }

    #[test]
    fn reversal_inserts_a_half_circle_or_fails_to_intersect() {
        let (e1, e2) = (line(0.0, 0.0, 10.0, 0.0), line(10.0, 0.0, 0.0, 0.0));
        assert_eq!(
            corner(&e1, &e2, 2.0, true, 0.0),
            Ok(Joint::Arc {
                a: V2::new(10.0, 2.0),
                b: V2::new(10.0, -2.0),
                ccw: false
            })
        );
        assert_eq!(
            corner(&e1, &e2, 2.0, false, 0.0),
            Err(CornerError::NoIntersection)
        );
    }

    #[test]
    fn ccw_arc_equidistant_on_the_left_is_smaller() {
        let arc = Geo::Arc {
            a: V2::new(10.0, 0.0),
            b: V2::new(0.0, 10.0),
            c: V2::new(0.0, 0.0),
            ccw: true,
        };
        assert_eq!(arc.offset_radius(3.0), Some((10.0, 7.0)));
        assert_eq!(arc.start_offset(3.0), V2::new(7.0, 0.0));
        assert_eq!(arc.equi(10.0), Err(CornerError::ArcTooSmall));
        assert_eq!(arc.end_tangent(), V2::new(-1.0, 0.0));
    }
}
