//! The emergency stop on a hardware limit switch (AXCFIL `AFC`, characterization-system-axes.md
//! §10.22, 003:2548-2568): an abort whose stop decelerates every axis at its AFC rate under the
//! linear law, replanned at once.

use crate::config::Law;
use crate::kernel::Kernel;
use crate::plan::{Motion, Piece};
use crate::profile::Dyn;

impl Kernel {
    /// The emergency stop on a hardware limit switch (AXCFIL `AFC`): an abort whose stop
    /// decelerates each axis at `decel` (mm/s² of the slide, Config order; None: the axis's
    /// acceleration limit, MAN or RAP) under the linear law, at once (no wait for zero
    /// acceleration).
    pub fn emergency_stop(&mut self, decel: &[Option<f64>]) {
        self.emergency = Some(decel.to_vec());
        self.abort();
    }

    /// The path dynamics of a stop of piece `p`: under an emergency stop the AFC decelerations
    /// over the axes' shares of the direction, else the piece's own.
    pub(crate) fn stop_dyn(&self, p: &Piece) -> Dyn {
        let Some(decel) = self.emergency.as_ref().filter(|_| self.abort) else {
            return p.dynm;
        };
        let mut a = f64::INFINITY;
        for (i, share) in p.axis[0].iter().enumerate() {
            if *share > 0.0 {
                let Some(ax) = self.cfg.axes.get(i) else {
                    continue;
                };
                let own = if p.motion == Motion::Rapid {
                    ax.a_rapid
                } else {
                    ax.a_max
                };
                let ai = decel.get(i).copied().flatten().unwrap_or(own);
                a = a.min(ai / share);
            }
        }
        Dyn {
            law: Law::Linear,
            a: if a.is_finite() && a > 0.0 {
                a
            } else {
                p.dynm.a
            },
            j: f64::INFINITY,
            exp_start: 1.0,
            exp_end: 1.0,
        }
    }
}
