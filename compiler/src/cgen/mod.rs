//! The IR as C, for measuring the JIT against `gcc -O2` on exactly the program it compiles.
//!
//! Not a product path: [`emit_c`] writes one C translation unit with the semantics of
//! [`crate::ir`] (the interpreter's value model: integers as normalised `int64_t`), exporting
//! `void plc_tick(uint8_t *image)`. The scan benchmark compiles it with gcc, loads it and checks
//! that it produces the interpreter's images before timing it.

mod expr;

use std::fmt::Write;

use crate::ir::{self, CounterKind, Place, Program, Stmt, TimerKind};
use expr::{Kind, cond, expr, place_at};

/// Statements per generated C function (gcc compiles many small functions faster than one huge one).
const CHUNK: usize = 256;

/// The C translation unit of `program` (see the module docs).
pub fn emit_c(program: &Program) -> String {
    let mut out = String::with_capacity(64 * program.statement_count() + 8192);
    let _ = writeln!(out, "#define FAULTS_AT {}", ir::HDR_FAULTS);
    out.push_str(include_str!("prelude.h"));
    let mut parts = Vec::new();
    let emit_part = |name: String, stmts: &[Stmt], out: &mut String| {
        let mut calls = Vec::new();
        for (i, chunk) in stmts.chunks(CHUNK).enumerate() {
            let f = format!("{name}_{i}");
            let _ = writeln!(out, "static void {f}(u8 *restrict m) {{");
            for s in chunk {
                stmt(program, s, 1, out);
            }
            out.push_str("}\n");
            calls.push(f);
        }
        calls
    };
    let fast = emit_part("fast".into(), &program.fast, &mut out);
    for (i, slice) in program.slow.iter().enumerate() {
        parts.push(emit_part(format!("slow{i}"), slice, &mut out));
    }
    out.push_str("void plc_tick(u8 *restrict m) {\n");
    for f in &fast {
        let _ = writeln!(out, "  {f}(m);");
    }
    if !parts.is_empty() {
        let n = parts.len();
        let at = ir::HDR_NEXT_SLICE;
        let _ = writeln!(out, "  uint32_t next = (uint32_t)ld(m, {at}, 4);");
        let _ = writeln!(out, "  uint32_t i = next < {n}u ? next : 0;");
        out.push_str("  switch (i) {\n");
        for (i, calls) in parts.iter().enumerate() {
            let _ = write!(out, "  case {i}:");
            for f in calls {
                let _ = write!(out, " {f}(m);");
            }
            out.push_str(" break;\n");
        }
        out.push_str("  }\n");
        let _ = writeln!(out, "  st(m, {at}, 4, i + 1 == {n}u ? 0 : i + 1);");
    }
    out.push_str("}\n");
    out
}

fn indent(depth: usize, out: &mut String) {
    for _ in 0..depth {
        out.push_str("  ");
    }
}

fn stmt(p: &Program, s: &Stmt, depth: usize, out: &mut String) {
    indent(depth, out);
    match s {
        Stmt::Assign { place, value } => {
            let (v, k) = expr(p, value);
            store(p, place, &v, k, out);
        }
        Stmt::Set { place, cond: c } | Stmt::Res { place, cond: c } => {
            let one = if matches!(s, Stmt::Set { .. }) {
                "1"
            } else {
                "0"
            };
            let _ = write!(out, "if {} {{ ", cond(p, c));
            store(p, place, one, Kind::I, out);
            out.push_str(" }");
        }
        Stmt::Pulse { pulse, input } => {
            let at = p.pulses[pulse.0 as usize].offset;
            let _ = write!(out, "pulse(m, {at}, {});", cond(p, input));
        }
        Stmt::Timer { timer, input } => {
            let d = &p.timers[timer.0 as usize];
            let f = match d.kind {
                TimerKind::Ton => "ton",
                TimerKind::Tof => "tof",
                TimerKind::Tp => "tp",
            };
            let _ = write!(
                out,
                "{f}(m, {}, {}, {}, {});",
                d.offset,
                d.preset_ms,
                p.tick_ms as i32,
                cond(p, input)
            );
        }
        Stmt::CounterCount { counter, input } => {
            let d = &p.counters[counter.0 as usize];
            let up = i32::from(d.kind == CounterKind::Ctu);
            let _ = write!(out, "count(m, {}, {up}, {});", d.offset, cond(p, input));
        }
        Stmt::CounterReset { counter, input } => {
            let d = &p.counters[counter.0 as usize];
            let cv0 = match d.kind {
                CounterKind::Ctu => 0,
                CounterKind::Ctd => d.preset,
            };
            let _ = write!(out, "creset(m, {}, {cv0}, {});", d.offset, cond(p, input));
        }
        Stmt::If {
            cond: c,
            then_,
            else_,
        } => {
            let _ = writeln!(out, "if {} {{", cond(p, c));
            for s in then_ {
                stmt(p, s, depth + 1, out);
            }
            indent(depth, out);
            out.push_str("} else {\n");
            for s in else_ {
                stmt(p, s, depth + 1, out);
            }
            indent(depth, out);
            out.push('}');
        }
    }
    out.push('\n');
}

/// Stores the C value `v` of kind `k` into `place` (a bit stores `v != 0`).
fn store(p: &Program, place: &Place, v: &str, k: Kind, out: &mut String) {
    let (at, bit) = place_at(p, place);
    if let Some(bit) = bit {
        let _ = write!(
            out,
            "m[{at}] = (u8)((m[{at}] & {}) | ((({v}) != 0) << {bit}));",
            !(1u8 << bit)
        );
        return;
    }
    let n = p.place_ty(place).size();
    let _ = match k {
        Kind::F => write!(out, "stf(m, {at}, {v});"),
        Kind::D => write!(out, "std_(m, {at}, {v});"),
        Kind::I => write!(out, "st(m, {at}, {n}, (uint64_t)({v}));"),
    };
}
