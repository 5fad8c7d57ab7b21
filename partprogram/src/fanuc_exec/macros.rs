//! Macro B in the Fanuc executor: the variable table, system variables, statements, `G65` calls and
//! words whose values are expressions.
//!
//! Variables: `#0` null; `#1`–`#33` local (a new set per `G65` level, bound from the arguments;
//! `M98` keeps the caller's); `#100`–`#199` common, null at the start of every plan; `#500`–`#999`
//! retained: at the start of a plan they hold [`crate::MachineSpec::retained`] (the machine's
//! `nc/MACROVARS`, [`crate::macro_b::retained`]), and the plan's final values are what a part run
//! writes back.
//! System variables, in the program unit (mm, or inch under G20), axes numbered in the machine's axis
//! order: `#2001`–`#2099` tool length of H1–H99 (the tool axis Z column, as `G10 L10`), `#2201`–`#2299`
//! its wear (`G10 L11`), `#2401`–`#2600` cutter radius of D1–D200 (as `G10 L12`; HAAS keeps
//! diameters there), `#2601`–`#2800` its wear (`G10 L13`), `#4001`–`#4130` and `#4201`–`#4330`
//! modal information (read only, [`modal_code`]: G groups, B, D, F, H, M, N, O, S, T), `#3000` alarm (writing stops
//! the run with 2531 and the block's comment), `#5001`+ end point of the last block in work
//! coordinates, `#5021`+ machine coordinates, `#5041`+ current work coordinates (no motion is in
//! progress in a plan: the same as `#5001`+), `#5201`+ external work offset (added to every work
//! system), `#5221`+ … `#5321`+ G54–G59 (20 apart).

use super::{Ex, Frame, run_err};
use crate::ast::{Val, Word};
use crate::canon::Plane;
use crate::codes;
use crate::exec::RunError;
use crate::lexer::{Lit, parse_number};
use crate::macro_b::eval::{MacroError, Vars, eval, is_null, truth, var_number, z};
use crate::macro_b::native::SysVars;
use crate::macro_b::{Expr, Macro, SLOTS, Stmt, Target, is_plain};
use crate::program::CBlock;

/// Deepest `G65` nesting (Fanuc: 5 levels of local variables below the main program).
pub const MAX_MACRO_LEVELS: usize = 5;

/// True for the system variables the executor reads or writes (see the module doc).
pub fn is_system(n: u32) -> bool {
    matches!(n, 2001..=2099 | 2201..=2299 | 2401..=2600 | 2601..=2800 | 3000)
        || modal_code(n).is_some()
        || matches!(n, 5001..=5006 | 5021..=5026 | 5041..=5046 | 5201..=5206)
        || (5221..=5326).contains(&n) && (n - 5221) % 20 < 6
}

/// The modal-information variable `#4001`–`#4130` (`#4201`–`#4330`: the executing block, the same
/// in a plan, which buffers nothing) that `n` names, as its `#40xx`/`#41xx` number.
pub fn modal_code(n: u32) -> Option<u32> {
    let k = match n {
        4001..=4130 => n,
        4201..=4330 => n - 200,
        _ => return None,
    };
    matches!(
        k,
        4001..=4003
            | 4005..=4014
            | 4016
            | 4102
            | 4107
            | 4109
            | 4111
            | 4113..=4115
            | 4119
            | 4120
            | 4130
    )
    .then_some(k)
}

/// The variable table of a plan.
#[derive(Debug, Clone)]
pub struct VarTable {
    /// Slot n is variable #n for the plain numbers; NaN is null.
    pub slots: Vec<f64>,
}

impl Default for VarTable {
    fn default() -> Self {
        VarTable {
            slots: vec![f64::NAN; SLOTS],
        }
    }
}

/// The saved locals of the caller of a `G65` level, and the level's own initial locals (L repeats).
#[derive(Debug, Clone)]
pub(super) struct MacroLevel {
    pub saved: [f64; 34],
    pub init: [f64; 34],
}

/// A value as the literal an NC word reads (rounded like a written number with a point).
fn lit_of(v: f64) -> Option<Lit> {
    parse_number(&format!("{v:.6}"))
}

fn merr(b: &CBlock, e: MacroError) -> RunError {
    run_err(b, codes::RUN_MACRO, e.to_string())
}

impl Vars for Ex<'_> {
    fn get(&self, n: i64) -> Result<f64, MacroError> {
        let Ok(u) = u32::try_from(n) else {
            return Err(MacroError::NoVar(n));
        };
        if u == 0 {
            return Ok(f64::NAN);
        }
        if is_plain(u) {
            return Ok(self.vars.slots[u as usize]);
        }
        let unit = if self.inch { 25.4 } else { 1.0 };
        let axis = |base: u32| -> Result<usize, MacroError> {
            let k = (u - base) as usize;
            if k < self.axes.len() {
                Ok(k)
            } else {
                Err(MacroError::NoVar(n))
            }
        };
        if let Some(k) = modal_code(u) {
            return Ok(self.modal(k));
        }
        let v = match u {
            2001..=2099 => self.tool_length_entry(u as usize - 2000)?,
            2201..=2299 => self.wear[u as usize - 2200][0],
            2601..=2800 => self.wear[u as usize - 2600][1],
            2401..=2600 => self
                .corrections
                .get(u as usize - 2400)
                .map_or(0.0, |c| c[0]),
            5001..=5006 | 5041..=5046 => {
                let i = axis(if u < 5041 { 5001 } else { 5041 })?;
                self.machine[i] - self.origin(i)
            }
            5021..=5026 => self.machine[axis(5021)?],
            5201..=5206 => self.ext[axis(5201)?],
            5221..=5326 if is_system(u) => {
                let row = ((u - 5221) / 20) as usize;
                self.work[row][axis(5221 + 20 * row as u32)?]
            }
            _ => return Err(MacroError::NoVar(n)),
        };
        Ok(v / unit)
    }
}

impl SysVars for Ex<'_> {
    fn read_sys(&self, n: u32) -> Option<f64> {
        (is_system(n) && n != 3000)
            .then(|| Vars::get(self, i64::from(n)).ok())
            .flatten()
    }

    fn write_sys(&mut self, n: u32, v: f64) -> bool {
        is_system(n) && n != 3000 && self.set_system(n, v).is_ok()
    }
}

impl Ex<'_> {
    /// Modal information `#4001`–`#4130` (`k`, see [`modal_code`]): the G code of a group, or the
    /// last B (never: null), D, F (program unit per minute), H, M (not M97–M99), N (the latest
    /// executed block with one, the reading block included), S, T, G154 P, and the O number of the
    /// executing program or subprogram; null when never given.
    fn modal(&self, k: u32) -> f64 {
        let opt = |v: Option<f64>| v.unwrap_or(f64::NAN);
        match k {
            4001 => f64::from(self.motion / 10),
            4002 => match self.plane {
                Plane::ZX => 18.0,
                Plane::YZ => 19.0,
                _ => 17.0,
            },
            4003 => {
                if self.abs {
                    90.0
                } else {
                    91.0
                }
            }
            4005 => 94.0,
            4006 => {
                if self.inch {
                    20.0
                } else {
                    21.0
                }
            }
            4007 => f64::from(self.comp),
            4008 => match self.tlo_sign {
                Some((s, _)) if s > 0.0 => 43.0,
                Some(_) => 44.0,
                None => 49.0,
            },
            4009 => self.cycle.map_or(80.0, |g| f64::from(g / 10)),
            4010 => {
                if self.g99 {
                    99.0
                } else {
                    98.0
                }
            }
            4011 => 50.0,
            4012 => {
                if self.exact_modal {
                    61.0
                } else {
                    64.0
                }
            }
            4013 => 97.0,
            4014 => {
                if self.wsel < 6 {
                    54.0 + self.wsel as f64
                } else {
                    154.0
                }
            }
            4016 => 69.0,
            // B is an axis address or refused: no second auxiliary function is ever given.
            4102 => f64::NAN,
            4107 => self.d as f64,
            4109 => opt(self.feed.map(|f| if self.inch { f / 25.4 } else { f })),
            4111 => self.tlo_h as f64,
            4113 => opt(self.last_m.map(f64::from)),
            4114 => self
                .vars
                .slots
                .get(crate::macro_b::SEQ_SLOT)
                .copied()
                .unwrap_or(f64::NAN),
            4115 => self
                .frames
                .last()
                .map_or(f64::NAN, |f| f64::from(self.prog.units[f.unit].l)),
            4119 => opt(self.s),
            4120 => opt(self.t.map(|t| t as f64)),
            4130 => {
                if self.wsel < 6 {
                    0.0
                } else {
                    (self.wsel - 5) as f64
                }
            }
            _ => f64::NAN,
        }
    }

    /// Length of the tool axis (Z) in correction entry `h`.
    fn tool_length_entry(&self, h: usize) -> Result<f64, MacroError> {
        let col = self
            .axes
            .iter()
            .position(|a| *a == 'Z')
            .and_then(crate::length::datum_of_axis)
            .ok_or(MacroError::NoVar(2000 + h as i64))?;
        Ok(self.corrections.get(h).map_or(0.0, |c| c[col]))
    }

    /// Writes variable `n` (raw value: null stays null in plain variables, reads as 0 elsewhere).
    fn set(&mut self, b: &CBlock, n: i64, v: f64) -> Result<(), RunError> {
        let u = u32::try_from(n).map_err(|_| merr(b, MacroError::NoVar(n)))?;
        if is_plain(u) {
            self.vars.slots[u as usize] = v;
            return Ok(());
        }
        if u == 3000 {
            let f = &self.prog.files[b.file];
            let text = f.text.get(b.span.0..b.span.1).unwrap_or("");
            let msg = text
                .find('(')
                .map(|i| text[i + 1..].trim_end_matches(')').trim().to_string())
                .unwrap_or_default();
            return Err(run_err(
                b,
                codes::RUN_MACRO,
                format!("macro alarm #3000 = {}: {msg}", z(v)),
            ));
        }
        self.set_system(u, v).map_err(|e| merr(b, e))
    }

    /// Writes system variable `u` (not `#3000`); nothing changes on an error.
    fn set_system(&mut self, u: u32, v: f64) -> Result<(), MacroError> {
        let n = i64::from(u);
        let unit = if self.inch { 25.4 } else { 1.0 };
        let x = z(v) * unit;
        let naxes = self.axes.len();
        let axis = |base: u32| -> Result<usize, MacroError> {
            let k = (u - base) as usize;
            if k < naxes {
                Ok(k)
            } else {
                Err(MacroError::NoVar(n))
            }
        };
        let entry = |t: &mut Vec<[f64; 5]>, i: usize| {
            if t.len() <= i {
                t.resize(i + 1, [0.0; 5]);
            }
        };
        match u {
            2001..=2099 => {
                let col = self
                    .axes
                    .iter()
                    .position(|a| *a == 'Z')
                    .and_then(crate::length::datum_of_axis)
                    .ok_or(MacroError::ReadOnly(n))?;
                entry(&mut self.corrections, u as usize - 2000);
                self.corrections[u as usize - 2000][col] = x;
            }
            2401..=2600 => {
                entry(&mut self.corrections, u as usize - 2400);
                self.corrections[u as usize - 2400][0] = x;
            }
            2201..=2299 => self.wear[u as usize - 2200][0] = x,
            2601..=2800 => self.wear[u as usize - 2600][1] = x,
            5201..=5206 => {
                let i = axis(5201)?;
                self.ext[i] = x;
            }
            5221..=5326 if is_system(u) => {
                let row = ((u - 5221) / 20) as usize;
                let i = axis(5221 + 20 * row as u32)?;
                self.work[row][i] = x;
            }
            _ => return Err(MacroError::ReadOnly(n)),
        }
        Ok(())
    }

    fn ev(&self, b: &CBlock, e: &Expr) -> Result<f64, RunError> {
        eval(e, self).map_err(|x| merr(b, x))
    }

    fn target(&self, b: &CBlock, t: &Target) -> Result<i64, RunError> {
        match t {
            Target::Var(n) => Ok(i64::from(*n)),
            Target::At(e) => Ok(var_number(self.ev(b, e)?)),
        }
    }

    fn jump_to(&mut self, b: &CBlock, to: usize) {
        if let Some(fr) = self.frames.last_mut() {
            fr.pc = to;
        }
        let _ = b;
    }

    /// Runs the statement of macro block `b`.
    pub(super) fn statement(&mut self, b: &CBlock, stmt: &Stmt) -> Result<(), RunError> {
        match stmt {
            Stmt::Assign(t, e) => {
                let v = self.ev(b, e)?;
                let n = self.target(b, t)?;
                self.set(b, n, v)
            }
            Stmt::IfThen(c, t, e) => {
                if truth(self.ev(b, c)?) {
                    let v = self.ev(b, e)?;
                    let n = self.target(b, t)?;
                    self.set(b, n, v)?;
                }
                Ok(())
            }
            Stmt::Goto(t) => self.goto(b, t),
            Stmt::IfGoto(c, t) => {
                if truth(self.ev(b, c)?) {
                    self.goto(b, t)?;
                }
                Ok(())
            }
            Stmt::While(c, _) => {
                let go = match c {
                    Some(c) => truth(self.ev(b, c)?),
                    None => true,
                };
                if !go && let Some(end) = b.jump {
                    self.jump_to(b, end + 1);
                }
                Ok(())
            }
            Stmt::End(_) => {
                if let Some(d) = b.jump {
                    self.jump_to(b, d);
                }
                Ok(())
            }
            Stmt::Call { p, l, args } => self.g65(b, *p, *l, args),
        }
    }

    fn goto(&mut self, b: &CBlock, t: &Expr) -> Result<(), RunError> {
        if let Some(to) = b.jump {
            self.jump_to(b, to);
            return Ok(());
        }
        let v = z(self.ev(b, t)?);
        let n = (v >= 0.0 && v.fract() == 0.0 && v <= 99_999_999.0).then_some(v as u32);
        let to = n
            .and_then(|n| self.prog.units[b.unit].index.get(n))
            .ok_or_else(|| {
                run_err(
                    b,
                    codes::RUN_TARGET,
                    format!("GOTO {v}: no block N{v} in this program"),
                )
            })?;
        self.jump_to(b, to);
        Ok(())
    }

    /// `G65 P<p> L<l>`: a new level of locals bound from the arguments.
    fn g65(&mut self, b: &CBlock, p: u32, l: u32, args: &[(u8, Expr)]) -> Result<(), RunError> {
        let mut init = [f64::NAN; 34];
        for (v, e) in args {
            init[usize::from(*v)] = self.ev(b, e)?;
        }
        let unit = match self.prog.library.get(&p) {
            Some(&u) => u,
            None if self.prog.units[0].l == p && p != 0 => 0,
            None => return Err(run_err(b, codes::RUN_TARGET, format!("no program O{p}"))),
        };
        if l == 0 {
            return Ok(());
        }
        let levels = self.frames.iter().filter(|f| f.level.is_some()).count();
        if levels >= MAX_MACRO_LEVELS || self.frames.len() >= 64 {
            return Err(run_err(
                b,
                codes::RUN_LIMIT,
                format!("G65 calls nested deeper than {MAX_MACRO_LEVELS} levels"),
            ));
        }
        let mut saved = [f64::NAN; 34];
        saved.copy_from_slice(&self.vars.slots[0..34]);
        self.vars.slots[0..34].copy_from_slice(&init);
        let start = self.prog.units[unit].start;
        self.frames.push(Frame {
            unit,
            pc: start,
            target: start,
            repeat: i64::from(l),
            level: Some(Box::new(MacroLevel { saved, init })),
        });
        Ok(())
    }

    /// Leaves the innermost frame, restoring the caller's locals after a `G65` level.
    pub(super) fn pop_frame(&mut self) {
        if let Some(fr) = self.frames.pop()
            && let Some(level) = fr.level
        {
            self.vars.slots[0..34].copy_from_slice(&level.saved);
        }
    }

    /// Starts the next repetition of the innermost frame (M99 with L left): a `G65` level starts
    /// again from its arguments.
    pub(super) fn restart_locals(&mut self) {
        if let Some(init) = self
            .frames
            .last()
            .and_then(|f| f.level.as_ref())
            .map(|l| l.init)
        {
            self.vars.slots[0..34].copy_from_slice(&init);
        }
    }

    /// The block `b` with its expression words evaluated: a null value drops the word (Fanuc: an
    /// address with an undefined variable is not commanded).
    pub(super) fn substitute(&self, b: &CBlock, m: &Macro) -> Result<CBlock, RunError> {
        let mut words: Vec<Word> = Vec::with_capacity(b.words.len());
        for w in &b.words {
            match w.val {
                Val::Expr(i) => {
                    let e = m
                        .exprs
                        .get(i as usize)
                        .ok_or_else(|| run_err(b, codes::RUN_MACRO, "missing expression"))?;
                    let v = self.ev(b, e)?;
                    if is_null(v) {
                        continue;
                    }
                    let l = lit_of(v).ok_or_else(|| {
                        run_err(
                            b,
                            codes::RUN_MACRO,
                            format!("value {v} does not fit address {}", w.addr),
                        )
                    })?;
                    words.push(Word {
                        val: Val::Lit(l),
                        ..*w
                    });
                }
                _ => words.push(*w),
            }
        }
        Ok(CBlock {
            n: b.n,
            file: b.file,
            unit: b.unit,
            span: b.span,
            skip: b.skip,
            words: words.into_boxed_slice(),
            decls: b.decls.clone(),
            arith_ops: b.arith_ops,
            native: b.native,
            mac: None,
            jump: b.jump,
        })
    }
}
