//! Path segments parameterised by arc length: straight lines and circular arcs/helices (programmed
//! arcs and the corner-blend arcs), in up to [`MAX_AXES`] dimensions (unused axes stay zero).

use detmath::Det as _;
use nalgebra::SVector;

use crate::config::MAX_AXES;

/// A point or direction over all axes.
pub type Vector = SVector<f64, MAX_AXES>;

/// Builds a vector from the first coordinates in `v` (the rest zero).
pub fn vector(v: &[f64]) -> Vector {
    let mut out = Vector::zeros();
    for (o, x) in out.iter_mut().zip(v) {
        *o = *x;
    }
    out
}

/// The shape of one segment (kept inline, not boxed: no allocation per piece in the tick path).
#[derive(Debug, Clone, PartialEq)]
#[allow(clippy::large_enum_variant)]
pub enum Shape {
    /// A straight line from `start` along the unit vector `dir`.
    Line {
        /// Unit direction.
        dir: Vector,
    },
    /// `center + r(s)·(cos φ·e1 + sin φ·e2) + lift·s/L`, φ = sweep·s/L, r linear from r0 to r1.
    Arc {
        /// Centre at s = 0.
        center: Vector,
        /// Unit vector to the start point.
        e1: Vector,
        /// Unit vector perpendicular to e1 in the plane, towards the motion at the start.
        e2: Vector,
        /// Radius at the start.
        r0: f64,
        /// Radius at the end.
        r1: f64,
        /// Swept angle, rad (> 0).
        sweep: f64,
        /// Displacement of the non-plane axes over the segment (helix).
        lift: Vector,
    },
}

/// A segment of the path.
#[derive(Debug, Clone, PartialEq)]
pub struct Seg {
    /// Start point.
    pub start: Vector,
    /// End point (returned exactly at s ≥ len).
    pub end: Vector,
    /// Length, mm.
    pub len: f64,
    /// The geometry.
    pub shape: Shape,
}

impl Seg {
    /// A line from `start` to `end`.
    pub fn line(start: Vector, end: Vector) -> Seg {
        let d = end - start;
        let len = d.norm();
        let dir = if len > 0.0 { d / len } else { Vector::zeros() };
        Seg {
            start,
            end,
            len,
            shape: Shape::Line { dir },
        }
    }

    /// A line from `start` to `end` along the known unit direction `dir` (kept when the line
    /// shrinks to zero length, so junction angles stay defined).
    pub fn line_along(start: Vector, end: Vector, dir: Vector) -> Seg {
        Seg {
            start,
            end,
            len: (end - start).norm(),
            shape: Shape::Line { dir },
        }
    }

    /// A circular arc or helix from `start` to `end` around `center` (only the plane axes of
    /// `center` matter; e1/e2 span the plane). `sweep` > 0 is the angle swept from e1 towards e2.
    #[allow(clippy::too_many_arguments)]
    pub fn arc(
        start: Vector,
        end: Vector,
        center: Vector,
        e1: Vector,
        e2: Vector,
        r0: f64,
        r1: f64,
        sweep: f64,
        lift: Vector,
    ) -> Seg {
        let rm = 0.5 * (r0 + r1);
        let len = ((rm * sweep).powi(2) + lift.norm_squared()).sqrt();
        Seg {
            start,
            end,
            len,
            shape: Shape::Arc {
                center,
                e1,
                e2,
                r0,
                r1,
                sweep,
                lift,
            },
        }
    }

    /// The point at arc length `s` (clamped to the segment; the exact end at s ≥ len).
    pub fn at(&self, s: f64) -> Vector {
        if s >= self.len {
            return self.end;
        }
        if s <= 0.0 {
            return self.start;
        }
        match &self.shape {
            Shape::Line { dir } => self.start + dir * s,
            Shape::Arc {
                center,
                e1,
                e2,
                r0,
                r1,
                sweep,
                lift,
            } => {
                let u = s / self.len;
                let phi = sweep * u;
                let r = r0 + (r1 - r0) * u;
                center + (e1 * phi.dcos() + e2 * phi.dsin()) * r + lift * u
            }
        }
    }

    /// The unit tangent at the start (`at_end` false) or at the end.
    pub fn tangent(&self, at_end: bool) -> Vector {
        match &self.shape {
            Shape::Line { dir } => *dir,
            Shape::Arc {
                e1,
                e2,
                r0,
                r1,
                sweep,
                lift,
                ..
            } => {
                let (phi, r) = if at_end { (*sweep, *r1) } else { (0.0, *r0) };
                let t = (e2 * phi.dcos() - e1 * phi.dsin()) * (r * sweep) + lift;
                let n = t.norm();
                if n > 0.0 { t / n } else { t }
            }
        }
    }

    /// For each axis, the largest |dp_i/ds| over the segment (an upper bound on arcs).
    pub fn max_share(&self) -> Vector {
        match &self.shape {
            Shape::Line { dir } => dir.abs(),
            Shape::Arc {
                e1,
                e2,
                r0,
                r1,
                sweep,
                lift,
                ..
            } => {
                let w = r0.max(*r1) * sweep / self.len;
                let mut out = lift.abs() / self.len;
                for i in 0..MAX_AXES {
                    if e1[i] != 0.0 || e2[i] != 0.0 {
                        out[i] += w * (e1[i] * e1[i] + e2[i] * e2[i]).sqrt();
                    }
                }
                out
            }
        }
    }

    /// For each axis, an upper bound of the centripetal acceleration share per (mm/s)² of path
    /// speed: κ·|n_i| (zero on lines).
    pub fn curvature_share(&self) -> Vector {
        match &self.shape {
            Shape::Line { .. } => Vector::zeros(),
            Shape::Arc {
                e1,
                e2,
                r0,
                r1,
                sweep,
                ..
            } => {
                let w = sweep / self.len;
                let r = r0.max(*r1);
                let mut out = Vector::zeros();
                for i in 0..MAX_AXES {
                    if e1[i] != 0.0 || e2[i] != 0.0 {
                        out[i] = r * w * w * (e1[i] * e1[i] + e2[i] * e2[i]).sqrt();
                    }
                }
                out
            }
        }
    }

    /// For a planar circular arc (constant radius, no lift): per axis, the largest |t_i| and the
    /// largest |n_i| over the sweep, exactly (t the unit tangent, n the unit normal towards the
    /// centre). On a short arc (a corner blend) they are far below the plane-wide bound 1.
    pub fn arc_shares(&self) -> Option<(Vector, Vector)> {
        let Shape::Arc {
            e1,
            e2,
            r0,
            r1,
            sweep,
            lift,
            ..
        } = &self.shape
        else {
            return None;
        };
        if r0 != r1 || lift.norm_squared() != 0.0 {
            return None;
        }
        let mut t = Vector::zeros();
        let mut n = Vector::zeros();
        let cs = (sweep.dcos(), sweep.dsin());
        for i in 0..MAX_AXES {
            let (p, q) = (e1[i], e2[i]);
            if p != 0.0 || q != 0.0 {
                // t_i = q cos φ − p sin φ, n_i = −(p cos φ + q sin φ).
                t[i] = max_abs_wave(q, -p, *sweep, cs);
                n[i] = max_abs_wave(p, q, *sweep, cs);
            }
        }
        Some((t, n))
    }

    /// For each axis, the extreme coordinates the segment reaches (exact for lines and for arcs
    /// whose plane is spanned by two axes).
    pub fn bounds(&self) -> (Vector, Vector) {
        let mut lo = self.start.inf(&self.end);
        let mut hi = self.start.sup(&self.end);
        if let Shape::Arc { sweep, .. } = &self.shape {
            // Candidate angles: every multiple of π/2 inside the sweep (axis extremes of an
            // axis-aligned plane) and, for general planes, the per-axis extremes.
            let Shape::Arc { e1, e2, .. } = &self.shape else {
                return (lo, hi);
            };
            for i in 0..MAX_AXES {
                if e1[i] == 0.0 && e2[i] == 0.0 {
                    continue;
                }
                let base = e2[i].datan2(e1[i]);
                for k in -1..=((sweep / std::f64::consts::PI).ceil() as i64 + 1) {
                    let phi = base + k as f64 * std::f64::consts::PI;
                    if phi > 0.0 && phi < *sweep {
                        let p = self.at(phi / sweep * self.len);
                        lo[i] = lo[i].min(p[i]);
                        hi[i] = hi[i].max(p[i]);
                    }
                }
            }
        }
        (lo, hi)
    }
}

impl Seg {
    /// The distance from `p` to the segment (exact for lines and planar circular arcs; for
    /// helices and spirals the distance to the point at the same angle, an upper bound).
    pub fn distance(&self, p: &Vector) -> f64 {
        let ends = (p - self.start).norm().min((p - self.end).norm());
        match &self.shape {
            Shape::Line { dir } => {
                let s = (p - self.start).dot(dir);
                if s <= 0.0 || s >= self.len {
                    ends
                } else {
                    (p - self.start - dir * s).norm()
                }
            }
            Shape::Arc {
                center,
                e1,
                e2,
                sweep,
                ..
            } => {
                let d = p - center;
                let mut psi = d.dot(e2).datan2(d.dot(e1));
                if psi < 0.0 {
                    psi += std::f64::consts::TAU;
                }
                let mut best = ends;
                // Every turn of the sweep that contains the angle.
                let mut a = psi;
                while a <= *sweep {
                    best = best.min((p - self.at(a / sweep * self.len)).norm());
                    a += std::f64::consts::TAU;
                }
                best
            }
        }
    }
}

/// The angle between two unit vectors, rad (0 when either is zero).
pub fn turn_angle(a: &Vector, b: &Vector) -> f64 {
    let c = a.dot(b).clamp(-1.0, 1.0);
    let s = (a - b * c).norm();
    s.datan2(c)
}

/// The largest |a cos φ + b sin φ| for φ in [0, s], given cos s and sin s.
pub fn max_abs_wave(a: f64, b: f64, s: f64, (cs, ss): (f64, f64)) -> f64 {
    if s >= std::f64::consts::PI {
        return a.dhypot(b);
    }
    // The derivative b cos φ − a sin φ has its zeros π apart: on [0, s], s < π, it changes sign
    // exactly when an extreme ±amplitude lies inside.
    if b * (b * cs - a * ss) <= 0.0 {
        return a.dhypot(b);
    }
    a.abs().max((a * cs + b * ss).abs())
}

#[cfg(test)]
mod tests {
    use super::max_abs_wave;
    use detmath::Det as _;

    fn wave(a: f64, b: f64, s: f64) -> f64 {
        max_abs_wave(a, b, s, (s.dcos(), s.dsin()))
    }

    #[test]
    fn max_abs_wave_finds_inner_and_end_extremes() {
        // cos on [0, 0.5]: 1 at 0; sin on [0, 1]: sin 1 at the end; sin on [0, 2]: 1 at π/2.
        assert_eq!(wave(1.0, 0.0, 0.5), 1.0);
        assert_eq!(wave(0.0, 1.0, 1.0), 1.0f64.dsin());
        assert_eq!(wave(0.0, 1.0, 2.0), 1.0);
        // sin − cos: −1 at 0, 1 at π/2, its extreme √2 at 3π/4 only on the longer interval.
        assert_eq!(wave(-1.0, 1.0, std::f64::consts::FRAC_PI_2), 1.0);
        assert_eq!(wave(-1.0, 1.0, 3.0), 2.0f64.sqrt());
    }
}
