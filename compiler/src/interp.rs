//! The reference interpreter: a direct tree walk of the IR, the semantics oracle the JIT is tested
//! against. It follows the rules in the [`crate::ir`] module docs literally.

use std::sync::Arc;

use crate::engine::Engine;
use crate::ir::{
    self, BinOp, CmpOp, CounterKind, Expr, FLAG_PREV, FLAG_Q, FLAG_RUN, Place, Program, Stmt,
    TimerKind, Ty, UnOp,
};

/// The tree-walking interpreter.
pub struct Interpreter {
    program: Arc<Program>,
    valid: bool,
}

/// A value during evaluation: integers and BOOL normalised to their type in an i64.
#[derive(Debug, Clone, Copy)]
enum V {
    I(i64),
    F(f32),
    D(f64),
}

impl V {
    fn i(self) -> i64 {
        match self {
            V::I(v) => v,
            V::F(f) => f as i64,
            V::D(d) => d as i64,
        }
    }
    fn b(self) -> bool {
        self.i() != 0
    }
}

/// Wraps an i64 to the value range of `ty` (BOOL: 0/1).
fn norm(ty: Ty, v: i64) -> i64 {
    match ty {
        Ty::Bool => i64::from(v != 0),
        Ty::Byte => i64::from(v as u8),
        Ty::Word => i64::from(v as u16),
        Ty::Dword => i64::from(v as u32),
        Ty::Int => i64::from(v as i16),
        Ty::Dint => i64::from(v as i32),
        Ty::Real | Ty::Lreal => v,
    }
}

fn canon32(f: f32) -> f32 {
    if f.is_nan() {
        f32::from_bits(ir::CANON_NAN_F32)
    } else {
        f
    }
}

fn canon64(f: f64) -> f64 {
    if f.is_nan() {
        f64::from_bits(ir::CANON_NAN_F64)
    } else {
        f
    }
}

fn read_le(image: &[u8], at: usize, n: usize) -> u64 {
    let mut b = [0u8; 8];
    b[..n].copy_from_slice(&image[at..at + n]);
    u64::from_le_bytes(b)
}

fn write_le(image: &mut [u8], at: usize, n: usize, v: u64) {
    image[at..at + n].copy_from_slice(&v.to_le_bytes()[..n]);
}

/// Decodes stored bits of type `ty`.
fn from_bits(ty: Ty, bits: u64) -> V {
    match ty {
        Ty::Real => V::F(f32::from_bits(bits as u32)),
        Ty::Lreal => V::D(f64::from_bits(bits)),
        Ty::Int => V::I(i64::from(bits as u16 as i16)),
        Ty::Dint => V::I(i64::from(bits as u32 as i32)),
        _ => V::I(norm(ty, bits as i64)),
    }
}

fn to_bits(v: V) -> u64 {
    match v {
        V::I(i) => i as u64,
        V::F(f) => u64::from(f.to_bits()),
        V::D(d) => d.to_bits(),
    }
}

fn read_i32(image: &[u8], at: usize) -> i32 {
    read_le(image, at, 4) as u32 as i32
}

fn write_i32(image: &mut [u8], at: usize, v: i32) {
    write_le(image, at, 4, u64::from(v as u32));
}

impl Interpreter {
    /// An interpreter for `program` (an invalid program makes every tick a no-op).
    pub fn new(program: Arc<Program>) -> Self {
        let valid = program.validate().is_ok();
        Interpreter { program, valid }
    }

    /// Runs a list of statements (used by tick, and by tests for a single part).
    fn run(&self, stmts: &[Stmt], m: &mut [u8]) {
        for s in stmts {
            self.stmt(s, m);
        }
    }

    fn place_offset(&self, place: &Place) -> (usize, Option<u8>) {
        match *place {
            Place::Signal(sig) => (sig.image_byte(), sig.bit()),
            Place::View { at, .. } => (at.image_byte(), None),
            Place::Var(v) => (self.program.vars[v.0 as usize].offset, None),
            Place::VarBit { var, bit } => (
                self.program.vars[var.0 as usize].offset + bit as usize / 8,
                Some(bit % 8),
            ),
        }
    }

    fn load(&self, place: &Place, m: &[u8]) -> V {
        let (at, bit) = self.place_offset(place);
        if let Some(bit) = bit {
            return V::I(i64::from((m[at] >> bit) & 1));
        }
        let ty = self.program.place_ty(place);
        from_bits(ty, read_le(m, at, ty.size()))
    }

    fn store(&self, place: &Place, v: V, m: &mut [u8]) {
        let (at, bit) = self.place_offset(place);
        if let Some(bit) = bit {
            m[at] = (m[at] & !(1 << bit)) | (u8::from(v.b()) << bit);
            return;
        }
        let ty = self.program.place_ty(place);
        write_le(m, at, ty.size(), to_bits(v));
    }

    fn stmt(&self, s: &Stmt, m: &mut [u8]) {
        let p = &*self.program;
        match s {
            Stmt::Assign { place, value } => {
                let v = self.expr(value, m);
                self.store(place, v, m);
            }
            Stmt::Set { place, cond } => {
                if self.expr(cond, m).b() {
                    self.store(place, V::I(1), m);
                }
            }
            Stmt::Res { place, cond } => {
                if self.expr(cond, m).b() {
                    self.store(place, V::I(0), m);
                }
            }
            Stmt::Pulse { pulse, input } => {
                let x = self.expr(input, m).b();
                let at = p.pulses[pulse.0 as usize].offset;
                let prev = m[at] & FLAG_PREV != 0;
                m[at] = u8::from(x && !prev) | if x { FLAG_PREV } else { 0 };
            }
            Stmt::Timer { timer, input } => {
                let x = self.expr(input, m).b();
                let d = &p.timers[timer.0 as usize];
                timer_step(d.kind, d.preset_ms, p.tick_ms as i32, x, m, d.offset);
            }
            Stmt::CounterCount { counter, input } => {
                let x = self.expr(input, m).b();
                let d = &p.counters[counter.0 as usize];
                let f = m[d.offset + 4];
                let rising = x && f & FLAG_PREV == 0;
                if rising && f & FLAG_RUN == 0 {
                    let cv = read_i32(m, d.offset);
                    let cv = match d.kind {
                        CounterKind::Ctu => cv.saturating_add(1),
                        CounterKind::Ctd => cv.saturating_sub(1),
                    };
                    write_i32(m, d.offset, cv);
                }
                m[d.offset + 4] = (f & !FLAG_PREV) | if x { FLAG_PREV } else { 0 };
            }
            Stmt::CounterReset { counter, input } => {
                let x = self.expr(input, m).b();
                let d = &p.counters[counter.0 as usize];
                if x {
                    let cv = match d.kind {
                        CounterKind::Ctu => 0,
                        CounterKind::Ctd => d.preset,
                    };
                    write_i32(m, d.offset, cv);
                }
                let f = m[d.offset + 4];
                m[d.offset + 4] = (f & !FLAG_RUN) | if x { FLAG_RUN } else { 0 };
            }
            Stmt::If { cond, then_, else_ } => {
                if self.expr(cond, m).b() {
                    self.run(then_, m);
                } else {
                    self.run(else_, m);
                }
            }
        }
    }

    fn expr(&self, e: &Expr, m: &mut [u8]) -> V {
        let p = &*self.program;
        match e {
            Expr::Const(v) => from_bits(v.ty(), v.to_bits()),
            Expr::Load(place) => self.load(place, m),
            Expr::BitOf { value, bit, .. } => V::I((self.expr(value, m).i() >> bit) & 1),
            Expr::Not(a) => V::I(i64::from(!self.expr(a, m).b())),
            Expr::Unary { op, ty, arg } => unary(*op, *ty, self.expr(arg, m)),
            Expr::Binary { op, ty, lhs, rhs } => {
                let a = self.expr(lhs, m);
                let b = self.expr(rhs, m);
                binary(*op, *ty, a, b, m)
            }
            Expr::Cmp { op, lhs, rhs, .. } => {
                let a = self.expr(lhs, m);
                let b = self.expr(rhs, m);
                V::I(i64::from(compare(*op, a, b)))
            }
            Expr::Convert { from, to, arg } => convert(*from, *to, self.expr(arg, m)),
            Expr::Bcd { ty, arg } => {
                let mut v = to_bits(self.expr(arg, m)) & mask(*ty);
                let mut r = 0u64;
                for i in 0..2 * ty.size() {
                    r |= (v % 10) << (4 * i);
                    v /= 10;
                }
                V::I(norm(*ty, r as i64))
            }
            Expr::Bin { ty, arg } => {
                let v = to_bits(self.expr(arg, m)) & mask(*ty);
                let mut r = 0u64;
                let mut scale = 1u64;
                for i in 0..2 * ty.size() {
                    r = r.wrapping_add(((v >> (4 * i)) & 0xF).wrapping_mul(scale));
                    scale = scale.wrapping_mul(10);
                }
                V::I(norm(*ty, r as i64))
            }
            Expr::Limit { ty, lo, x, hi } => {
                let lo = self.expr(lo, m);
                let x = self.expr(x, m);
                let hi = self.expr(hi, m);
                let t = binary(BinOp::Max, *ty, x, lo, m);
                binary(BinOp::Min, *ty, t, hi, m)
            }
            Expr::Pulse(id) => V::I(i64::from(m[p.pulses[id.0 as usize].offset] & 1)),
            Expr::TimerQ(id) => V::I(i64::from(m[p.timers[id.0 as usize].offset + 4] & FLAG_Q)),
            Expr::TimerEt(id) => V::I(i64::from(read_i32(m, p.timers[id.0 as usize].offset))),
            Expr::CounterQ(id) => {
                let d = &p.counters[id.0 as usize];
                let cv = read_i32(m, d.offset);
                V::I(i64::from(match d.kind {
                    CounterKind::Ctu => cv >= d.preset,
                    CounterKind::Ctd => cv <= 0,
                }))
            }
            Expr::CounterCv(id) => V::I(i64::from(read_i32(m, p.counters[id.0 as usize].offset))),
        }
    }
}

/// One execution of a timer (the rules on [`Stmt::Timer`]).
fn timer_step(kind: TimerKind, pt: i32, tick: i32, x: bool, m: &mut [u8], at: usize) {
    let f = m[at + 4];
    let prev = f & FLAG_PREV != 0;
    let running = f & FLAG_RUN != 0;
    let mut et = read_i32(m, at);
    let (q, run) = match kind {
        TimerKind::Ton => {
            et = if x && prev {
                et.wrapping_add(tick).min(pt)
            } else {
                0
            };
            (x && et >= pt, false)
        }
        TimerKind::Tof => {
            let mut run = false;
            if x {
                et = 0;
            } else {
                if prev {
                    run = true;
                    et = 0;
                } else if running {
                    run = true;
                    et = et.wrapping_add(tick);
                }
                if run && et >= pt {
                    run = false;
                }
            }
            (x || run, run)
        }
        TimerKind::Tp => {
            let run = if running {
                et = et.wrapping_add(tick);
                et < pt
            } else if x && !prev && pt > 0 {
                et = 0;
                true
            } else {
                if !x {
                    et = 0;
                }
                false
            };
            (run, run)
        }
    };
    write_i32(m, at, et);
    m[at + 4] =
        (u8::from(q) * FLAG_Q) | if x { FLAG_PREV } else { 0 } | if run { FLAG_RUN } else { 0 };
}

fn mask(ty: Ty) -> u64 {
    if ty.size() >= 8 {
        u64::MAX
    } else {
        (1u64 << (8 * ty.size())) - 1
    }
}

fn unary(op: UnOp, ty: Ty, a: V) -> V {
    match (op, a) {
        (UnOp::Neg, V::F(f)) => V::F(-f),
        (UnOp::Neg, V::D(d)) => V::D(-d),
        (UnOp::Abs, V::F(f)) => V::F(f.abs()),
        (UnOp::Abs, V::D(d)) => V::D(d.abs()),
        (UnOp::Neg, V::I(i)) => V::I(norm(ty, i.wrapping_neg())),
        (UnOp::Abs, V::I(i)) => V::I(norm(ty, i.wrapping_abs())),
        (UnOp::BitNot, V::I(i)) => V::I(norm(ty, !i)),
        (_, v) => v,
    }
}

fn fmin32(a: f32, b: f32) -> f32 {
    if b < a { b } else { a }
}
fn fmax32(a: f32, b: f32) -> f32 {
    if b > a { b } else { a }
}
fn fmin64(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}
fn fmax64(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

fn binary(op: BinOp, ty: Ty, a: V, b: V, m: &mut [u8]) -> V {
    match (a, b) {
        (V::F(x), V::F(y)) => V::F(match op {
            BinOp::Add => canon32(x + y),
            BinOp::Sub => canon32(x - y),
            BinOp::Mul => canon32(x * y),
            BinOp::Div => canon32(x / y),
            BinOp::Min => fmin32(x, y),
            BinOp::Max => fmax32(x, y),
            _ => x,
        }),
        (V::D(x), V::D(y)) => V::D(match op {
            BinOp::Add => canon64(x + y),
            BinOp::Sub => canon64(x - y),
            BinOp::Mul => canon64(x * y),
            BinOp::Div => canon64(x / y),
            BinOp::Min => fmin64(x, y),
            BinOp::Max => fmax64(x, y),
            _ => x,
        }),
        (a, b) => {
            let (x, y) = (a.i(), b.i());
            let r = match op {
                BinOp::Add => x.wrapping_add(y),
                BinOp::Sub => x.wrapping_sub(y),
                BinOp::Mul => x.wrapping_mul(y),
                BinOp::Div | BinOp::Mod => {
                    if y == 0 {
                        let f = read_le(m, ir::HDR_FAULTS, 4) | u64::from(ir::FAULT_DIV_ZERO);
                        write_le(m, ir::HDR_FAULTS, 4, f);
                        0
                    } else if op == BinOp::Div {
                        x.wrapping_div(y)
                    } else {
                        x.wrapping_rem(y)
                    }
                }
                BinOp::BitAnd | BinOp::And => x & y,
                BinOp::BitOr | BinOp::Or => x | y,
                BinOp::BitXor | BinOp::Xor => x ^ y,
                BinOp::Shl | BinOp::Shr => {
                    let amount = (y as u64) & mask(ty);
                    if amount >= u64::from(ty.bits()) {
                        if op == BinOp::Shr && x < 0 { -1 } else { 0 }
                    } else if op == BinOp::Shl {
                        x << amount
                    } else {
                        x >> amount
                    }
                }
                BinOp::Min => x.min(y),
                BinOp::Max => x.max(y),
            };
            V::I(norm(ty, r))
        }
    }
}

fn compare(op: CmpOp, a: V, b: V) -> bool {
    macro_rules! cmp {
        ($x:expr, $y:expr) => {
            match op {
                CmpOp::Eq => $x == $y,
                CmpOp::Ne => $x != $y,
                CmpOp::Lt => $x < $y,
                CmpOp::Le => $x <= $y,
                CmpOp::Gt => $x > $y,
                CmpOp::Ge => $x >= $y,
            }
        };
    }
    match (a, b) {
        (V::F(x), V::F(y)) => cmp!(x, y),
        (V::D(x), V::D(y)) => cmp!(x, y),
        (a, b) => cmp!(a.i(), b.i()),
    }
}

fn convert(_from: Ty, to: Ty, a: V) -> V {
    match (a, to) {
        (V::F(f), Ty::Real) => V::F(f),
        (V::F(f), Ty::Lreal) => V::D(canon64(f64::from(f))),
        (V::D(d), Ty::Real) => V::F(canon32(d as f32)),
        (V::D(d), Ty::Lreal) => V::D(d),
        (V::F(f), Ty::Bool) => V::I(i64::from(f != 0.0)),
        (V::D(d), Ty::Bool) => V::I(i64::from(d != 0.0)),
        (V::F(f), _) => V::I(norm(to, f as i64)),
        (V::D(d), _) => V::I(norm(to, d as i64)),
        (V::I(i), Ty::Real) => V::F(i as f32),
        (V::I(i), Ty::Lreal) => V::D(i as f64),
        (V::I(i), _) => V::I(norm(to, i)),
    }
}

impl Engine for Interpreter {
    fn tick(&mut self, image: &mut [u8]) {
        let p = &*self.program;
        if !self.valid || image.len() < p.image_len {
            return;
        }
        self.run(&p.fast, image);
        if !p.slow.is_empty() {
            let next = read_le(image, ir::HDR_NEXT_SLICE, 4) as usize;
            let i = if next < p.slow.len() { next } else { 0 };
            self.run(&p.slow[i], image);
            let n = if i + 1 == p.slow.len() { 0 } else { i + 1 };
            write_le(image, ir::HDR_NEXT_SLICE, 4, n as u64);
        }
    }

    fn name(&self) -> &'static str {
        "interp"
    }
}
