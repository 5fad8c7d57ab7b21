//! Operations with their own sub-field layouts: 48 LOGIC (decade logic), 49 READ(TAB) and 50 WRITE.

use super::{ArithError, ArithState, Word, fit, round};

impl ArithState {
    pub(super) fn logic(&mut self, w: Word) -> Result<(), ArithError> {
        let kind = w.a / 10;
        let dec = u32::from(w.a % 10);
        if !(1..=8).contains(&dec) {
            return Err(ArithError::BadField(w.a));
        }
        let pow = 10i64.pow(dec - 1);
        let digit = |v: i64| (v.unsigned_abs() as i64 / pow) % 10;
        let set = |v: i64, d: i64| {
            let mag = v.unsigned_abs() as i64;
            let mag = mag - ((mag / pow) % 10) * pow + d * pow;
            if v < 0 { -mag } else { mag }
        };
        let c = Self::param_index(w.c)?;
        let tgt = self.r[c];
        let p1 = || -> Result<i64, ArithError> { Ok(self.r[Self::param_index(w.b)?]) };
        let v = match kind {
            1 => set(tgt, 1),
            2 => set(tgt, 0),
            3 => set(tgt, i64::from(digit(tgt) == 0)),
            4 => set(tgt, i64::from(digit(p1()?) != 0 || digit(tgt) != 0)),
            5 => set(tgt, i64::from(digit(p1()?) != 0 && digit(tgt) != 0)),
            6 => set(tgt, i64::from((digit(p1()?) != 0) != (digit(tgt) != 0))),
            7 => {
                if digit(p1()?) != 0 {
                    73
                } else {
                    78
                }
            }
            _ => return Err(ArithError::BadOp(48)),
        };
        self.r[c] = fit(v)?;
        Ok(())
    }

    pub(super) fn read_table(&mut self, w: Word) -> Result<(), ArithError> {
        let (table, col, src) = (w.a / 10, w.a % 10, w.b);
        let v = match table {
            1 => {
                let e = self
                    .corrections
                    .get(usize::from(src))
                    .ok_or(ArithError::BadField(src))?;
                round(
                    e.get(usize::from(col))
                        .copied()
                        .ok_or(ArithError::BadField(w.a))?
                        * 1000.0,
                )?
            }
            2 => {
                if !(53..=59).contains(&src) || !(1..=6).contains(&col) {
                    return Err(ArithError::BadField(src));
                }
                round(self.offsets[usize::from(src - 53)][usize::from(col - 1)] * 1000.0)?
            }
            3 => 0,
            4 | 5 => match col {
                1 => i64::from(
                    *self
                        .m_groups
                        .get(usize::from(src))
                        .ok_or(ArithError::BadField(src))?,
                ),
                2 => i64::from(
                    *self
                        .g_groups
                        .get(usize::from(src))
                        .ok_or(ArithError::BadField(src))?,
                ),
                5 => self.s_t_d[0],
                6 => self.s_t_d[1],
                8 => self.s_t_d[2],
                _ => 0,
            },
            _ => return Err(ArithError::BadField(w.a)),
        };
        let c = Self::param_index(w.c)?;
        self.r[c] = fit(v)?;
        Ok(())
    }

    pub(super) fn write_table(&mut self, w: Word) -> Result<(), ArithError> {
        let (table, col) = (w.a / 10, w.a % 10);
        let v = self.r[Self::param_index(w.b)?] as f64 / 1000.0;
        match table {
            1 => {
                let e = self
                    .corrections
                    .get_mut(usize::from(w.c))
                    .ok_or(ArithError::BadField(w.c))?;
                *e.get_mut(usize::from(col))
                    .ok_or(ArithError::BadField(w.a))? = v;
            }
            2 => {
                if !(53..=59).contains(&w.c) || !(1..=6).contains(&col) {
                    return Err(ArithError::BadField(w.c));
                }
                self.offsets[usize::from(w.c - 53)][usize::from(col - 1)] = v;
            }
            _ => return Err(ArithError::BadField(w.a)),
        }
        Ok(())
    }
}
