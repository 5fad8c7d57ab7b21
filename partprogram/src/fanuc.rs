//! The Fanuc/HAAS dialect: units, static checks and the executor.
//!
//! Blocks end at the line end or `;`; `( … )` are comments; `O<n>` names a program (the first the
//! main program, every further one a program M98 can call). Supported: G00–G03 (I/J/K or R arcs, full
//! circles with I/J/K), G04 P, G09/G61/G64 P, G10 L2/L10/L12/L20, G17–G19, G20/G21, G28, G40–G42 D,
//! G43/G44/G49 H, G52, G53, G54–G59, G110–G129, G154 P, G90/G91, G92, G94, G96/G97 (G50 S: top
//! speed of G96), G98/G99 with the canned cycles G73, G74, G81–G86, G89 and L repeats (G80, G00/G01
//! cancel), G12/G13 circular pockets, G7.1 cylinder interpolation, M97/M98 P L, M99; G50 without S,
//! G69 and G100 are no-ops (their functions are refused). Everything else is refused with a located
//! error; the table is docs/fanuc-conformance.md.
//! The manual gives no peck retract amount for G73: 0.5 mm is used (documented in DIAGNOSTICS.md).

use std::collections::HashMap;

use diag::{Diagnostic, Sink};

use crate::ast::Val;
use crate::codes;
use crate::groups::{fanuc_g_group, fanuc_m_group};
use crate::program::{CBlock, Program, SourceFile};

fn err(
    code: u32,
    f: &SourceFile,
    span: (usize, usize),
    msg: impl Into<String>,
    hint: &str,
) -> Diagnostic {
    crate::program::err(code, &f.name, &f.text, span, msg, hint)
}

fn lit(v: &Val) -> Option<f64> {
    match v {
        Val::Lit(l) => Some(l.value()),
        Val::Param(_) | Val::Expr(_) => None,
    }
}

/// An `M97`/`M98` call of a block with its literal `P` (None: none written): what the unit
/// builder ([`crate::fanuc_units`]) checks once the targets are known.
pub(crate) type MCall = (i64, Option<u32>);

/// The static checks of block `b` of `prog` on a machine with `axes` into `diags`; returns its
/// `M97`/`M98` calls.
pub(crate) fn check_block(
    prog: &Program,
    b: &CBlock,
    axes: &[char],
    diags: &mut Sink,
) -> Vec<MCall> {
    // On a lathe H is the incremental C address, not a length register.
    let lathe = !axes.contains(&'Y');
    let f = &prog.files[b.file];
    let mut seen: HashMap<char, ()> = HashMap::new();
    let mut groups: HashMap<u8, ()> = HashMap::new();
    let mut m_calls = Vec::new();
    for w in &b.words {
        if let Val::Param(_) = w.val {
            diags.push(err(
                codes::UNKNOWN_ADDRESS,
                f,
                w.span,
                "`R<n>` parameters are MEFI syntax",
                "write literal values in the Fanuc/HAAS dialect",
            ));
            continue;
        }
        let v = lit(&w.val).unwrap_or(0.0);
        let known = matches!(
            w.addr,
            'G' | 'M' | 'I' | 'J' | 'K' | 'R' | 'F' | 'S' | 'T' | 'D' | 'H' | 'P' | 'Q' | 'L'
        ) || (lathe && matches!(w.addr, 'U' | 'W'))
            || axes.contains(&w.addr);
        if w.addr == 'E' {
            diags.push(err(
                codes::UNKNOWN_ADDRESS,
                f,
                w.span,
                "address E (G187 corner accuracy) is not supported",
                "see docs/fanuc-conformance.md",
            ));
            continue;
        }
        if !known {
            diags.push(err(
                codes::UNKNOWN_ADDRESS,
                f,
                w.span,
                format!("unknown address `{}`", w.addr),
                "Fanuc/HAAS addresses: O N G M X Y Z A B C I J K R F S T D H P Q L E",
            ));
            continue;
        }
        match w.addr {
            'G' => {
                let key = (v * 10.0).round() as i64;
                match u16::try_from(key).ok().and_then(fanuc_g_group) {
                    Some(gr) => {
                        if gr != 0 && groups.insert(gr, ()).is_some() {
                            diags.push(err(
                                codes::GROUP_CONFLICT,
                                f,
                                w.span,
                                "two G codes of the same group",
                                "one G code per modal group per block",
                            ));
                        }
                    }
                    None => diags.push(err(
                        codes::UNKNOWN_G,
                        f,
                        w.span,
                        format!("G{v} is not supported by the Fanuc/HAAS dialect"),
                        "see gcode-haas-fanuc.md §4",
                    )),
                }
            }
            'M' => {
                let m = v as i64;
                if !(0..=199).contains(&m) || v.fract() != 0.0 {
                    diags.push(err(
                        codes::OUT_OF_RANGE,
                        f,
                        w.span,
                        "M code out of range",
                        "M0..M199",
                    ));
                } else if m == 96 {
                    diags.push(err(
                        codes::UNKNOWN_G,
                        f,
                        w.span,
                        "M96 (jump if no input) is not supported: a plan cannot read inputs",
                        "see docs/fanuc-conformance.md",
                    ));
                } else {
                    if prog.machine.check_m_declared
                        && m < 97
                        && prog.machine.m_timing(m as u16).is_none()
                    {
                        diags.push(err(
                            codes::UNDECLARED_M,
                            f,
                            w.span,
                            format!("M{m:02} is not declared for process 1 in IOCFIL section 2"),
                            "declare it in IOCFIL section 2",
                        ));
                    }
                    if let Some(g) = fanuc_m_group(m)
                        && m_calls.iter().any(|&o| fanuc_m_group(o) == Some(g))
                    {
                        diags.push(err(
                            codes::GROUP_CONFLICT,
                            f,
                            w.span,
                            format!("M{m:02} contradicts an M code of its group in the block"),
                            "one of M03 M04 M05 M19, of M07 M08 M09, of M00 M01 M02 M30, of M97 M98 M99 per block",
                        ));
                    }
                    m_calls.push(m);
                }
            }
            'N' | 'D' | 'H' | 'T' | 'L' if v < 0.0 => diags.push(err(
                codes::OUT_OF_RANGE,
                f,
                w.span,
                format!("{} must not be negative", w.addr),
                "",
            )),
            'H' if v > 99.0 && !lathe => diags.push(err(
                codes::OUT_OF_RANGE,
                f,
                w.span,
                format!("H{v}: tool lengths come from the correction table, entries 0..99"),
                "HAAS allows registers up to 200; this controller's table (TAB0.KOR) ends at 99",
            )),
            'D' if v > 200.0 => diags.push(err(
                codes::OUT_OF_RANGE,
                f,
                w.span,
                format!("D{v}: offset registers are D0..D200"),
                "D0..D200",
            )),
            _ => {}
        }
        if w.addr != 'G' && w.addr != 'M' && seen.insert(w.addr, ()).is_some() {
            diags.push(err(
                codes::DUPLICATE_ADDRESS,
                f,
                w.span,
                format!("address {} appears twice in the block", w.addr),
                "each address once per block",
            ));
        }
    }
    let p = b.word('P').and_then(|w| lit(&w.val)).map(|v| v as u32);
    let g43 = b
        .words
        .iter()
        .any(|w| w.addr == 'G' && lit(&w.val).is_some_and(|g| g == 43.0 || g == 44.0));
    if g43 && !lathe && b.word('H').is_none() {
        diags.push(err(
            codes::G43_WITHOUT_H,
            f,
            b.span,
            "G43/G44 without H",
            "write the length register with it: G43 H01 Z2.",
        ));
    }
    let arc = b
        .words
        .iter()
        .any(|w| w.addr == 'G' && lit(&w.val).is_some_and(|g| g == 2.0 || g == 3.0));
    let comp = b
        .words
        .iter()
        .any(|w| w.addr == 'G' && lit(&w.val).is_some_and(|g| g == 40.0 || g == 41.0 || g == 42.0));
    if arc && comp {
        diags.push(err(
            codes::COMP_ON_ARC,
            f,
            b.span,
            "cutter compensation G41/G42/G40 in a circular block",
            "switch compensation on or off on a G01/G00 line",
        ));
    }
    let mut out = Vec::new();
    for m in m_calls {
        match (m, p) {
            (97 | 98, None) => diags.push(err(
                codes::MISSING_L,
                f,
                b.span,
                format!("M{m} needs P"),
                "M97 P<line number>, M98 P<program number>",
            )),
            (97 | 98, _) => out.push((m, p)),
            _ => {}
        }
    }
    out
}

pub use crate::fanuc_exec::plan;
