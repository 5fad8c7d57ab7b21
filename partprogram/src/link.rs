//! Linking: resolves literal jump and call targets, detects unbounded recursion in the static call
//! graph and checks the M functions of every reachable unit against IOCFIL section 2.
//!
//! It works on what [`crate::units`] kept of each block while building ([`LinkRef`]s, the block
//! numbers of each unit, the undeclared M functions of library blocks), not on the blocks, so a
//! rejected program is linked without keeping its blocks.

use diag::Diagnostic;

use crate::ast::Val;
use crate::codes;
use crate::program::{CBlock, Program, UnitKind, err, lit_int};
use crate::units::Units;

/// What linking needs of a block with a literal `L` or a fixed cycle G81–G89.
pub(crate) struct LinkRef {
    unit: usize,
    file: usize,
    span: (usize, usize),
    /// The literal `L`.
    l: Option<i64>,
    /// `L` is a jump target in the unit (G73, or a computed G without G71/G72/G79).
    jump: bool,
    /// G71: `L` is a subprogram.
    sub: bool,
    /// G72: `L` is a library unit.
    macro_call: bool,
    /// The fixed cycles G81–G89 written, in order.
    cycles: Vec<u8>,
}

impl LinkRef {
    /// What `b` asks of linking, when anything.
    pub(crate) fn of(b: &CBlock) -> Option<LinkRef> {
        let l = b.word('L').and_then(|w| {
            if let Val::Lit(l) = w.val {
                lit_int(&l)
            } else {
                None
            }
        });
        let gs = b.words.iter().filter(|w| w.addr == 'G').map(|w| {
            if let Val::Lit(l) = w.val {
                lit_int(&l)
            } else {
                None
            }
        });
        let cycles: Vec<u8> = gs
            .clone()
            .flatten()
            .filter(|g| (81..=89).contains(g))
            .map(|g| g as u8)
            .collect();
        if l.is_none() && cycles.is_empty() {
            return None;
        }
        let has = |g: i64| gs.clone().any(|x| x == Some(g));
        let dyn_g = gs.clone().any(|x| x.is_none());
        Some(LinkRef {
            unit: b.unit,
            file: b.file,
            span: b.span,
            l,
            jump: has(73) || (dyn_g && !(has(71) || has(72) || has(79))),
            sub: has(71),
            macro_call: has(72),
            cycles,
        })
    }
}

impl LinkRef {
    /// Drops the jump check when the target is among `numbers` (the block numbers of the unit).
    pub(crate) fn resolve_jump(&mut self, numbers: &roaring::RoaringBitmap) {
        if let Some(l) = self.l
            && self.jump
            && numbers.contains(l as u32)
        {
            self.jump = false;
        }
    }

    /// The block number a jump of the block still waits for, if any.
    pub(crate) fn jump_target(&self) -> Option<u32> {
        self.l
            .filter(|_| self.jump)
            .and_then(|l| u32::try_from(l).ok())
    }

    /// True while linking has something to do with the block.
    pub(crate) fn pending(&self) -> bool {
        self.jump || self.sub || self.macro_call || !self.cycles.is_empty()
    }
}

/// The undeclared M functions of `b` (when the machine checks them), as diagnostics.
pub(crate) fn undeclared_m(prog: &Program, b: &CBlock) -> Vec<Diagnostic> {
    let f = &prog.files[b.file];
    b.words
        .iter()
        .filter(|w| w.addr == 'M')
        .filter_map(|w| {
            if let Val::Lit(l) = w.val
                && let Some(mv) = lit_int(&l).filter(|v| (0..=99).contains(v))
                && prog.machine.m_timing(mv as u16).is_none()
            {
                Some(err(codes::UNDECLARED_M, &f.name, "", w.span, format!("M{mv:02} is not declared for process 1 in IOCFIL section 2"), "declare it as `Mxx=m_type,m_request,class` in IOCFIL section 2, or do not use it"))
            } else {
                None
            }
        })
        .collect()
}

/// Resolves literal jump and call targets and detects recursion.
pub(crate) fn link(prog: &Program, units: &mut Units) {
    let refs = units.take_refs();
    let diags = &mut units.table.phases.link;
    // Per unit, the calls out of it: (callee, index of the calling LinkRef).
    let mut edges: Vec<Vec<(usize, usize)>> = vec![Vec::new(); prog.units.len()];
    for (ri, r) in refs.iter().enumerate() {
        let file = prog.files[r.file].name.as_str();
        if let Some(l) = r.l {
            let l32 = l as u32;
            if r.jump && !units.table.numbers[r.unit].contains(l32) {
                diags.push(err(
                    codes::MISSING_BLOCK,
                    file,
                    "",
                    r.span,
                    format!("jump to N{l}, which is not in this program unit"),
                    "jumps go to a block of the same main program, subprogram or macro",
                ));
            }
            if r.sub {
                match prog.subs.get(&l32) {
                    Some(&u) => edges[r.unit].push((u, ri)),
                    None => diags.push(err(
                        codes::MISSING_SUBPROGRAM,
                        file,
                        "",
                        r.span,
                        format!("subprogram L{l} does not exist in this file"),
                        "subprograms follow M02/M30 as `G79 L<n>` … `G70`",
                    )),
                }
            }
            if r.macro_call {
                match prog.library.get(&l32) {
                    Some(&u) => edges[r.unit].push((u, ri)),
                    None => diags.push(err(
                        codes::MISSING_MACRO,
                        file,
                        "",
                        r.span,
                        format!("macro L{l} is not in the machine's macro folder"),
                        "store the macro as file L<n> in the macro folder",
                    )),
                }
            }
        }
        for &g in &r.cycles {
            match prog.library.get(&u32::from(g)) {
                Some(&u) => edges[r.unit].push((u, ri)),
                None => diags.push(err(
                    codes::MISSING_MACRO,
                    file,
                    "",
                    r.span,
                    format!("fixed cycle G{g} has no unit L{g} in the macro folder"),
                    "ship the fixed cycles as units G79 L81 … G70 in the machine's macro folder",
                )),
            }
        }
    }
    // Recursion: a cycle in the static call graph never terminates.
    let n = prog.units.len();
    let mut hits = crate::unit_table::back_edges(&edges);
    // M functions must be declared in IOCFIL section 2: checked in the main file (while building)
    // and in every library unit the program reaches through literal calls (computed calls cannot
    // be followed statically).
    if !units.lib_m.is_empty() {
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
        for m in std::mem::take(&mut units.lib_m) {
            if reach[m.unit] {
                units.table.phases.m.push(m.diagnostic);
            }
        }
    }
    hits.sort_unstable();
    hits.dedup();
    for ri in hits {
        let r = &refs[ri];
        units.table.phases.rec.push(err(
            codes::RECURSION,
            &prog.files[r.file].name,
            "",
            r.span,
            "this call leads back to its own unit: unbounded recursion",
            "a subprogram or macro must not call itself directly or through other calls",
        ));
    }
}
