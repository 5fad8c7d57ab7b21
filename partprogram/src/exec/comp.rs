//! The MEFI side of radius compensation: the [`Ctx`] of a block from the modal G40/G41/G42, the
//! correction entry D (datum I, the radius; D0 is radius 0), the plane, diameter programming and mirror.

use super::Exec;
use crate::canon::Plane;
use crate::program::CBlock;
use crate::radius::{Ctx, Side};

impl Exec<'_> {
    /// The compensation context of block `b` in the current modal state.
    pub(super) fn comp_ctx(&self, b: &CBlock) -> Ctx {
        let plane: Plane = self.modal.plane;
        let (a1, a2) = plane.axes();
        let radius = match usize::try_from(self.modal.d) {
            Ok(0) | Err(_) => 0.0,
            Ok(e) => self.st.corrections.get(e.min(99)).map_or(0.0, |c| c[0]),
        };
        let index = |a: char| self.geo.axes.iter().position(|c| *c == a);
        let k = |a: char| {
            if self.geo.diameter && a == 'X' {
                0.5
            } else {
                1.0
            }
        };
        let mirrored = match (index(a1), index(a2)) {
            (Some(i), Some(j)) => self.geo.mirror[i] != self.geo.mirror[j],
            _ => false,
        };
        Ctx {
            side: Side::from_g(self.modal.comp),
            radius,
            axes: (a1, a2),
            scale: (k(a1), k(a2)),
            mirrored,
            file: b.file,
            span: b.span,
        }
    }
}
