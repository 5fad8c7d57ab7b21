//! Power flow for an HMI's Program page: every statement gets a slot in a *flow area* appended to
//! the image, and the scan writes into it the value the statement computed — the assigned value
//! (read back from its target), or the condition of an IF, SET/RES, one-shot, timer or counter
//! input. An IR-to-IR pass: both back ends run the instrumented program as any other, so the
//! flow is the same on the JIT and the interpreter by construction (the differential tests run
//! instrumented programs too).
//!
//! Slot `k` belongs to the `k`-th statement in pre-order (FAST, then the SLOW slices in order; an
//! IF before its branches), whose source line is [`Program::lines`]`[k]`. A statement that did not
//! run this scan (a branch not taken, a SLOW slice not due) keeps its last value.

use serde::{Deserialize, Serialize};

use super::{Expr, Place, Program, Stmt, Ty, Value, VarDecl, VarId};

/// One statement's slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct FlowSlot {
    /// The statement's 1-based source line.
    pub line: u32,
    /// Image offset of the value.
    pub offset: usize,
    /// Its type (BOOL for conditions).
    pub ty: Ty,
}

/// Where an instrumented program writes its power flow.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct FlowMap {
    /// One slot per statement, in pre-order.
    pub slots: Vec<FlowSlot>,
    /// The flow area: image bytes `start..end`.
    pub area: (usize, usize),
}

/// `program` with every statement writing its flow slot, and the map of the slots; `None` when
/// the program has no source lines (built without a source) or they do not match its statements.
pub fn instrument(program: &Program) -> Option<(Program, FlowMap)> {
    let count = count(&program.fast) + program.slow.iter().map(|s| count(s)).sum::<usize>();
    if count == 0 || program.lines.len() != count {
        return None;
    }
    let mut p = program.clone();
    let start = p.image_len.div_ceil(8) * 8;
    let mut pass = Pass {
        lines: &program.lines,
        vars: std::mem::take(&mut p.vars),
        at: start,
        map: FlowMap::default(),
    };
    p.fast = pass.block(std::mem::take(&mut p.fast));
    let slow = std::mem::take(&mut p.slow);
    p.slow = slow.into_iter().map(|s| pass.block(s)).collect();
    p.vars = pass.vars;
    p.image_len = pass.at;
    pass.map.area = (start, pass.at);
    p.validate().ok()?;
    Some((p, pass.map))
}

/// Statements in pre-order.
pub fn count(stmts: &[Stmt]) -> usize {
    stmts
        .iter()
        .map(|s| match s {
            Stmt::If { then_, else_, .. } => 1 + count(then_) + count(else_),
            _ => 1,
        })
        .sum()
}

struct Pass<'a> {
    lines: &'a [u32],
    vars: Vec<VarDecl>,
    at: usize,
    map: FlowMap,
}

impl Pass<'_> {
    /// A new flow slot of type `ty` for the next statement.
    fn slot(&mut self, ty: Ty) -> Place {
        let k = self.map.slots.len();
        let size = ty.size();
        self.at = self.at.div_ceil(size) * size;
        let id = VarId(self.vars.len() as u32);
        self.vars.push(VarDecl {
            name: format!("$FLOW{k}"),
            ty,
            init: Value::zero(ty),
            retain: false,
            offset: self.at,
        });
        self.map.slots.push(FlowSlot {
            line: self.lines.get(k).copied().unwrap_or(0),
            offset: self.at,
            ty,
        });
        self.at += size;
        Place::Var(id)
    }

    fn block(&mut self, stmts: Vec<Stmt>) -> Vec<Stmt> {
        let mut out = Vec::with_capacity(stmts.len() * 2);
        for s in stmts {
            self.stmt(s, &mut out);
        }
        out
    }

    /// Rewrites `s` into `out`: a condition is computed into its slot first and read from there
    /// (so it is evaluated once, as before); an assignment's slot is read back from the target.
    fn stmt(&mut self, s: Stmt, out: &mut Vec<Stmt>) {
        let via = |pass: &mut Self, e: Expr, out: &mut Vec<Stmt>| {
            let place = pass.slot(Ty::Bool);
            out.push(Stmt::Assign { place, value: e });
            Expr::Load(place)
        };
        match s {
            Stmt::Assign { place, value } => {
                let ty = self.place_ty(&place);
                let slot = self.slot(ty);
                out.push(Stmt::Assign { place, value });
                out.push(Stmt::Assign {
                    place: slot,
                    value: Expr::Load(place),
                });
            }
            Stmt::Set { place, cond } => {
                let cond = via(self, cond, out);
                out.push(Stmt::Set { place, cond });
            }
            Stmt::Res { place, cond } => {
                let cond = via(self, cond, out);
                out.push(Stmt::Res { place, cond });
            }
            Stmt::Pulse { pulse, input } => {
                let input = via(self, input, out);
                out.push(Stmt::Pulse { pulse, input });
            }
            Stmt::Timer { timer, input } => {
                let input = via(self, input, out);
                out.push(Stmt::Timer { timer, input });
            }
            Stmt::CounterCount { counter, input } => {
                let input = via(self, input, out);
                out.push(Stmt::CounterCount { counter, input });
            }
            Stmt::CounterReset { counter, input } => {
                let input = via(self, input, out);
                out.push(Stmt::CounterReset { counter, input });
            }
            Stmt::If { cond, then_, else_ } => {
                let cond = via(self, cond, out);
                let then_ = self.block(then_);
                let else_ = self.block(else_);
                out.push(Stmt::If { cond, then_, else_ });
            }
        }
    }

    fn place_ty(&self, place: &Place) -> Ty {
        match place {
            Place::Signal(packets::Signal::Bit { .. }) | Place::VarBit { .. } => Ty::Bool,
            Place::Signal(packets::Signal::Byte { .. }) => Ty::Byte,
            Place::View { ty, .. } => *ty,
            Place::Var(v) => self.vars.get(v.0 as usize).map_or(Ty::Bool, |d| d.ty),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use crate::{Engine, Interpreter, MachineContext, compile};

    const SRC: &str = "DEF A = I0A0\nU4A0 = A * I0A1\nIF I0A2 THEN\nSET U4A1 = I0A1\nELSE\nRES U4A1 = 1\nEND_IF\nU4A2 = /U4A0\n";

    #[test]
    fn each_statement_writes_what_it_computed_into_its_lines_slot() {
        let ctx = MachineContext {
            a_inputs: vec![0],
            a_outputs: vec![4],
            ..MachineContext::lathe_like()
        };
        let c = compile("PLCPRG", SRC.as_bytes(), &ctx);
        assert_eq!(c.diagnostics, vec![]);
        let p = c.program.expect("compiles");
        assert_eq!(p.lines, [2, 3, 4, 6, 8]);
        let (f, map) = super::instrument(&p).expect("instruments");
        let lines: Vec<u32> = map.slots.iter().map(|s| s.line).collect();
        assert_eq!(lines, [2, 3, 4, 6, 8]);
        let f = Arc::new(f);
        let mut interp = Interpreter::new(f.clone());
        let mut jit = crate::jit::compile(&f).expect("JIT compiles");
        let mut a = f.new_image();
        let mut b = f.new_image();
        let sig = |s: &str| s.parse::<packets::Signal>().expect("signal");
        // (I0A0, I0A1, I0A2) per tick and the slots after it: line 2 the AND, line 3 the IF's
        // condition, lines 4 and 6 the SET/RES conditions (a branch not run keeps its value),
        // line 8 the NOT.
        for (inputs, flow) in [
            ([1, 1, 0], [1, 0, 0, 1, 0]),
            ([1, 0, 1], [0, 1, 0, 1, 1]),
            ([1, 1, 1], [1, 1, 1, 1, 0]),
        ] {
            for (name, v) in ["I0A0", "I0A1", "I0A2"].iter().zip(inputs) {
                sig(name).write(&mut a, v);
                sig(name).write(&mut b, v);
            }
            interp.tick(&mut a);
            jit.tick(&mut b);
            assert_eq!(a, b);
            let got: Vec<u8> = map.slots.iter().map(|s| a[s.offset]).collect();
            assert_eq!(got, flow, "inputs {inputs:?}");
        }
    }
}
