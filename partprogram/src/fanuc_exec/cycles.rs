//! Fanuc/HAAS canned drilling cycles (G73, G74, G81–G86, G89 with G98/G99 and L repeats) and
//! circular pockets (G12/G13). G76 (orient and shift), G77 (back boring) and G87/G88 (manual retract)
//! are refused by the static check: their sequences need spindle orientation or the operator.

use super::{Ex, PECK_CLEARANCE, run_err};
use crate::ast::Val;
use crate::canon::{Kind, MFunc};
use crate::codes;
use crate::exec::RunError;
use crate::program::CBlock;

impl Ex<'_> {
    pub(super) fn canned(
        &mut self,
        b: &CBlock,
        g: u16,
        first: bool,
        vals: &[Option<f64>; 6],
        m: &[MFunc],
    ) -> Result<(), RunError> {
        let num = |a: char| {
            b.word(a).and_then(|w| {
                if let Val::Lit(l) = w.val {
                    Some(l.value())
                } else {
                    None
                }
            })
        };
        let Some(zi) = self.idx('Z') else {
            return Err(run_err(b, codes::RUN_BAD_G, "canned cycles need a Z axis"));
        };
        if first {
            self.init_z = self.machine[zi];
        }
        let oz = self.origin(zi);
        // (R plane, Z depth, Q peck, P dwell) in machine Z.
        if let Some(r) = self.dim(b, 'R') {
            self.cyc.0 = if self.abs { r + oz } else { self.init_z + r };
        } else if first {
            self.cyc.0 = self.machine[zi];
        }
        if let Some(z) = vals[zi] {
            self.cyc.1 = if self.abs { z + oz } else { self.cyc.0 + z };
        }
        if let Some(q) = self.dim(b, 'Q') {
            self.cyc.2 = q.abs();
        }
        if let Some(p) = b.word('P').and_then(|w| {
            if let Val::Lit(l) = w.val {
                Some(if l.point {
                    l.value()
                } else {
                    l.value() / 1000.0
                })
            } else {
                None
            }
        }) {
            self.cyc.3 = p;
        }
        // L repeats the hole: at the same place under G90, each time shifted by the increments under
        // G91 (HAAS 002:221, L = "counter for repeated cycles"); L0 stores the data without drilling.
        let reps = match num('L') {
            Some(l) if !(0.0..=32767.0).contains(&l) || l.fract() != 0.0 => {
                return Err(run_err(
                    b,
                    codes::RUN_RANGE,
                    format!("L{l}: the repeat count is an integer 0..32767"),
                ));
            }
            Some(l) => l as u32,
            None => 1,
        };
        if reps == 0 && !m.is_empty() {
            self.emit(b, Kind::Aux, Vec::new(), m, None);
        }
        for k in 0..reps {
            self.hole(b, g, zi, vals, if k == 0 { m } else { &[] });
        }
        Ok(())
    }

    /// One hole of cycle `g`: position in the plane at the current level, then the Z sequence.
    fn hole(&mut self, b: &CBlock, g: u16, zi: usize, vals: &[Option<f64>; 6], m: &[MFunc]) {
        let (r, z, q, p) = self.cyc;
        // Position in XY at the current (initial) level.
        let mut xy = [None; 6];
        for (i, a) in self.axes.clone().iter().enumerate() {
            if *a != 'Z'
                && let Some(v) = vals[i]
            {
                xy[i] = Some(if self.abs {
                    v + self.origin(i)
                } else {
                    self.machine[i] + v
                });
            }
        }
        if xy.iter().any(Option::is_some) {
            self.move_to(b, Kind::Rapid, xy, m);
        } else if !m.is_empty() {
            self.emit(b, Kind::Aux, Vec::new(), m, None);
        }
        let zto = |ex: &mut Self, kind: Kind, v: f64| {
            let mut t = [None; 6];
            t[zi] = Some(v);
            ex.move_to(b, kind, t, &[]);
        };
        zto(self, Kind::Rapid, r);
        let down = if z < r { -1.0 } else { 1.0 };
        match g {
            730 | 830 if q > 0.0 => {
                let mut d = r;
                loop {
                    let next = d + down * q;
                    let last = (next - z) * down >= 0.0;
                    let next = if last { z } else { next };
                    zto(self, Kind::Linear, next);
                    if last {
                        break;
                    }
                    if g == 730 {
                        zto(self, Kind::Rapid, next - down * PECK_CLEARANCE);
                    } else {
                        zto(self, Kind::Rapid, r);
                        zto(self, Kind::Rapid, next - down * PECK_CLEARANCE);
                    }
                    d = next;
                }
            }
            _ => zto(self, Kind::Linear, z),
        }
        let top = if self.g99 { r } else { self.init_z };
        match g {
            820 | 890 => {
                self.emit(b, Kind::Dwell, Vec::new(), &[], Some(p));
            }
            _ => {}
        }
        match g {
            840 | 740 => {
                let rev = if g == 840 { 4 } else { 3 };
                self.emit(
                    b,
                    Kind::Aux,
                    Vec::new(),
                    &[MFunc {
                        m: rev,
                        before: true,
                    }],
                    None,
                );
                zto(self, Kind::Linear, r);
                let back = if g == 840 { 3 } else { 4 };
                self.emit(
                    b,
                    Kind::Aux,
                    Vec::new(),
                    &[MFunc {
                        m: back,
                        before: true,
                    }],
                    None,
                );
                if !self.g99 {
                    zto(self, Kind::Rapid, top);
                }
            }
            860 => {
                // Boring, spindle stop at the bottom, rapid out, spindle on again (M05 … M03).
                let stop = |m| [MFunc { m, before: true }];
                self.emit(b, Kind::Aux, Vec::new(), &stop(5), None);
                zto(self, Kind::Rapid, top);
                self.emit(b, Kind::Aux, Vec::new(), &stop(3), None);
            }
            850 | 890 => {
                zto(self, Kind::Linear, r);
                if !self.g99 {
                    zto(self, Kind::Rapid, top);
                }
            }
            _ => zto(self, Kind::Rapid, top),
        }
    }

    pub(super) fn pocket(
        &mut self,
        b: &CBlock,
        g: u16,
        vals: &[Option<f64>; 6],
        m: &[MFunc],
    ) -> Result<(), RunError> {
        let num = |a: char| {
            b.word(a).and_then(|w| {
                if let Val::Lit(l) = w.val {
                    Some(l.value())
                } else {
                    None
                }
            })
        };
        let (Some(xi), Some(yi), Some(zi)) = (self.idx('X'), self.idx('Y'), self.idx('Z')) else {
            return Err(run_err(b, codes::RUN_BAD_G, "G12/G13 need X, Y and Z axes"));
        };
        let mut centre = [None; 6];
        for i in [xi, yi] {
            if let Some(v) = vals[i] {
                centre[i] = Some(if self.abs {
                    v + self.origin(i)
                } else {
                    self.machine[i] + v
                });
            }
        }
        if centre.iter().any(Option::is_some) {
            self.move_to(b, Kind::Linear, centre, m);
        }
        let (cx, cy) = (self.machine[xi], self.machine[yi]);
        let first = self
            .dim(b, 'I')
            .ok_or_else(|| run_err(b, codes::RUN_RANGE, "G12/G13 need I (first radius)"))?;
        let mut radii = vec![first];
        if let Some(k) = self.dim(b, 'K') {
            if let Some(q) = self.dim(b, 'Q').filter(|q| *q > 0.0) {
                let mut r = first + q;
                while r < k - 1e-9 {
                    radii.push(r);
                    r += q;
                }
            }
            radii.push(k);
        }
        // G12 implies G42, G13 implies G41: both keep the tool inside the pocket, so every circle of
        // the tool centre is the programmed radius less the radius of register D (D0: none). Circles
        // the tool already covers from the centre are left out; the finishing circle must remain.
        let kor = self.tool_radius(self.d);
        let finish = radii.last().copied().unwrap_or(first) - kor;
        if finish <= 1e-9 {
            return Err(run_err(
                b,
                codes::RUN_EQUIDISTANT,
                format!(
                    "G{}: the pocket radius {:.4} is not larger than the tool radius {kor:.4}",
                    g / 10,
                    finish + kor
                ),
            ));
        }
        let radii: Vec<f64> = radii
            .into_iter()
            .map(|r| r - kor)
            .filter(|r| *r > 1e-9)
            .collect();
        let reps = if self.abs {
            1
        } else {
            num('L').map_or(1, |l| l.max(1.0) as i64)
        };
        let cw = g == 120;
        for _ in 0..reps {
            if let Some(z) = vals[zi] {
                let mut t = [None; 6];
                t[zi] = Some(if self.abs {
                    z + self.origin(zi)
                } else {
                    self.machine[zi] + z
                });
                self.move_to(b, Kind::Linear, t, &[]);
            }
            for &r in &radii {
                let mut t = [None; 6];
                t[xi] = Some(cx + r);
                t[yi] = Some(cy);
                self.move_to(b, Kind::Linear, t, &[]);
                self.emit(
                    b,
                    if cw { Kind::ArcCw } else { Kind::ArcCcw },
                    vec![('X', cx), ('Y', cy)],
                    &[],
                    None,
                );
            }
            let mut t = [None; 6];
            t[xi] = Some(cx);
            t[yi] = Some(cy);
            self.move_to(b, Kind::Linear, t, &[]);
        }
        Ok(())
    }
}
