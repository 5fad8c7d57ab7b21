//! The Fanuc/HAAS side of radius compensation: the D register (radius of entry D of the offset table,
//! D00 is radius 0; geometry + wear, `G10 L12`/`L13` write them, see [`super::offsets`]), the [`Ctx`] of a block, and the
//! implicit compensation of the G12/G13 pockets.

use super::Ex;
use crate::program::CBlock;
use crate::radius::{Ctx, Side};

/// Number of offset registers (D0…D200, HAAS 002:1163).
pub const REGISTERS: usize = 201;

impl Ex<'_> {
    /// Radius of the active D register (0 for D00).
    pub(super) fn tool_radius(&self, d: i64) -> f64 {
        match usize::try_from(d) {
            Ok(0) | Err(_) => 0.0,
            Ok(e) => {
                self.corrections.get(e).map_or(0.0, |c| c[0])
                    + self.wear.get(e).map_or(0.0, |w| w[1])
            }
        }
    }

    /// The compensation context of block `b` in the current modal state. Under G7.1 the plane is the
    /// development (C in degrees scaled by r·π/180, Z).
    pub(super) fn comp_ctx(&self, b: &CBlock) -> Ctx {
        let (axes, scale) = match self.cyl {
            Some(r) => (('C', 'Z'), (r * std::f64::consts::PI / 180.0, 1.0)),
            None => {
                let axes = self.plane.axes();
                let k = |a: char| if self.diameter && a == 'X' { 0.5 } else { 1.0 };
                (axes, (k(axes.0), k(axes.1)))
            }
        };
        Ctx {
            side: Side::from_g(self.comp),
            radius: self.tool_radius(self.d),
            axes,
            scale,
            mirrored: false,
            file: b.file,
            span: b.span,
        }
    }
}
