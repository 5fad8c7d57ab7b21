//! Static checks of Macro B control flow, per program unit: `WHILE … DO m` / `DO m` pair with the next
//! `END m` (m = 1..3; loops nest at most three deep, an inner loop may not reuse an open number and
//! loops may not overlap), literal `GOTO n` targets must be block numbers of the unit, and `G65 P`
//! must name a loaded program. Pairs and targets are stored in [`CBlock::jump`].

use diag::{Diagnostic, Sink};

use super::{Expr, Stmt};
use crate::codes;
use crate::program::{CBlock, Program};

fn err(prog: &Program, b: &CBlock, code: u32, msg: String, hint: &str) -> Diagnostic {
    let f = &prog.files[b.file];
    crate::program::err(code, &f.name, &f.text, b.span, msg, hint)
}

/// A literal block number of a `GOTO` (None when computed).
pub fn literal_target(e: &Expr) -> Option<f64> {
    match e {
        Expr::Num(v) => Some(*v),
        _ => None,
    }
}

/// Checks and links the macro blocks of `prog`.
pub fn link(prog: &mut Program, diags: &mut Sink) {
    let mut links: Vec<(usize, usize)> = Vec::new();
    for u in 0..prog.units.len() {
        let unit = &prog.units[u];
        let mut open: Vec<(u8, usize)> = Vec::new();
        for bi in unit.start..unit.end {
            let b = &prog.blocks[bi];
            let Some(stmt) = b.mac.as_ref().and_then(|m| m.stmt.as_ref()) else {
                continue;
            };
            match stmt {
                Stmt::While(_, m) => {
                    if open.iter().any(|(id, _)| id == m) {
                        diags.push(err(
                            prog,
                            b,
                            codes::MACRO_NESTING,
                            format!("DO {m} inside an open DO {m}"),
                            "nested loops need different numbers 1..3",
                        ));
                    } else if open.len() >= 3 {
                        diags.push(err(
                            prog,
                            b,
                            codes::MACRO_NESTING,
                            "loops nested deeper than 3".into(),
                            "WHILE … DO loops nest at most three levels",
                        ));
                    }
                    open.push((*m, bi));
                }
                Stmt::End(m) => match open.last() {
                    Some(&(id, d)) if id == *m => {
                        open.pop();
                        links.push((d, bi));
                        links.push((bi, d));
                    }
                    _ if open.iter().any(|(id, _)| id == m) => {
                        diags.push(err(
                            prog,
                            b,
                            codes::MACRO_NESTING,
                            format!("END {m} closes an outer loop while an inner one is open: loops overlap"),
                            "close the inner loop first",
                        ));
                        while open.last().is_some_and(|(id, _)| id != m) {
                            open.pop();
                        }
                        if let Some((_, d)) = open.pop() {
                            links.push((d, bi));
                            links.push((bi, d));
                        }
                    }
                    _ => diags.push(err(
                        prog,
                        b,
                        codes::MACRO_NESTING,
                        format!("END {m} without WHILE … DO {m}"),
                        "every END m closes the last open DO m",
                    )),
                },
                Stmt::Goto(t) | Stmt::IfGoto(_, t) => {
                    if let Some(v) = literal_target(t) {
                        let n = (v >= 0.0 && v.fract() == 0.0 && v <= 99_999_999.0)
                            .then_some(v as u32)
                            .and_then(|n| unit.index.get(n));
                        match n {
                            Some(t) => links.push((bi, t)),
                            None => diags.push(err(
                                prog,
                                b,
                                codes::MISSING_BLOCK,
                                format!("GOTO {v}: no block N{v} in this program"),
                                "GOTO jumps to a block number of the same program",
                            )),
                        }
                    }
                }
                Stmt::Call { p, .. } => {
                    if !(prog.library.contains_key(p) || (prog.units[0].l == *p && *p != 0)) {
                        diags.push(err(
                            prog,
                            b,
                            codes::MISSING_SUBPROGRAM,
                            format!("G65 P{p}: program O{p} not found"),
                            "store macro programs as files O<n> in the machine's macro folder or after the main program",
                        ));
                    }
                }
                Stmt::Assign(..) | Stmt::IfThen(..) => {}
            }
        }
        for (m, bi) in open {
            diags.push(err(
                prog,
                &prog.blocks[bi],
                codes::MACRO_NESTING,
                format!("DO {m} without END {m}"),
                "close the loop with END m in the same program",
            ));
        }
    }
    for (bi, t) in links {
        prog.blocks[bi].jump = Some(t);
    }
}
