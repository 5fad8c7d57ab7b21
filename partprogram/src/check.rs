//! Static checks of one MEFI block: addresses, value ranges, G/M groups, L with G71–G79, G79 blocks.

use std::collections::BTreeMap;

use diag::Sink;

use crate::ast::Val;
use crate::codes;
use crate::groups::{mefi_g_group, mefi_m_group};
use crate::machine::MachineSpec;
use crate::program::{CBlock, Program, err, lit_int};

fn is_axis(machine: &MachineSpec, a: char) -> bool {
    machine.axes().contains(&a)
}

/// Static checks of one MEFI block `b` of `prog` (which need not hold it).
pub(crate) fn check_block(prog: &Program, b: &CBlock, diags: &mut Sink) {
    let f = &prog.files[b.file];
    let (file, src) = (f.name.as_str(), f.text.as_str());
    let m = &prog.machine;
    let mut seen: BTreeMap<char, (usize, usize)> = BTreeMap::new();
    let mut ggroups: BTreeMap<u8, i64> = BTreeMap::new();
    let mut mgroups: BTreeMap<u8, i64> = BTreeMap::new();
    let mut axes = 0;
    for w in &b.words {
        let a = w.addr;
        let known = matches!(
            a,
            'G' | 'M' | 'I' | 'J' | 'K' | 'F' | 'S' | 'T' | 'D' | 'L' | 'Q' | 'H' | 'P' | 'E' | '&'
        ) || is_axis(m, a);
        if !known {
            let (code, msg, hint) = if a == 'R' {
                (
                    codes::R_WORD,
                    "`R<n>` without `=`".to_string(),
                    "declare a parameter with `R<n>=<value>`; to use it write `<address>R<n>`",
                )
            } else if "XYZUVWABC".contains(a) {
                (
                    codes::UNKNOWN_ADDRESS,
                    format!("the machine has no axis {a}"),
                    "use the axis letters of the machine (AXCFIL)",
                )
            } else {
                (
                    codes::UNKNOWN_ADDRESS,
                    format!("unknown address `{a}`"),
                    "MEFI addresses: N G M X Y Z U V W A B C I J K R F S T D L Q H P E & /",
                )
            };
            diags.push(err(code, file, src, w.span, msg, hint));
            continue;
        }
        if is_axis(m, a) {
            axes += 1;
        }
        if a != 'G' && a != 'M' && seen.insert(a, w.span).is_some() {
            diags.push(err(
                codes::DUPLICATE_ADDRESS,
                file,
                src,
                w.span,
                format!("address {a} appears twice in the block"),
                "each address may be written once per block (G and M once per group)",
            ));
        }
        if matches!(a, 'H' | 'P' | 'K') {
            let (msg, hint) = if a == 'K' {
                (
                    "K has no meaning in MEFI blocks".to_string(),
                    "circle centres are I (first axis of the plane) and J (second axis)",
                )
            } else {
                (
                    format!(
                        "{a}: the auxiliary functions H and P are not output by this controller"
                    ),
                    "the interface map has no signal that carries H or P to the PLC; use an M function",
                )
            };
            diags.push(err(codes::NO_MEANING, file, src, w.span, msg, hint));
            continue;
        }
        let lit = match w.val {
            Val::Lit(l) => l,
            Val::Expr(_) => continue,
            Val::Param(p) => {
                if p.point || p.signed || !(0..=95).contains(&p.int) {
                    diags.push(err(
                        codes::BAD_PARAMETER,
                        file,
                        src,
                        w.span,
                        "parameter number must be 0..95",
                        "write `<address>R<n>` with n = 0..95",
                    ));
                }
                continue;
            }
        };
        let int = lit_int(&lit);
        let count_range = |lo: i64, hi: i64, what: &str, diags: &mut Sink| match int {
            Some(v) if (lo..=hi).contains(&v) && !lit.negative => Some(v),
            Some(_) => {
                diags.push(err(
                    codes::OUT_OF_RANGE,
                    file,
                    src,
                    w.span,
                    format!("{a} value out of range"),
                    &format!("{what}: {lo}..{hi}"),
                ));
                None
            }
            None => {
                diags.push(err(
                    codes::NOT_INTEGER,
                    file,
                    src,
                    w.span,
                    format!("{a} takes a whole number"),
                    &format!("{what}: {lo}..{hi} without a fraction"),
                ));
                None
            }
        };
        match a {
            'G' => {
                if let Some(g) = count_range(0, 99, "G functions", diags) {
                    if (14..=16).contains(&g)
                        && let Err(msg) = m.plane_341_axes(g as u16)
                    {
                        diags.push(err(
                            codes::PLANE_AXIS,
                            file,
                            src,
                            w.span,
                            msg,
                            "G14–G16 select the planes of machine constant 341 with the 4th axis; use G17–G19 on this machine",
                        ));
                    }
                    match mefi_g_group(g as u16) {
                        Some(grp) => {
                            if let Some(prev) = ggroups.insert(grp, g) {
                                diags.push(err(
                                    codes::GROUP_CONFLICT,
                                    file,
                                    src,
                                    w.span,
                                    format!("G{g:02} and G{prev:02} belong to the same group"),
                                    "one G function per group per block",
                                ));
                            }
                        }
                        None => diags.push(err(
                            codes::UNKNOWN_G,
                            file,
                            src,
                            w.span,
                            format!("G{g:02} is not a MEFI G function"),
                            "see the G groups G0…G11 of the dialect",
                        )),
                    }
                }
            }
            'M' => {
                if let Some(mv) = count_range(0, 99, "M functions", diags) {
                    let grp = mefi_m_group(mv as u16);
                    if grp != 14
                        && let Some(prev) = mgroups.insert(grp, mv)
                    {
                        diags.push(err(
                            codes::GROUP_CONFLICT,
                            file,
                            src,
                            w.span,
                            format!("M{mv:02} and M{prev:02} belong to the same group"),
                            "one M function per group per block",
                        ));
                    }
                }
            }
            'L' | 'Q' => {
                let lo = if a == 'Q' && b.has_g(4) { 0 } else { 1 };
                count_range(
                    lo,
                    9999,
                    if a == 'L' {
                        "L (unit or block number)"
                    } else {
                        "Q"
                    },
                    diags,
                );
            }
            'T' => {
                count_range(0, 99_999_999, "T", diags);
            }
            'S' => {
                count_range(0, 9999, "S", diags);
            }
            'D' => {
                count_range(0, 99, "D", diags);
            }

            '&' => {
                let c = m.length_method == crate::machine::LengthMethod::C;
                if let Some(v) = count_range(
                    0,
                    if c { 1 } else { 2222 },
                    if c {
                        "& under length correction method C"
                    } else {
                        "&"
                    },
                    diags,
                ) && v.to_string().bytes().any(|c| c > b'2')
                {
                    diags.push(err(
                        codes::OUT_OF_RANGE,
                        file,
                        src,
                        w.span,
                        "& digits must be 0, 1 or 2",
                        "each digit of & is 0, 1 or 2",
                    ));
                }
            }
            'E' => {
                if !lit.point {
                    diags.push(err(
                        codes::E_WITHOUT_POINT,
                        file,
                        src,
                        w.span,
                        "E must be written with a decimal point",
                        "write the thread run-in with a point, e.g. E5.0",
                    ));
                }
            }
            'F' => {
                if lit.negative || lit.milli() > 99_999_000 {
                    diags.push(err(
                        codes::OUT_OF_RANGE,
                        file,
                        src,
                        w.span,
                        "F out of range",
                        "feed is positive, at most 99999",
                    ));
                }
            }
            _ => {
                if lit.int_digits() > 5 || lit.frac_digits > 3 {
                    diags.push(err(
                        codes::OUT_OF_RANGE,
                        file,
                        src,
                        w.span,
                        format!("{a} value out of range"),
                        "dimensions have the format ±5.3 (±69999.999)",
                    ));
                }
            }
        }
    }
    if axes > 6 {
        diags.push(err(
            codes::TOO_MANY_AXES,
            file,
            src,
            b.span,
            "more than 6 axis words in a block",
            "at most 6 axes move in one block",
        ));
    }
    let gl: Vec<i64> = b
        .words
        .iter()
        .filter(|w| w.addr == 'G')
        .filter_map(|w| {
            if let Val::Lit(l) = w.val {
                lit_int(&l)
            } else {
                None
            }
        })
        .collect();
    for g in [71, 72, 73, 79] {
        if gl.contains(&g) && b.word('L').is_none() {
            diags.push(err(
                codes::MISSING_L,
                file,
                src,
                b.span,
                format!("G{g} needs the address L in the same block"),
                "write the unit or block number, e.g. `G71 L100`",
            ));
        }
    }
    if (gl.contains(&2) || gl.contains(&3)) && gl.iter().any(|g| (40..=42).contains(g)) {
        diags.push(err(
            codes::COMP_ON_ARC,
            file,
            src,
            b.span,
            "radius compensation G41/G42/G40 in a circular block",
            "switch compensation on or off in a linear block (G01/G00)",
        ));
    }
    if gl.contains(&79) {
        if let Some(w) = b.words.iter().find(|w| {
            !(w.addr == 'L'
                || (w.addr == 'G' && matches!(w.val, Val::Lit(l) if l.milli() == 79_000)))
        }) {
            diags.push(err(
                codes::G79_BLOCK,
                file,
                src,
                w.span,
                "a G79 block holds only N, G79 and L",
                "move other words to the next block",
            ));
        } else if !b.decls.is_empty() {
            diags.push(err(
                codes::G79_BLOCK,
                file,
                src,
                b.span,
                "a G79 block holds only N, G79 and L",
                "move declarations to the next block",
            ));
        }
        if let Some(w) = b.word('L')
            && matches!(w.val, Val::Param(_))
        {
            diags.push(err(
                codes::NOT_PARAMETRISABLE,
                file,
                src,
                w.span,
                "the L of G79 cannot be a parameter",
                "write the unit number literally",
            ));
        }
    }
}
