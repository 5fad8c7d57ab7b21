//! Circular moves of the Fanuc executor: the active arc plane's axes and centre words, and the
//! centre of a G2/G3 block from R or from I/J/K (checked against the circle tolerance), in the
//! Cartesian frame of the plane (C in development mm under G7.1, X as radius under diameter mode).

use detmath::Det as _;

use super::{Ex, run_err};
use crate::canon::Plane;
use crate::codes;
use crate::exec::RunError;
use crate::program::CBlock;

impl Ex<'_> {
    /// True when the block writes a centre word (I, J or K) of the active arc plane.
    pub(super) fn has_centre_words(&self, b: &CBlock) -> bool {
        let (_, _, w1, w2) = if self.cyl.is_some() {
            ('C', 'Z', 'J', 'K')
        } else {
            self.plane_axes()
        };
        b.word(w1).is_some() || b.word(w2).is_some()
    }

    pub(super) fn plane_axes(&self) -> (char, char, char, char) {
        // (first axis, second axis, centre word along first, along second)
        match self.plane {
            Plane::XY => ('X', 'Y', 'I', 'J'),
            Plane::ZX => ('Z', 'X', 'K', 'I'),
            Plane::YZ => ('Y', 'Z', 'J', 'K'),
            // G14–G16 are MEFI functions: the Fanuc executor never selects such a plane.
            Plane::Extra { first, second, .. } => (first, second, 'I', 'J'),
        }
    }

    pub(super) fn arc(
        &self,
        b: &CBlock,
        t: &[Option<f64>; 6],
    ) -> Result<Vec<(char, f64)>, RunError> {
        let (a1, a2, w1, w2) = if self.cyl.is_some() {
            ('C', 'Z', 'J', 'K')
        } else {
            self.plane_axes()
        };
        let (Some(i1), Some(i2)) = (self.idx(a1), self.idx(a2)) else {
            return Err(run_err(
                b,
                codes::RUN_CIRCLE,
                format!("the machine has no {a1}{a2} plane"),
            ));
        };
        // Scale to a Cartesian frame: C degrees → development mm, X diameter → radius.
        let k = |i: usize| -> f64 {
            match (self.axes[i], self.cyl) {
                ('C', Some(r)) => r * std::f64::consts::PI / 180.0,
                ('X', _) if self.diameter => 0.5,
                _ => 1.0,
            }
        };
        let (k1, k2) = (k(i1), k(i2));
        let s = (self.machine[i1] * k1, self.machine[i2] * k2);
        let e = (
            t[i1].unwrap_or(self.machine[i1]) * k1,
            t[i2].unwrap_or(self.machine[i2]) * k2,
        );
        let cw = self.motion == 20;
        let c = if let Some(r) = self.dim(b, 'R') {
            let (dx, dy) = (e.0 - s.0, e.1 - s.1);
            let d = dx.dhypot(dy);
            if d == 0.0 || d > 2.0 * r.abs() + 1e-6 {
                return Err(run_err(
                    b,
                    codes::RUN_CIRCLE,
                    format!("R{r} cannot join the start and end point"),
                ));
            }
            let h = (r * r - d * d / 4.0).max(0.0).sqrt();
            let (ux, uy) = (dx / d, dy / d);
            let right = (uy, -ux);
            let side = if cw == (r > 0.0) { 1.0 } else { -1.0 };
            (
                (s.0 + e.0) / 2.0 + side * h * right.0,
                (s.1 + e.1) / 2.0 + side * h * right.1,
            )
        } else {
            let c = (
                s.0 + self.dim(b, w1).unwrap_or(0.0),
                s.1 + self.dim(b, w2).unwrap_or(0.0),
            );
            let r0 = (s.0 - c.0).dhypot(s.1 - c.1);
            let r1 = (e.0 - c.0).dhypot(e.1 - c.1);
            if (r0 - r1).abs() > self.prog.machine.circle_tolerance.max(0.002) {
                return Err(run_err(
                    b,
                    codes::RUN_CIRCLE,
                    format!(
                        "end point is not on the circle: radius {r0:.4} at the start, {r1:.4} at the end"
                    ),
                ));
            }
            c
        };
        Ok(vec![(a1, c.0 / k1), (a2, c.1 / k2)])
    }
}
