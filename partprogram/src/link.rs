//! Linking: resolves literal jump and call targets, detects unbounded recursion in the static call
//! graph and checks the M functions of every reachable unit against IOCFIL section 2.

use diag::Sink;

use crate::ast::Val;
use crate::codes;
use crate::program::{Program, UnitKind, err, lit_int};

/// Resolves literal jump and call targets and detects recursion.
pub(crate) fn link(prog: &mut Program, diags: &mut Sink) {
    let mut edges: Vec<Vec<(usize, usize)>> = vec![Vec::new(); prog.units.len()];
    for (bi, b) in prog.blocks.iter().enumerate() {
        let f = &prog.files[b.file];
        let (file, src) = (f.name.as_str(), f.text.as_str());
        let unit = &prog.units[b.unit];
        let l = b.word('L').and_then(|w| {
            if let Val::Lit(l) = w.val {
                lit_int(&l)
            } else {
                None
            }
        });
        let gs: Vec<Option<i64>> = b
            .words
            .iter()
            .filter(|w| w.addr == 'G')
            .map(|w| {
                if let Val::Lit(l) = w.val {
                    lit_int(&l)
                } else {
                    None
                }
            })
            .collect();
        let dyn_g = gs.iter().any(Option::is_none);
        if let Some(l) = l {
            let l32 = l as u32;
            if (gs.contains(&Some(73))
                || (dyn_g
                    && !gs
                        .iter()
                        .any(|g| matches!(g, Some(71) | Some(72) | Some(79)))))
                && !unit.index.contains_key(&l32)
            {
                diags.push(err(
                    codes::MISSING_BLOCK,
                    file,
                    src,
                    b.span,
                    format!("jump to N{l}, which is not in this program unit"),
                    "jumps go to a block of the same main program, subprogram or macro",
                ));
            }
            if gs.contains(&Some(71)) {
                match prog.subs.get(&l32) {
                    Some(&u) => edges[b.unit].push((u, bi)),
                    None => diags.push(err(
                        codes::MISSING_SUBPROGRAM,
                        file,
                        src,
                        b.span,
                        format!("subprogram L{l} does not exist in this file"),
                        "subprograms follow M02/M30 as `G79 L<n>` … `G70`",
                    )),
                }
            }
            if gs.contains(&Some(72)) {
                match prog.library.get(&l32) {
                    Some(&u) => edges[b.unit].push((u, bi)),
                    None => diags.push(err(
                        codes::MISSING_MACRO,
                        file,
                        src,
                        b.span,
                        format!("macro L{l} is not in the machine's macro folder"),
                        "store the macro as file L<n> in the macro folder",
                    )),
                }
            }
        }
        for g in gs.iter().flatten() {
            if (81..=89).contains(g) {
                match prog.library.get(&(*g as u32)) {
                    Some(&u) => edges[b.unit].push((u, bi)),
                    None => diags.push(err(codes::MISSING_MACRO, file, src, b.span, format!("fixed cycle G{g} has no unit L{g} in the macro folder"), "ship the fixed cycles as units G79 L81 … G70 in the machine's macro folder")),
                }
            }
        }
    }
    // Recursion: a cycle in the static call graph never terminates.
    let n = prog.units.len();
    let mut state = vec![0u8; n];
    fn dfs(u: usize, edges: &[Vec<(usize, usize)>], state: &mut [u8], hit: &mut Vec<usize>) {
        state[u] = 1;
        for &(v, bi) in &edges[u] {
            if state[v] == 1 {
                hit.push(bi);
            } else if state[v] == 0 {
                dfs(v, edges, state, hit);
            }
        }
        state[u] = 2;
    }
    let mut hits = Vec::new();
    for u in 0..n {
        if state[u] == 0 {
            dfs(u, &edges, &mut state, &mut hits);
        }
    }
    // M functions must be declared in IOCFIL section 2: checked in the main file and in every library
    // unit the program reaches through literal calls (computed calls cannot be followed statically).
    if prog.machine.check_m_declared {
        let mut reach = vec![false; n];
        let mut stack: Vec<usize> = (0..n)
            .filter(|&u| prog.units[u].kind != UnitKind::Library)
            .collect();
        while let Some(u) = stack.pop() {
            if std::mem::replace(&mut reach[u], true) {
                continue;
            }
            stack.extend(edges[u].iter().map(|e| e.0));
        }
        for b in &prog.blocks {
            if !reach[b.unit] {
                continue;
            }
            let f = &prog.files[b.file];
            for w in b.words.iter().filter(|w| w.addr == 'M') {
                if let Val::Lit(l) = w.val
                    && let Some(mv) = lit_int(&l).filter(|v| (0..=99).contains(v))
                    && prog.machine.m_timing(mv as u16).is_none()
                {
                    diags.push(err(codes::UNDECLARED_M, &f.name, &f.text, w.span, format!("M{mv:02} is not declared for process 1 in IOCFIL section 2"), "declare it as `Mxx=m_type,m_request,class` in IOCFIL section 2, or do not use it"));
                }
            }
        }
    }
    hits.sort_unstable();
    hits.dedup();
    for bi in hits {
        let b = &prog.blocks[bi];
        let f = &prog.files[b.file];
        diags.push(err(
            codes::RECURSION,
            &f.name,
            &f.text,
            b.span,
            "this call leads back to its own unit: unbounded recursion",
            "a subprogram or macro must not call itself directly or through other calls",
        ));
    }
}
