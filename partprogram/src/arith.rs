//! Parameter arithmetic G26–G29: the reference interpreter of control words.
//!
//! A control word is the count r of a parameter, `±KK AA BB CC`: operation code, operand 1, operand 2,
//! target ("cíl"). A minus sign selects raw-integer arithmetic, a plus sign decimal arithmetic on r/1000
//! (parameters-cycles spec §4.2–§4.3). Field values 50..99 address the double-precision pair
//! (n−50, n−49) when double precision is enabled (§4.4): the 64-bit value v is stored as
//! `hi = v >> 32` in the first and `lo = v & 0xFFFF_FFFF` in the second parameter.
//!
//! Choices where the manual is silent (documented in DIAGNOSTICS.md): division and real→int truncate
//! toward zero; float results round to nearest; angles are degrees; division by zero, √ or log of an
//! invalid argument, overflow of a 32-bit parameter, codes 36, 40, 43 and >51 are run-time errors.
//! The native code in [`crate::jit`] reproduces this module bit for bit.

use detmath::Det as _;
mod tables;

use crate::machine::DoublePrecision;

/// Number of R parameters.
pub const NPARAM: usize = 96;

/// Why an arithmetic operation failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum ArithError {
    /// Division by zero.
    #[error("division by zero")]
    DivZero,
    /// A result does not fit a 32-bit parameter.
    #[error("result does not fit a parameter")]
    Overflow,
    /// √, log, arcsin or similar of an invalid argument.
    #[error("invalid argument")]
    Domain,
    /// The operation code is not defined (43, >51) or its operands are not defined by the manual (36, 40).
    #[error("operation code {0} is not defined")]
    BadOp(u8),
    /// A parameter field addresses a parameter that does not exist.
    #[error("parameter field {0} addresses no parameter")]
    BadField(u8),
    /// Binary shift by more than 32 (64 for double) places.
    #[error("shift count out of range")]
    Shift,
}

impl ArithError {
    /// Stable numeric code used across the native-code boundary (non-zero).
    pub fn code(self) -> i32 {
        match self {
            ArithError::DivZero => 2,
            ArithError::Overflow => 3,
            ArithError::Domain => 4,
            ArithError::BadOp(k) => 1000 + i32::from(k),
            ArithError::BadField(f) => 2000 + i32::from(f),
            ArithError::Shift => 5,
        }
    }

    /// Inverse of [`ArithError::code`].
    pub fn from_code(c: i32) -> ArithError {
        match c {
            2 => ArithError::DivZero,
            3 => ArithError::Overflow,
            4 => ArithError::Domain,
            5 => ArithError::Shift,
            c if (1000..1100).contains(&c) => ArithError::BadOp((c - 1000) as u8),
            c if (2000..2100).contains(&c) => ArithError::BadField((c - 2000) as u8),
            _ => ArithError::Overflow,
        }
    }
}

/// A message raised by operation 51.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Message {
    /// Message code 1..99.
    pub code: u8,
    /// Value of the shown parameter (count r).
    pub value: i64,
    /// Display mode 0..3.
    pub mode: u8,
}

/// Everything parameter arithmetic reads and writes. `r` comes first so native code can address it.
#[derive(Debug, Clone)]
#[repr(C)]
pub struct ArithState {
    /// R0..R95 as thousandths counts.
    pub r: [i64; NPARAM],
    /// The SAVE area of operation 44.
    pub saved: [i64; NPARAM],
    /// Programmed position per axis ordinal 1..6 (index 0..5), mm (X as radius under diameter programming).
    pub programmed: [f64; 6],
    /// Zero-offset table G53..G59 (index 0..6) × axis ordinal, mm.
    pub offsets: [[f64; 6]; 7],
    /// Correction table D0..D99 × datum (0 radius, 1..4 lengths of axes 1..4), mm.
    pub corrections: Vec<[f64; 5]>,
    /// Current M function per M group 1..14 (index = group).
    pub m_groups: [u16; 15],
    /// Current G function per G group 0..11.
    pub g_groups: [u16; 12],
    /// Current S, T, D.
    pub s_t_d: [i64; 3],
    /// Double-precision setting.
    pub double: DoublePrecision,
    /// Messages raised by operation 51.
    pub messages: Vec<Message>,
}

impl Default for ArithState {
    fn default() -> Self {
        ArithState {
            r: [0; NPARAM],
            saved: [0; NPARAM],
            programmed: [0.0; 6],
            offsets: [[0.0; 6]; 7],
            corrections: vec![[0.0; 5]; 100],
            m_groups: [0, 0, 5, 40, 36, 9, 53, 0, 48, 0, 0, 0, 0, 0, 0],
            g_groups: [1, 17, 98, 40, 0, 53, 94, 70, 80, 90, 0, 34],
            s_t_d: [0; 3],
            double: DoublePrecision::Enabled,
            messages: Vec::new(),
        }
    }
}

/// A decoded control word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Word {
    /// True for the raw-integer (minus) mode.
    pub raw: bool,
    /// Operation code.
    pub op: u8,
    /// Operand 1 field.
    pub a: u8,
    /// Operand 2 field.
    pub b: u8,
    /// Target field.
    pub c: u8,
}

impl Word {
    /// Decodes the count r of a control parameter; None when it has more than 8 digits.
    pub fn decode(r: i64) -> Option<Word> {
        let w = r.unsigned_abs();
        if w > 99_999_999 {
            return None;
        }
        Some(Word {
            raw: r < 0,
            op: (w / 1_000_000) as u8,
            a: ((w / 10_000) % 100) as u8,
            b: ((w / 100) % 100) as u8,
            c: (w % 100) as u8,
        })
    }
}

/// Outcome of one operation for the sequence runner.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// Continue with the next operation.
    Next,
    /// A condition was false: skip up to and including the next code 22.
    Skip,
}

/// Fits a result into a single 32-bit parameter.
pub fn fit(v: i64) -> Result<i64, ArithError> {
    if v < i64::from(i32::MIN) || v > i64::from(i32::MAX) {
        Err(ArithError::Overflow)
    } else {
        Ok(v)
    }
}

fn round(v: f64) -> Result<i64, ArithError> {
    if !v.is_finite() || v.abs() > 9.0e18 {
        return Err(ArithError::Domain);
    }
    Ok(v.round() as i64)
}

impl ArithState {
    /// True when fields 50..99 address pairs.
    pub fn double_enabled(&self) -> bool {
        match self.double {
            DoublePrecision::Enabled => true,
            DoublePrecision::Disabled => false,
            DoublePrecision::ByR95 => self.r[95].unsigned_abs().is_multiple_of(10),
        }
    }

    /// Reads the value addressed by field `f`.
    pub fn read(&self, f: u8) -> Result<i64, ArithError> {
        if self.double_enabled() && f >= 50 {
            let i = usize::from(f - 50);
            Ok((self.r[i] << 32) | (self.r[i + 1] & 0xFFFF_FFFF))
        } else if usize::from(f) < NPARAM {
            Ok(self.r[usize::from(f)])
        } else {
            Err(ArithError::BadField(f))
        }
    }

    /// Writes `v` to the target addressed by field `f` (a pair or a 32-bit parameter).
    pub fn write(&mut self, f: u8, v: i64) -> Result<(), ArithError> {
        if self.double_enabled() && f >= 50 {
            let i = usize::from(f - 50);
            self.r[i] = v >> 32;
            self.r[i + 1] = v & 0xFFFF_FFFF;
            Ok(())
        } else if usize::from(f) < NPARAM {
            self.r[usize::from(f)] = fit(v)?;
            Ok(())
        } else {
            Err(ArithError::BadField(f))
        }
    }

    fn is_pair(&self, f: u8) -> bool {
        self.double_enabled() && f >= 50
    }

    fn param_index(f: u8) -> Result<usize, ArithError> {
        if usize::from(f) < NPARAM {
            Ok(usize::from(f))
        } else {
            Err(ArithError::BadField(f))
        }
    }

    /// Executes the control word with count `r`.
    pub fn exec(&mut self, r: i64) -> Result<Step, ArithError> {
        let w = Word::decode(r).ok_or(ArithError::BadOp(99))?;
        self.exec_word(w, 0)
    }

    /// Runs the operations in `words` in order with IF…ENDIF skipping.
    pub fn exec_seq(&mut self, words: &[i64]) -> Result<(), ArithError> {
        self.exec_seq_depth(words, 0)
    }

    fn exec_seq_depth(&mut self, words: &[i64], depth: u8) -> Result<(), ArithError> {
        let mut skipping = false;
        for &r in words {
            let w = Word::decode(r).ok_or(ArithError::BadOp(99))?;
            if skipping {
                if w.op == 22 {
                    skipping = false;
                }
                continue;
            }
            if self.exec_word(w, depth)? == Step::Skip {
                skipping = true;
            }
            if w.op == 33 {
                break;
            }
        }
        Ok(())
    }

    fn float_in(&self, f: u8, raw: bool) -> Result<f64, ArithError> {
        let v = self.read(f)? as f64;
        Ok(if raw { v } else { v / 1000.0 })
    }

    fn float_out(&mut self, f: u8, raw: bool, v: f64) -> Result<(), ArithError> {
        let v = round(if raw { v } else { v * 1000.0 })?;
        self.write(f, v)
    }

    fn cond(&self, w: Word, t: impl Fn(i64, i64) -> bool) -> Result<Step, ArithError> {
        Ok(if t(self.read(w.a)?, self.read(w.b)?) {
            Step::Next
        } else {
            Step::Skip
        })
    }

    fn compare(&mut self, w: Word, t: impl Fn(i64, i64) -> bool) -> Result<Step, ArithError> {
        let v = if t(self.read(w.a)?, self.read(w.b)?) {
            73
        } else {
            78
        };
        self.write(w.c, v)?;
        Ok(Step::Next)
    }

    /// Executes one decoded operation.
    pub fn exec_word(&mut self, w: Word, depth: u8) -> Result<Step, ArithError> {
        let raw = w.raw;
        match w.op {
            0 => {
                if self.is_pair(w.a) && self.is_pair(w.c) {
                    let (s, d) = (usize::from(w.a - 50), usize::from(w.c - 50));
                    let (x, y) = (self.r[s], self.r[s + 1]);
                    self.r[d] = x;
                    self.r[d + 1] = y;
                } else {
                    let v = self.read(w.a)?;
                    self.write(w.c, v)?;
                }
            }
            1 => {
                let v = self
                    .read(w.a)?
                    .checked_add(self.read(w.b)?)
                    .ok_or(ArithError::Overflow)?;
                self.write(w.c, v)?;
            }
            2 => {
                let v = self
                    .read(w.a)?
                    .checked_sub(self.read(w.b)?)
                    .ok_or(ArithError::Overflow)?;
                self.write(w.c, v)?;
            }
            3 => {
                let p = i128::from(self.read(w.a)?) * i128::from(self.read(w.b)?);
                let p = if raw { p } else { p / 1000 };
                self.write(w.c, i64::try_from(p).map_err(|_| ArithError::Overflow)?)?;
            }
            4 => {
                let (x, y) = (self.read(w.a)?, self.read(w.b)?);
                if y == 0 {
                    return Err(ArithError::DivZero);
                }
                let q = if raw {
                    i128::from(x) / i128::from(y)
                } else {
                    i128::from(x) * 1000 / i128::from(y)
                };
                self.write(w.c, i64::try_from(q).map_err(|_| ArithError::Overflow)?)?;
            }
            5 => {
                let x = i128::from(self.read(w.a)?);
                let p = if raw { x * x } else { x * x / 1000 };
                self.write(w.c, i64::try_from(p).map_err(|_| ArithError::Overflow)?)?;
            }
            6 => {
                let x = self.float_in(w.a, raw)?;
                if x < 0.0 {
                    return Err(ArithError::Domain);
                }
                self.float_out(w.c, raw, x.sqrt())?;
            }
            7 => {
                let v = self.read(w.a)?.checked_abs().ok_or(ArithError::Overflow)?;
                self.write(w.c, v)?;
            }
            8 => {
                let v = self.read(w.a)?.checked_neg().ok_or(ArithError::Overflow)?;
                self.write(w.c, v)?;
            }
            9 => {
                let n = self.r[Self::param_index(w.b)?];
                let limit = if self.is_pair(w.a) || self.is_pair(w.c) {
                    64
                } else {
                    32
                };
                if n.abs() > limit {
                    return Err(ArithError::Shift);
                }
                let x = i128::from(self.read(w.a)?);
                let v = if n >= 0 { x << n } else { x >> (-n) };
                self.write(w.c, i64::try_from(v).map_err(|_| ArithError::Overflow)?)?;
            }
            10 => {
                let x = self.read(w.a)?;
                if x == 0 {
                    return Err(ArithError::DivZero);
                }
                let v = if raw { 1 / x } else { 1_000_000 / x };
                self.write(w.c, v)?;
            }
            11 => {
                let x = self.float_in(w.a, raw)?;
                self.float_out(w.c, raw, x.exp2())?;
            }
            12 => {
                let x = self.float_in(w.a, raw)?;
                if x <= 0.0 {
                    return Err(ArithError::Domain);
                }
                self.float_out(w.c, raw, x.dlog2())?;
            }
            13 => {
                let (x, y) = (self.float_in(w.a, raw)?, self.float_in(w.b, raw)?);
                self.float_out(w.c, raw, x.dpowf(y))?;
            }
            14 => {
                let (x, y) = (self.float_in(w.a, raw)?, self.float_in(w.b, raw)?);
                self.float_out(w.c, raw, x.dhypot(y))?;
            }
            15 => return self.compare(w, |x, y| x > y),
            16 => return self.compare(w, |x, y| x >= y),
            17 => return self.compare(w, |x, y| x < y),
            18 => return self.compare(w, |x, y| x <= y),
            19 => return self.compare(w, |x, y| x == y),
            20 => return self.cond(w, |x, y| x == y),
            21 => return self.cond(w, |x, y| x != y),
            22 => {}
            23 => {
                let v = self
                    .read(w.a)?
                    .checked_mul(1000)
                    .ok_or(ArithError::Overflow)?;
                self.write(w.c, v)?;
            }
            24 => {
                let v = self.read(w.a)? / 1000;
                self.write(w.c, v)?;
            }
            25 | 26 => {
                let pos = |o: u8| -> Result<i64, ArithError> {
                    if !(1..=6).contains(&o) {
                        return Err(ArithError::BadField(o));
                    }
                    round(self.programmed[usize::from(o - 1)] * 1000.0)
                };
                if self.is_pair(w.c) {
                    let (x, y) = (pos(w.a)?, pos(w.b)?);
                    let d = usize::from(w.c - 50);
                    self.r[d] = fit(x)?;
                    self.r[d + 1] = fit(y)?;
                } else {
                    let x = pos(w.a)?;
                    self.write(w.c, x)?;
                }
            }
            27 => {
                let x = self.float_in(w.a, raw)?;
                self.float_out(w.c, raw, x.to_radians().dtan())?;
            }
            28 => {
                let (k, n) = (self.float_in(w.a, raw)?, self.float_in(w.b, raw)?);
                let v = if k == 1.0 {
                    n
                } else {
                    (k.dpowf(n) - 1.0) / (k - 1.0)
                };
                self.float_out(w.c, raw, v)?;
            }
            29 => return self.cond(w, |x, y| x > y),
            30 => return self.cond(w, |x, y| x >= y),
            31 => return self.cond(w, |x, y| x < y),
            32 => return self.cond(w, |x, y| x <= y),
            33 => {
                let (s, e) = (Self::param_index(w.a)?, Self::param_index(w.c)?);
                if depth >= 4 || s > e {
                    return Err(ArithError::BadField(w.a));
                }
                let words: Vec<i64> = self.r[s..=e].to_vec();
                self.exec_seq_depth(&words, depth + 1)?;
            }
            34 => {
                let (b, c) = (Self::param_index(w.b)?, Self::param_index(w.c)?);
                if w.a == 99 {
                    if c > b {
                        return Err(ArithError::BadField(w.c));
                    }
                    self.r[c..=b].fill(0);
                } else {
                    let a = Self::param_index(w.a)?;
                    if a > b || c + (b - a) >= NPARAM {
                        return Err(ArithError::BadField(w.c));
                    }
                    let tmp: Vec<i64> = self.r[a..=b].to_vec();
                    self.r[c..c + tmp.len()].copy_from_slice(&tmp);
                }
            }
            35 => {
                let (a, b, c) = (
                    Self::param_index(w.a)?,
                    Self::param_index(w.b)?,
                    Self::param_index(w.c)?,
                );
                if a > b || c + (b - a) >= NPARAM {
                    return Err(ArithError::BadField(w.c));
                }
                for k in 0..=(b - a) {
                    self.r.swap(a + k, c + k);
                }
            }
            37 | 38 => {
                let x = self.float_in(w.a, raw)?.to_radians();
                let v = if w.op == 37 { x.dsin() } else { x.dcos() };
                self.write(w.c, round(v * 10_000_000.0)?)?;
            }
            39 => {
                let (x, y) = (self.float_in(w.a, raw)?, self.float_in(w.b, raw)?);
                if y == 0.0 {
                    return Err(ArithError::DivZero);
                }
                let q = x / y;
                if !(-1.0..=1.0).contains(&q) {
                    return Err(ArithError::Domain);
                }
                self.float_out(w.c, raw, q.dasin().to_degrees())?;
            }
            41 | 42 => {
                let step = i64::from(if w.b == 0 { 1 } else { w.b });
                let step = if raw { step } else { step * 1000 };
                let x = self.read(w.a)?;
                let v = if w.op == 41 {
                    x.checked_add(step)
                } else {
                    x.checked_sub(step)
                };
                self.write(w.c, v.ok_or(ArithError::Overflow)?)?;
            }
            44 => self.saved = self.r,
            45 => {
                if w.a == 0 && w.b == 0 && w.c == 0 {
                    self.r = self.saved;
                } else {
                    let (a, b, c) = (
                        Self::param_index(w.a)?,
                        Self::param_index(w.b)?,
                        Self::param_index(w.c)?,
                    );
                    if a > b || c + (b - a) >= NPARAM {
                        return Err(ArithError::BadField(w.c));
                    }
                    for k in 0..=(b - a) {
                        self.r[c + k] = self.saved[a + k];
                    }
                }
            }
            46 | 47 => {
                let odd = self.read(w.a)? % 2 != 0;
                let v = if odd == (w.op == 46) { 73 } else { 78 };
                self.write(w.c, v)?;
            }
            48 => self.logic(w)?,
            49 => self.read_table(w)?,
            50 => self.write_table(w)?,
            51 => {
                let p = Self::param_index(w.b)?;
                self.messages.push(Message {
                    code: w.a,
                    value: self.r[p],
                    mode: w.c % 10,
                });
            }
            op => return Err(ArithError::BadOp(op)),
        }
        Ok(Step::Next)
    }
}
