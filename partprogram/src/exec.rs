//! The MEFI executor: runs a compiled [`Program`] block by block and emits canonical blocks.
//!
//! Order inside one block (parameters-cycles spec §10): substitute `<addr>R<n>` with the parameter
//! values from before the block; apply the block's declarations; run G26–G29 (native code or the
//! reference interpreter); update modal state; move; run the active fixed cycle; transfer control
//! (G71/G72 calls, G73/`GR<n>` jumps, G70 return, M02/M30 end).

use std::collections::HashMap;

use crate::arith::{ArithError, ArithState, NPARAM};
use crate::ast::Val;
use crate::canon::{Canon, Kind, MFunc, Plane};
use crate::codes;
use crate::geom::{Geometry, Target};
use crate::groups::mefi_m_group;
use crate::lexer::Lit;
use crate::program::{CBlock, Program, UnitKind};
pub use crate::run::{Backend, Plan, PlanOptions, RunError};

/// Modal state that fixed cycles save and restore.
#[derive(Debug, Clone)]
pub(crate) struct Modal {
    pub motion: u16,
    pub plane: Plane,
    pub abs: bool,
    pub offset: usize,
    pub feed_mode: u16,
    pub comp: u16,
    pub cycle: Option<u16>,
    pub feed: Option<f64>,
    pub per_rev: bool,
    pub s: Option<f64>,
    pub t: Option<i64>,
    pub d: i64,
    pub amp: i64,
    /// Helix on (G09) until G98.
    pub helix: bool,
    /// Helix lift (G10): towed axis index and travel per full circle.
    pub lift: Option<(usize, f64)>,
    /// Thread lead (G33), mm per revolution.
    pub lead: Option<f64>,
}

#[derive(Debug)]
struct Snapshot {
    r: [i64; NPARAM],
    modal: Modal,
    m_groups: [u16; 15],
    g_groups: [u16; 12],
    s_t_d: [i64; 3],
}

#[derive(Debug)]
struct Frame {
    unit: usize,
    pc: usize,
    counters: HashMap<usize, i64>,
    repeat: i64,
    cycle: Option<Box<Snapshot>>,
}

/// Raw substituted value of a word.
#[derive(Debug, Clone, Copy)]
enum V {
    Lit(Lit),
    R(i64),
}

impl V {
    /// Dimension in mm (literal as written, parameter r µm).
    fn mm(self) -> f64 {
        match self {
            V::Lit(l) => l.value(),
            V::R(r) => r as f64 / 1000.0,
        }
    }
    /// Count (literal integer part, parameter r).
    fn count(self) -> i64 {
        match self {
            V::Lit(l) => l.milli / 1000,
            V::R(r) => r,
        }
    }
}

/// The executor.
pub struct Exec<'p> {
    prog: &'p Program,
    opts: PlanOptions,
    pub(crate) st: Box<ArithState>,
    pub(crate) modal: Modal,
    pub(crate) geo: Geometry,
    frames: Vec<Frame>,
    out: Vec<Canon>,
    executed: u64,
    ended: bool,
}

fn run_err(b: &CBlock, code: u32, message: impl Into<String>) -> RunError {
    RunError {
        code,
        message: message.into(),
        file: b.file,
        span: b.span,
    }
}

fn arith_err(b: &CBlock, e: ArithError) -> RunError {
    let code = match e {
        ArithError::BadOp(_) => codes::RUN_BAD_OP,
        _ => codes::RUN_ARITH,
    };
    run_err(b, code, format!("parameter arithmetic: {e}"))
}

/// Plans `prog`: runs it and returns its canonical blocks.
pub fn plan(prog: &Program, opts: PlanOptions) -> Result<Plan, (Vec<Canon>, RunError)> {
    let mut ex = Exec::new(prog, opts);
    match ex.run() {
        Ok(()) => Ok(Plan {
            blocks: ex.out,
            params: ex.st.r,
            executed: ex.executed,
            messages: std::mem::take(&mut ex.st.messages),
        }),
        Err(e) => Err((ex.out, e)),
    }
}

impl<'p> Exec<'p> {
    /// A fresh executor at program start (priority block state).
    pub fn new(prog: &'p Program, opts: PlanOptions) -> Self {
        let m = &prog.machine;
        let plane = match m.default_plane {
            18 => Plane::ZX,
            19 => Plane::YZ,
            _ => Plane::XY,
        };
        let mut st = Box::<ArithState>::default();
        st.double = m.double_precision;
        st.g_groups[1] = match plane {
            Plane::XY => 17,
            Plane::ZX => 18,
            Plane::YZ => 19,
        };
        Exec {
            prog,
            opts,
            st,
            modal: Modal {
                motion: 1,
                plane,
                abs: true,
                offset: 0,
                feed_mode: 94,
                comp: 40,
                cycle: None,
                feed: None,
                per_rev: false,
                s: None,
                t: None,
                d: 0,
                amp: 0,
                helix: false,
                lift: None,
                lead: None,
            },
            geo: Geometry::new(&m.axes(), m.diameter_x),
            frames: vec![Frame {
                unit: 0,
                pc: prog.units.first().map_or(0, |u| u.start),
                counters: HashMap::new(),
                repeat: 1,
                cycle: None,
            }],
            out: Vec::new(),
            executed: 0,
            ended: false,
        }
    }

    /// The parameter table.
    pub fn params(&self) -> &[i64; NPARAM] {
        &self.st.r
    }

    fn run(&mut self) -> Result<(), RunError> {
        if self.prog.units.is_empty() {
            return Ok(());
        }
        while !self.ended {
            let Some(fr) = self.frames.last_mut() else {
                break;
            };
            let unit = &self.prog.units[fr.unit];
            if fr.pc >= unit.end {
                if unit.kind == UnitKind::Main {
                    break;
                }
                let bi = unit.end.saturating_sub(1);
                self.ret(bi)?;
                continue;
            }
            let bi = fr.pc;
            fr.pc += 1;
            self.executed += 1;
            if self.executed > self.opts.max_blocks {
                return Err(run_err(
                    &self.prog.blocks[bi],
                    codes::RUN_LIMIT,
                    format!(
                        "more than {} blocks executed: endless loop?",
                        self.opts.max_blocks
                    ),
                ));
            }
            self.block(bi)?;
        }
        Ok(())
    }

    fn unit_label(&self) -> Option<String> {
        let fr = self.frames.last()?;
        let u = &self.prog.units[fr.unit];
        match u.kind {
            UnitKind::Main => None,
            UnitKind::Sub => Some(format!("sub{}", u.l)),
            UnitKind::Library => Some(format!("L{}", u.l)),
        }
    }

    fn call(
        &mut self,
        b: &CBlock,
        unit: usize,
        repeat: i64,
        cycle: Option<Box<Snapshot>>,
    ) -> Result<(), RunError> {
        if self.frames.len() >= 64 {
            return Err(run_err(
                b,
                codes::RUN_LIMIT,
                "calls nested deeper than 64 levels",
            ));
        }
        let start = self.prog.units[unit].start;
        self.frames.push(Frame {
            unit,
            pc: start,
            counters: HashMap::new(),
            repeat,
            cycle,
        });
        Ok(())
    }

    fn ret(&mut self, bi: usize) -> Result<(), RunError> {
        let Some(fr) = self.frames.last_mut() else {
            return Ok(());
        };
        if self.prog.units[fr.unit].kind == UnitKind::Main {
            let b = &self.prog.blocks[bi];
            return Err(run_err(b, codes::RUN_TARGET, "G70 in the main program"));
        }
        if fr.repeat > 1 {
            fr.repeat -= 1;
            fr.pc = self.prog.units[fr.unit].start;
            fr.counters.clear();
            return Ok(());
        }
        if let Some(fr) = self.frames.pop() {
            if let Some(s) = fr.cycle {
                self.st.r = s.r;
                self.modal = s.modal;
                self.st.m_groups = s.m_groups;
                self.st.g_groups = s.g_groups;
                self.st.s_t_d = s.s_t_d;
            }
        }
        Ok(())
    }

    fn run_arith(&mut self, b: &CBlock, ops: u8, literal: bool) -> Result<(), RunError> {
        if literal && self.opts.backend == Backend::Native {
            if let (Some(fi), Some(native)) = (b.native, self.prog.native.as_ref()) {
                let rc = native.call(fi, &mut self.st);
                return if rc == 0 {
                    Ok(())
                } else {
                    Err(arith_err(b, ArithError::from_code(rc)))
                };
            }
        }
        let words: Vec<i64> = self.st.r[5..5 + usize::from(ops)].to_vec();
        self.st.exec_seq(&words).map_err(|e| arith_err(b, e))
    }

    #[allow(clippy::too_many_lines)]
    fn block(&mut self, bi: usize) -> Result<(), RunError> {
        let prog = self.prog;
        let b = &prog.blocks[bi];
        if b.skip && self.opts.block_skip {
            return Ok(());
        }
        // 1. Substitution with the parameter values from before the block.
        let mut gs: Vec<(u16, bool)> = Vec::with_capacity(4);
        let mut ms: Vec<u16> = Vec::new();
        let naxes = self.geo.axes.len();
        let mut axes: [Option<f64>; 6] = [None; 6];
        let mut ijk: [Option<f64>; 3] = [None; 3];
        let (mut f, mut s, mut t, mut d, mut l, mut q, mut amp) =
            (None, None, None, None, None, None, None);
        for w in &b.words {
            let v = match w.val {
                Val::Lit(l) => V::Lit(l),
                Val::Param(p) => V::R(self.st.r[(p.int as usize).min(NPARAM - 1)]),
            };
            match w.addr {
                'G' => {
                    let g = v.count();
                    if !(0..=99).contains(&g) {
                        return Err(run_err(
                            b,
                            codes::RUN_RANGE,
                            format!(
                                "G{g}: a two-decade address cannot take a value with more than 2 decades"
                            ),
                        ));
                    }
                    gs.push((g as u16, matches!(v, V::Lit(_))));
                }
                'M' => {
                    let m = v.count();
                    if !(0..=99).contains(&m) {
                        return Err(run_err(
                            b,
                            codes::RUN_RANGE,
                            format!(
                                "M{m}: a two-decade address cannot take a value with more than 2 decades"
                            ),
                        ));
                    }
                    ms.push(m as u16);
                }
                'I' => ijk[0] = Some(v.mm()),
                'J' => ijk[1] = Some(v.mm()),
                'K' => ijk[2] = Some(v.mm()),
                'F' => f = Some(v),
                'S' => s = Some(v.count()),
                'T' => t = Some(v.count()),
                'D' => d = Some(v.count()),
                'L' => l = Some(v.count()),
                'Q' => q = Some(v.count()),
                '&' => amp = Some(v.count()),
                'H' | 'P' | 'E' => {}
                a => {
                    if let Some(i) = self.geo.axes.iter().position(|c| *c == a) {
                        if i < naxes {
                            axes[i] = Some(v.mm());
                        }
                    }
                }
            }
        }
        // 2. Declarations.
        for dcl in &b.decls {
            self.st.r[usize::from(dcl.param)] = dcl.r;
        }
        // 3. Arithmetic.
        if let Some(&(g, lit)) = gs.iter().find(|(g, _)| (26..=29).contains(g)) {
            self.run_arith(b, (g - 25) as u8, lit)?;
        }
        // 4. Modal G functions.
        let mut block_offset = None;
        let (mut dwell, mut g92, mut g93, mut transform, mut g30) =
            (false, false, false, None, false);
        let mut lift = false;
        let mut flow: Option<u16> = None;
        let mut cycle_start = false;
        let mut cancel_cycle = false;
        for &(g, _) in &gs {
            match g {
                0..=3 | 33 => self.modal.motion = g,
                30 => g30 = true,
                17 => self.modal.plane = Plane::XY,
                18 => self.modal.plane = Plane::ZX,
                19 => self.modal.plane = Plane::YZ,
                40..=42 => self.modal.comp = g,
                53..=57 => {
                    self.modal.offset = usize::from(g - 53);
                    self.geo.select_offset(&self.st, self.modal.offset);
                }
                58 | 59 => block_offset = Some(usize::from(g - 53)),
                94..=97 => self.modal.feed_mode = g,
                80 => {
                    self.modal.cycle = None;
                    cancel_cycle = true;
                }
                81..=89 => {
                    self.modal.cycle = Some(g);
                    cycle_start = true;
                }
                90 => self.modal.abs = true,
                91 => self.modal.abs = false,
                74 => {
                    self.geo.diameter =
                        prog.machine.diameter_x || self.geo.axes.first() == Some(&'X')
                }
                75 => self.geo.diameter = false,
                4 => dwell = true,
                92 => g92 = true,
                93 => g93 = true,
                34..=37 => transform = Some(g),
                70 | 71 | 72 | 73 | 78 | 79 => flow = Some(g),
                9 => self.modal.helix = true,
                98 => self.modal.helix = false,
                10 => lift = true,
                26..=29 | 5..=7 | 23 | 24 | 14..=16 => {}
                g => {
                    return Err(run_err(
                        b,
                        codes::RUN_BAD_G,
                        format!("G{g:02} is not a MEFI G function"),
                    ));
                }
            }
        }
        let _ = cycle_start;
        self.sync_groups(&gs);
        // 5. Technological words.
        if let (Some(v), 33) = (f, self.modal.motion) {
            // Thread lead in mm/rev: with a point mm, without a point µm (as G95), a parameter r µm.
            self.modal.lead = Some(match v {
                V::Lit(l) if l.point => l.value(),
                V::Lit(l) => l.value() / 1000.0,
                V::R(r) => r as f64 / 1000.0,
            });
        } else if let Some(v) = f {
            let per_rev = matches!(self.modal.feed_mode, 95 | 97);
            let value = match (v, per_rev) {
                (V::Lit(l), false) => {
                    if l.point {
                        l.value() * 1000.0
                    } else {
                        l.value()
                    }
                }
                (V::Lit(l), true) => {
                    if l.point {
                        l.value()
                    } else {
                        l.value() / 1000.0
                    }
                }
                (V::R(r), false) => r as f64,
                (V::R(r), true) => r as f64 / 1000.0,
            };
            self.modal.feed = Some(value);
            self.modal.per_rev = per_rev;
        }
        if let Some(s) = s {
            if !(0..=9999).contains(&s) {
                return Err(run_err(
                    b,
                    codes::RUN_RANGE,
                    format!("S{s} out of range 0..9999"),
                ));
            }
            self.modal.s = Some(s as f64);
            self.st.s_t_d[0] = s;
        }
        if let Some(t) = t {
            self.modal.t = Some(t);
            self.st.s_t_d[1] = t;
        }
        if let Some(d) = d {
            self.modal.d = d;
            self.st.s_t_d[2] = d;
        }
        if let Some(a) = amp {
            self.modal.amp = a;
        }
        let mut mfuncs: Vec<MFunc> = Vec::with_capacity(ms.len());
        let mut end_program = false;
        for &m in &ms {
            let grp = usize::from(mefi_m_group(m));
            if grp < self.st.m_groups.len() {
                self.st.m_groups[grp] = m;
            }
            if m == 2 || m == 30 {
                end_program = true;
            }
            let before = match prog.machine.m_timing(m) {
                Some(tm) => tm.before_motion(),
                None => matches!(m, 3 | 4 | 7 | 8 | 17 | 41..=44 | 50..=52),
            };
            mfuncs.push(MFunc { m, before });
        }
        mfuncs.sort_by_key(|m| !m.before);
        // 6. Tables, transformations, motion.
        let any_axis = axes.iter().any(Option::is_some);
        let mut moved = false;
        if g92 {
            if d.is_some() {
                let e = usize::try_from(self.modal.d).unwrap_or(0).min(99);
                for dcl in b.decls.iter().filter(|x| x.param <= 4) {
                    self.st.corrections[e][usize::from(dcl.param)] = dcl.r as f64 / 1000.0;
                }
            } else {
                let k = block_offset.unwrap_or(self.modal.offset);
                for (i, v) in axes.iter().enumerate() {
                    if let Some(v) = v {
                        self.st.offsets[k][i] = *v;
                    }
                }
                self.geo.select_offset(&self.st, self.modal.offset);
            }
        } else if g93 {
            let k = block_offset.unwrap_or(self.modal.offset);
            for (i, v) in axes.iter().enumerate() {
                if let Some(v) = v {
                    self.st.offsets[k][i] = self.geo.machine[i] - v;
                }
            }
            self.geo.select_offset(&self.st, self.modal.offset);
        } else if lift {
            if let Some(i) = axes.iter().position(Option::is_some) {
                self.modal.lift = axes[i].map(|v| (i, v));
            }
        } else if let Some(g) = transform {
            self.geo.set_transform(g, &axes);
        } else if g30 {
            let mut target = self.geo.machine;
            for (i, v) in axes.iter().enumerate() {
                if v.is_some() {
                    target[i] = 0.0;
                }
            }
            self.geo.move_machine(target, &self.st, self.modal.offset);
            self.emit(b, Kind::Rapid, Vec::new(), None, &mfuncs, false);
            moved = true;
        } else if any_axis
            || (matches!(self.modal.motion, 2 | 3) && ijk.iter().any(Option::is_some))
        {
            let offset = block_offset.unwrap_or(self.modal.offset);
            let tgt = Target {
                axes,
                ijk,
                abs: self.modal.abs,
                offset,
            };
            let motion = self.modal.motion;
            match motion {
                2 | 3 => {
                    let arc = self
                        .geo
                        .arc(
                            &tgt,
                            self.modal.plane,
                            &self.st,
                            prog.machine.circle_tolerance,
                        )
                        .map_err(|m| run_err(b, codes::RUN_CIRCLE, m))?;
                    let cw = (motion == 2) != arc.mirrored;
                    if let (true, Some((i, l))) = (self.modal.helix, self.modal.lift) {
                        let sweep = if motion == 2 {
                            arc.sweep_cw
                        } else {
                            std::f64::consts::TAU - arc.sweep_cw
                        };
                        let sweep = if sweep < 1e-9 || sweep > std::f64::consts::TAU - 1e-9 {
                            std::f64::consts::TAU
                        } else {
                            sweep
                        };
                        self.geo.tow(i, l * sweep / std::f64::consts::TAU);
                    }
                    self.emit(
                        b,
                        if cw { Kind::ArcCw } else { Kind::ArcCcw },
                        arc.center,
                        self.feed(),
                        &mfuncs,
                        false,
                    );
                }
                0 => {
                    self.geo.linear(&tgt, &self.st);
                    self.emit(b, Kind::Rapid, Vec::new(), None, &mfuncs, false);
                }
                _ => {
                    self.geo.linear(&tgt, &self.st);
                    let feed = if motion == 33 {
                        self.modal.lead.zip(self.modal.s).map(|(l, s)| l * s)
                    } else {
                        self.feed()
                    };
                    self.emit(b, Kind::Linear, Vec::new(), feed, &mfuncs, motion == 33);
                }
            }
            moved = true;
        }
        self.geo.export_programmed(&mut self.st);
        let count_q = if dwell { 1 } else { q.unwrap_or(1) };
        if dwell {
            let secs = q.unwrap_or(0) as f64 * 0.01;
            let m = if moved {
                Vec::new()
            } else {
                std::mem::take(&mut mfuncs)
            };
            self.emit_dwell(b, secs, &m);
            moved = true;
        }
        if !moved && (!mfuncs.is_empty() || s.is_some() || t.is_some()) {
            self.emit(b, Kind::Aux, Vec::new(), None, &mfuncs, false);
        }
        let active_cycle = if cancel_cycle { None } else { self.modal.cycle };
        // 7. Program flow at the end of the block.
        match flow {
            Some(71) | Some(72) => {
                let Some(lv) = l else {
                    return Err(run_err(b, codes::RUN_TARGET, "call without L"));
                };
                let map = if flow == Some(71) {
                    &prog.subs
                } else {
                    &prog.library
                };
                let unit = *map.get(&(lv as u32)).ok_or_else(|| {
                    run_err(b, codes::RUN_TARGET, format!("unit L{lv} does not exist"))
                })?;
                if count_q > 0 {
                    self.call(b, unit, count_q, None)?;
                }
            }
            Some(73) => self.jump(b, bi, l, count_q)?,
            Some(70) => {
                if !self
                    .frames
                    .last()
                    .is_some_and(|f| prog.units[f.unit].kind == UnitKind::Main)
                {
                    self.ret(bi)?;
                }
            }
            _ => {}
        }
        if end_program && self.frames.len() == 1 {
            self.ended = true;
        }
        // 8. The active fixed cycle runs after the motion of the block (before the flow takes effect,
        //    which is already recorded in the frames below it).
        if let Some(c) = active_cycle {
            {
                let unit = *prog.library.get(&u32::from(c)).ok_or_else(|| {
                    run_err(
                        b,
                        codes::RUN_TARGET,
                        format!("fixed cycle G{c} has no unit L{c}"),
                    )
                })?;
                let snap = Box::new(Snapshot {
                    r: self.st.r,
                    modal: self.modal.clone(),
                    m_groups: self.st.m_groups,
                    g_groups: self.st.g_groups,
                    s_t_d: self.st.s_t_d,
                });
                self.modal.cycle = None;
                let was_ended = self.ended;
                self.ended = false;
                self.call(b, unit, 1, Some(snap))?;
                if was_ended {
                    // Run the cycle, then stop: the main frame has nothing left.
                    if let Some(main) = self.frames.first_mut() {
                        main.pc = prog.units[main.unit].end;
                    }
                }
            }
        }
        Ok(())
    }

    fn jump(&mut self, b: &CBlock, bi: usize, l: Option<i64>, q: i64) -> Result<(), RunError> {
        let Some(lv) = l else {
            return Err(run_err(b, codes::RUN_TARGET, "G73 without L"));
        };
        let unit = &self.prog.units[b.unit];
        let target = *unit.index.get(&(lv as u32)).ok_or_else(|| {
            run_err(
                b,
                codes::RUN_TARGET,
                format!("jump to N{lv}, which is not in this program unit"),
            )
        })?;
        let Some(fr) = self.frames.last_mut() else {
            return Ok(());
        };
        let take = match fr.counters.get(&bi).copied() {
            None => {
                if q > 0 {
                    fr.counters.insert(bi, q - 1);
                    true
                } else {
                    false
                }
            }
            Some(0) => {
                fr.counters.remove(&bi);
                false
            }
            Some(k) => {
                fr.counters.insert(bi, k - 1);
                true
            }
        };
        if take {
            fr.pc = target;
        }
        Ok(())
    }

    fn sync_groups(&mut self, gs: &[(u16, bool)]) {
        for &(g, _) in gs {
            if let Some(grp) = crate::groups::mefi_g_group(g) {
                if let Some(slot) = self.st.g_groups.get_mut(usize::from(grp)) {
                    *slot = g;
                }
            }
        }
    }

    fn feed(&self) -> Option<f64> {
        let f = self.modal.feed?;
        if self.modal.per_rev {
            self.modal.s.map(|s| f * s)
        } else {
            Some(f)
        }
    }

    fn emit(
        &mut self,
        b: &CBlock,
        kind: Kind,
        center: Vec<(char, f64)>,
        feed: Option<f64>,
        m: &[MFunc],
        thread: bool,
    ) {
        if !self.opts.record {
            return;
        }
        let c = Canon {
            n: b.n,
            unit: self.unit_label(),
            kind,
            end: self.geo.end_list(),
            center,
            plane: self.modal.plane,
            feed,
            m: m.to_vec(),
            s: self.modal.s,
            t: self.modal.t,
            dwell: None,
            thread,
        };
        self.out.push(c);
    }

    fn emit_dwell(&mut self, b: &CBlock, secs: f64, m: &[MFunc]) {
        if !self.opts.record {
            return;
        }
        let c = Canon {
            n: b.n,
            unit: self.unit_label(),
            kind: Kind::Dwell,
            end: self.geo.end_list(),
            center: Vec::new(),
            plane: self.modal.plane,
            feed: None,
            m: m.to_vec(),
            s: self.modal.s,
            t: self.modal.t,
            dwell: Some(secs),
            thread: false,
        };
        self.out.push(c);
    }
}
