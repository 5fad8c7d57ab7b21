//! Executor of the Fanuc/HAAS dialect: modal state, work offsets, canned cycles, circular pockets,
//! cylinder interpolation G7.1 and M97/M98/M99 calls, emitting the same canonical blocks as MEFI.

mod arc;
mod comp;
mod cycles;
pub mod macros;
mod offsets;
mod tlo;
mod words;

use crate::ast::Val;
use crate::canon::{Canon, Kind, MFunc, Plane};
use crate::codes;
use crate::exec::{Plan, PlanOptions, RunError};
use crate::program::{CBlock, Program, UnitKind};
use crate::radius::Compensator;

/// Peck retract of G73 and clearance of G83 re-entry (mm); the HAAS text gives no value.
pub const PECK_CLEARANCE: f64 = 0.5;

struct Frame {
    unit: usize,
    pc: usize,
    target: usize,
    repeat: i64,
    /// A `G65` level: the caller's locals and the level's arguments.
    level: Option<Box<macros::MacroLevel>>,
}

struct Ex<'p> {
    prog: &'p Program,
    opts: PlanOptions,
    axes: Vec<char>,
    machine: [f64; 6],
    /// Work offsets: G54–G59, then G154 P1–P99 ([`offsets::WORK_ROWS`]).
    work: Vec<[f64; 6]>,
    wsel: usize,
    local: [f64; 6],
    g92: [f64; 6],
    motion: u16,
    plane: Plane,
    abs: bool,
    inch: bool,
    feed: Option<f64>,
    s: Option<f64>,
    /// G96 constant surface speed (S in m/min, ft/min under G20) until G97.
    css: bool,
    /// G50 S: top spindle speed under G96 (rev/min).
    max_rpm: Option<f64>,
    t: Option<i64>,
    cycle: Option<u16>,
    g99: bool,
    init_z: f64,
    cyc: (f64, f64, f64, f64),
    cyl: Option<f64>,
    diameter: bool,
    /// Active tool length per axis (G43/G44), part of the origin.
    tlo: [f64; 6],
    /// Length changes not yet taken by an incremental move, per axis.
    tlo_due: [f64; 6],
    /// G43 (+1) or G44 (−1) with the plane that fixed the tool axis; None: G49.
    tlo_sign: Option<(f64, Plane)>,
    /// The last H number.
    tlo_h: i64,
    frames: Vec<Frame>,
    out: Vec<Canon>,
    /// Cutter compensation: modal G40/G41/G42, D register, the compensator.
    comp: u16,
    d: i64,
    /// Offset registers 0..=200 (radius, lengths of axes 1..4): 0..=99 from the machine's correction
    /// table, the others zero until `G10 L12` sets a radius.
    corrections: Vec<[f64; 5]>,
    /// Wear of each register (length, radius), 0 until `G10 L11`/`L13` or `#2201`+/`#2601`+ set it;
    /// the active length and radius are geometry + wear.
    wear: Vec<[f64; 2]>,
    rc: Compensator,
    executed: u64,
    ended: bool,
    /// True when the canonical blocks are only checked ([`check`]): `out` is emptied after each
    /// block, so the run holds the look-ahead of the compensation, not the plan.
    discard: bool,
    /// G61 exact stop (modal, group 13) until G64.
    exact_modal: bool,
    /// G09 in the current block.
    exact_once: bool,
    /// `G64 P<tol>` blending tolerance (mm) until G61 or a G64 without P.
    tolerance: Option<f64>,
    /// AI contour control (`G05.1 Q1` or `G08 P1`) until `G05.1 Q0` or `G08 P0`.
    contour: bool,
    /// Macro B variables.
    vars: macros::VarTable,
    /// External work offset (`#5201`+), added to every work system.
    ext: [f64; 6],
    /// The last M code executed (not M97/M98/M99), for `#4113`.
    last_m: Option<u16>,
}

fn run_err(b: &CBlock, code: u32, msg: impl Into<String>) -> RunError {
    RunError {
        code,
        message: msg.into(),
        file: b.file,
        span: b.span,
    }
}

/// Plans a Fanuc/HAAS program.
pub fn plan(prog: &Program, opts: PlanOptions) -> Result<Plan, (Vec<Canon>, RunError)> {
    let mut ex = Ex::new(prog, opts);
    ex.out.reserve_exact(crate::run::plan_capacity(prog, &opts));
    let done = ex.run().and_then(|()| ex.rc.finish(&mut ex.out));
    // Without the spare room of the last doubling (up to as much again): a part run holds its plans.
    ex.out.shrink_to_fit();
    match done {
        Ok(()) => Ok(Plan {
            blocks: ex.out,
            params: [0; 96],
            executed: ex.executed,
            messages: Vec::new(),
            macro_vars: std::mem::take(&mut ex.vars.slots),
        }),
        Err(e) => Err((ex.out, e)),
    }
}

/// Runs `prog` as [`plan`] does, keeping none of its canonical blocks: the run-time error
/// [`plan`] would give, or the number of blocks executed.
pub fn check(prog: &Program, opts: PlanOptions) -> Result<u64, RunError> {
    let mut ex = Ex::new(prog, opts);
    ex.discard = true;
    ex.run().and_then(|()| ex.rc.finish(&mut ex.out))?;
    Ok(ex.executed)
}

impl<'p> Ex<'p> {
    /// A fresh executor at program start, the retained variables loaded.
    fn new(prog: &'p Program, opts: PlanOptions) -> Self {
        let axes = prog.machine.axes();
        let lathe = !axes.contains(&'Y');
        let mut ex = Ex {
            prog,
            opts,
            axes: axes.iter().copied().take(6).collect(),
            machine: opts.start,
            // G54–G59 from the machine's zero-offset table (rows G54..G59 of `TAB0.POS`).
            work: (0..offsets::WORK_ROWS)
                .map(|k| {
                    prog.machine
                        .zero_offsets
                        .rows
                        .get(k + 1)
                        .copied()
                        .unwrap_or([0.0; 6])
                })
                .collect(),
            wsel: 0,
            local: [0.0; 6],
            g92: [0.0; 6],
            motion: 0,
            plane: if lathe { Plane::ZX } else { Plane::XY },
            abs: true,
            inch: false,
            feed: None,
            s: None,
            css: false,
            max_rpm: None,
            t: None,
            cycle: None,
            g99: false,
            init_z: 0.0,
            cyc: (0.0, 0.0, 0.0, 0.0),
            cyl: None,
            diameter: prog.machine.diameter_x,
            tlo: [0.0; 6],
            tlo_due: [0.0; 6],
            tlo_sign: None,
            tlo_h: 0,
            frames: Vec::new(),
            out: Vec::new(),
            comp: 40,
            d: 0,
            corrections: {
                let mut rows = prog.machine.corrections.rows();
                rows.resize(comp::REGISTERS, [0.0; 5]);
                rows
            },
            wear: vec![[0.0; 2]; comp::REGISTERS],
            // Fanuc keeps the programmed feed at the tool centre on compensated arcs (no F·R'/R).
            rc: Compensator::new(crate::radius::RadiusOptions {
                adapt_arc_feed: false,
                ..opts.radius
            }),
            executed: 0,
            ended: false,
            discard: false,
            exact_modal: false,
            exact_once: false,
            tolerance: None,
            contour: false,
            vars: macros::VarTable::default(),
            ext: [0.0; 6],
            last_m: None,
        };
        prog.machine.retained.load_into(&mut ex.vars.slots);
        ex
    }
}

impl Ex<'_> {
    /// A length word of block `b` in mm: the written value rounded to the resolution of the active
    /// unit (0.001 mm, or 0.0001 in converted to mm).
    pub(crate) fn dim(&self, b: &CBlock, a: char) -> Option<f64> {
        match b.word(a)?.val {
            Val::Lit(l) if self.inch => Some(l.value4() * 25.4),
            Val::Lit(l) => Some(l.value()),
            Val::Param(_) | Val::Expr(_) => None,
        }
    }

    fn idx(&self, a: char) -> Option<usize> {
        self.axes.iter().position(|c| *c == a)
    }

    fn origin(&self, i: usize) -> f64 {
        self.work[self.wsel][i] + self.ext[i] + self.local[i] + self.g92[i] + self.tlo[i]
    }

    fn run(&mut self) -> Result<(), RunError> {
        let Some(main) = self.prog.units.first() else {
            return Ok(());
        };
        self.frames.push(Frame {
            unit: 0,
            pc: main.start,
            target: main.start,
            repeat: 1,
            level: None,
        });
        while !self.ended {
            let Some(fr) = self.frames.last_mut() else {
                break;
            };
            let unit = &self.prog.units[fr.unit];
            if fr.pc >= unit.end {
                if self.frames.len() == 1 {
                    break;
                }
                self.pop_frame();
                continue;
            }
            let mut bi = fr.pc;
            if self.opts.backend == crate::run::Backend::Native
                && let Some(code) = self.prog.macro_native.as_ref()
                && let Some(ri) = code.run_at(bi)
            {
                use crate::macro_b::native::MacroExit;
                let max = self.opts.max_blocks;
                // The table leaves `self` for the call, so the executor can serve system variables.
                let mut slots = std::mem::take(&mut self.vars.slots);
                let mut executed = self.executed;
                let exit = code.run(ri, bi, &mut slots, &mut executed, max, Some(self));
                self.vars.slots = slots;
                self.executed = executed;
                match exit {
                    MacroExit::Next(n) => {
                        if let Some(fr) = self.frames.last_mut() {
                            fr.pc = n;
                        }
                        continue;
                    }
                    MacroExit::Interpret(at) => {
                        // The interpreter runs this block (below), then native code resumes.
                        if let Some(fr) = self.frames.last_mut() {
                            fr.pc = at;
                        }
                        bi = at;
                    }
                    MacroExit::Error(at, e) => {
                        return Err(run_err(
                            &self.prog.blocks[at],
                            codes::RUN_MACRO,
                            e.to_string(),
                        ));
                    }
                    MacroExit::Limit(at) => {
                        return Err(run_err(
                            &self.prog.blocks[at],
                            codes::RUN_LIMIT,
                            "too many blocks executed: endless loop?",
                        ));
                    }
                }
            }
            let Some(fr) = self.frames.last_mut() else {
                break;
            };
            fr.pc += 1;
            self.executed += 1;
            if self.executed > self.opts.max_blocks {
                return Err(run_err(
                    &self.prog.blocks[bi],
                    codes::RUN_LIMIT,
                    "too many blocks executed: endless loop?",
                ));
            }
            self.block(bi)?;
        }
        Ok(())
    }

    fn label(&self) -> Option<String> {
        let fr = self.frames.last()?;
        let u = &self.prog.units[fr.unit];
        match u.kind {
            UnitKind::Library => Some(format!("O{}", u.l)),
            _ if self.frames.len() > 1 => Some("M97".to_string()),
            _ => None,
        }
    }

    fn emit(
        &mut self,
        b: &CBlock,
        kind: Kind,
        center: Vec<(char, f64)>,
        m: &[MFunc],
        dwell: Option<f64>,
    ) {
        if !self.opts.record {
            return;
        }
        let feed = if matches!(kind, Kind::Linear | Kind::ArcCw | Kind::ArcCcw) {
            self.feed
        } else {
            None
        };
        let plane = if self.cyl.is_some() {
            Plane::YZ
        } else {
            self.plane
        };
        let c = Canon {
            n: b.n,
            unit: self.label(),
            kind,
            end: self
                .axes
                .iter()
                .enumerate()
                .map(|(i, a)| (*a, self.machine[i]))
                .collect(),
            center,
            plane,
            feed,
            m: m.to_vec(),
            s: self.s,
            t: self.t,
            dwell,
            thread: false,
            thread_angle: 0.0,
            exact_stop: self.exact_modal || self.exact_once,
            tolerance: self.tolerance,
            css: self.css(),
            feed_g94: true,
            modal: self.block_modal(),
        };
        let ctx = self.comp_ctx(b);
        self.rc.push(c, &ctx, &mut self.out);
        if self.discard {
            self.out.clear();
        }
    }

    /// The block's modal record: G90/G91, G94 (the only feed mode), the work offset, G40–G42
    /// with D, G43/G44/G49 with H.
    fn block_modal(&self) -> crate::canon::BlockModal {
        let (work, work_p) = match self.wsel {
            k @ 0..=5 => (54 + k, 0),
            k => (154, k - 5),
        };
        crate::canon::BlockModal {
            distance: if self.abs { 90 } else { 91 },
            feed_mode: 94,
            work: u8::try_from(work).unwrap_or(0),
            work_p: u8::try_from(work_p).unwrap_or(0),
            cutter: u8::try_from(self.comp).unwrap_or(40),
            d: self.d,
            length: match self.tlo_sign {
                Some((s, _)) if s > 0.0 => 43,
                Some(_) => 44,
                None => 49,
            },
            h: self.tlo_h,
            contour: self.contour,
        }
    }

    /// G96 of the block: the surface speed in m/min, radius from the work origin.
    fn css(&self) -> Option<crate::canon::Css> {
        let s = self.s.filter(|_| self.css)?;
        Some(crate::canon::Css {
            m_min: if self.inch { s * 0.3048 } else { s },
            max_rpm: self.max_rpm,
            origin: (0..self.axes.len())
                .map(|i| (self.axes[i], self.origin(i)))
                .collect(),
            diameter: self.diameter,
        })
    }

    fn move_to(&mut self, b: &CBlock, kind: Kind, target: [Option<f64>; 6], m: &[MFunc]) {
        for (i, v) in target.iter().enumerate() {
            if let Some(v) = v {
                self.machine[i] = *v;
            }
        }
        self.emit(b, kind, Vec::new(), m, None);
    }

    fn block(&mut self, bi: usize) -> Result<(), RunError> {
        let prog = self.prog;
        let b = &prog.blocks[bi];
        if let Some(n) = b.n.filter(|_| !(b.skip && self.opts.block_skip)) {
            self.vars.slots[crate::macro_b::SEQ_SLOT] = f64::from(n);
        }
        if let Some(m) = &b.mac {
            if b.skip && self.opts.block_skip {
                return Ok(());
            }
            if let Some(stmt) = &m.stmt {
                return self.statement(b, stmt);
            }
            let nb = self.substitute(b, m)?;
            return self.nc_block(&nb);
        }
        self.nc_block(b)
    }

    /// Runs NC block `b` (its words literal).
    #[allow(clippy::too_many_lines)]
    fn nc_block(&mut self, b: &CBlock) -> Result<(), RunError> {
        let prog = self.prog;
        self.rc.check()?;
        if b.skip && self.opts.block_skip {
            return Ok(());
        }
        let val = |a: char| {
            b.word(a).and_then(|w| {
                if let Val::Lit(l) = w.val {
                    Some(l)
                } else {
                    None
                }
            })
        };
        let num = |a: char| val(a).map(|l| l.value());
        let mut gs = Vec::new();
        for w in b.words.iter().filter(|w| w.addr == 'G') {
            if let Val::Lit(l) = w.val {
                gs.push((l.value() * 10.0).round() as u16);
            }
        }
        let ms: Vec<u16> = b
            .words
            .iter()
            .filter(|w| w.addr == 'M')
            .filter_map(|w| {
                if let Val::Lit(l) = w.val {
                    Some(l.value() as u16)
                } else {
                    None
                }
            })
            .collect();
        if let Some(&m) = ms.iter().rev().find(|m| !matches!(m, 97..=99)) {
            self.last_m = Some(m);
        }
        let (mut dwell, mut g28, mut g53, mut g92, mut g52, mut pocket, mut cyl_cmd) =
            (false, false, false, false, false, None, false);
        let mut new_cycle = false;
        let mut tlo_g = None;
        self.exact_once = false;
        // G64 P<tol>: the blending tolerance, in the program unit (G20/G21 of this block included).
        let inch_now = if gs.contains(&200) {
            true
        } else if gs.contains(&210) {
            false
        } else {
            self.inch
        };
        let g64_p = if gs.contains(&640) {
            val('P').map(|l| {
                if inch_now {
                    l.value4() * 25.4
                } else {
                    l.value()
                }
            })
        } else {
            None
        };
        let mut g10 = false;
        let mut g154 = false;
        for &g in &gs {
            match g {
                430 | 440 | 490 => tlo_g = Some(g),
                0 | 10 | 20 | 30 => {
                    self.motion = g;
                    self.cycle = None;
                }
                170 => self.plane = Plane::XY,
                180 => self.plane = Plane::ZX,
                190 => self.plane = Plane::YZ,
                200 => self.inch = true,
                210 => self.inch = false,
                900 => self.abs = true,
                910 => self.abs = false,
                // G94 feed per minute: the planner's only feed mode. G69 and G100 cancel rotation
                // and mirroring, which are refused: nothing to cancel. G50 with S is the top
                // spindle speed of G96; without S it cancels scaling (refused: nothing to cancel).
                940 | 690 | 1000 => {}
                960 => self.css = true,
                970 => self.css = false,
                500 => {
                    if let Some(s) = num('S') {
                        self.max_rpm = Some(s);
                    }
                }
                90 => self.exact_once = true,
                610 => {
                    self.exact_modal = true;
                    self.tolerance = None;
                }
                640 => {
                    self.exact_modal = false;
                    self.tolerance = g64_p;
                }
                400 | 410 | 420 => self.comp = g / 10,
                100 => g10 = true,
                540..=590 => self.wsel = usize::from((g - 540) / 10),
                1100..=1290 => self.wsel = usize::from((g - 1100) / 10) + 6,
                1540 => g154 = true,
                980 => self.g99 = false,
                990 => self.g99 = true,
                800 => self.cycle = None,
                730 | 740 | 810..=860 | 890 => {
                    self.cycle = Some(g);
                    new_cycle = true;
                }
                40 => dwell = true,
                280 => g28 = true,
                530 => g53 = true,
                920 => g92 = true,
                520 => g52 = true,
                120 | 130 => pocket = Some(g),
                71 => cyl_cmd = true,
                // AI contour control: G05.1 Q1/Q0 (AICC), G08 P1/P0 (AI look-ahead).
                51 | 80 => {
                    let (word, name) = if g == 51 {
                        ('Q', "G05.1")
                    } else {
                        ('P', "G08")
                    };
                    self.contour = match num(word) {
                        Some(1.0) => true,
                        Some(0.0) => false,
                        other => {
                            let got = other.map_or("none".to_string(), |v| v.to_string());
                            return Err(run_err(
                                b,
                                codes::RUN_BAD_G,
                                format!(
                                    "{name} takes {word}1 (contour control on) or {word}0 (off), found {word} {got}"
                                ),
                            ));
                        }
                    };
                }
                g => {
                    return Err(run_err(
                        b,
                        codes::RUN_BAD_G,
                        format!("G{} is not supported by the planner", f64::from(g) / 10.0),
                    ));
                }
            }
        }
        if g154 {
            self.g154(b, num('P'))?;
        }
        if let Some(s) = num('S')
            && !gs.contains(&500)
        {
            self.s = Some(s);
        }
        if let Some(t) = num('T') {
            self.t = Some(t as i64);
        }
        if let Some(d) = num('D') {
            self.d = d as i64;
        }
        if let Some(f) = self.dim(b, 'F') {
            self.feed = Some(f);
        }
        let mut mf: Vec<MFunc> = Vec::new();
        for &m in &ms {
            if matches!(m, 97..=99) {
                continue;
            }
            let before = match prog.machine.m_timing(m) {
                Some(t) => t.before_motion(),
                None => matches!(m, 3 | 4 | 7 | 8 | 21),
            };
            mf.push(MFunc { m, before });
        }
        mf.sort_by_key(|m| !m.before);
        // Axis words (lathe U/W/H are incremental X/Z/C).
        let lathe = !self.axes.contains(&'Y');
        let mut vals: [Option<f64>; 6] = [None; 6];
        let mut incr: [bool; 6] = [false; 6];
        for (i, a) in self.axes.clone().iter().enumerate() {
            if *a == 'C' && cyl_cmd {
                continue;
            }
            // `G04 X<s>`: X is the dwell time, not a position.
            if *a == 'X' && dwell && b.word('P').is_none() {
                continue;
            }
            // Rotary axes are in degrees whatever G20/G21 say.
            if matches!(*a, 'A' | 'B' | 'C') {
                if let Some(v) = num(*a) {
                    vals[i] = Some(v);
                }
            } else if let Some(v) = self.dim(b, *a) {
                vals[i] = Some(v);
            }
            let inc_letter = match a {
                'X' if lathe => Some('U'),
                'Z' if lathe => Some('W'),
                'C' if lathe => Some('H'),
                _ => None,
            };
            if let Some(l) = inc_letter {
                let v = if *a == 'C' { num(l) } else { self.dim(b, l) };
                if let Some(v) = v {
                    vals[i] = Some(v);
                    incr[i] = true;
                }
            }
        }
        let any = vals.iter().any(Option::is_some);
        let non_motion = g92 || g52 || g28 || g53;
        let uses = words::Uses {
            dwell,
            g10: if g10 {
                num('L').map(|l| l as i64)
            } else {
                None
            },
            pocket: pocket.is_some() && !g10 && !non_motion,
            p_value: g154 || gs.contains(&640) || gs.contains(&80),
            q_value: gs.contains(&51),
            cycle: self
                .cycle
                .filter(|_| !g10 && !non_motion && pocket.is_none() && (new_cycle || any)),
            non_motion,
            call: ms.contains(&97) || ms.contains(&98),
            ret: ms.contains(&99),
        };
        self.check_words(b, &uses)?;
        self.tool_length(b, tlo_g, g28)?;
        let target = |ex: &Self, vals: &[Option<f64>; 6]| -> [Option<f64>; 6] {
            let mut t = [None; 6];
            for i in 0..ex.axes.len() {
                if let Some(v) = vals[i] {
                    t[i] = Some(if incr[i] || !ex.abs {
                        ex.machine[i] + v + ex.tlo_due[i]
                    } else {
                        v + ex.origin(i)
                    });
                }
            }
            t
        };
        if cyl_cmd {
            let c = num('C').unwrap_or(0.0);
            self.cyl = if c > 0.0 { Some(c) } else { None };
        }
        let mut moved = false;
        if g10 {
            self.g10(b, &vals)?;
        } else if g92 {
            self.g92(&vals);
        } else if g52 {
            self.g52(&vals);
        } else if g28 && !any {
            // G28 without axis words: every axis returns to machine zero at rapid, the additional
            // rotary axes B and C after the others (HAAS 002:1747).
            let (main, extra): (Vec<usize>, Vec<usize>) =
                (0..self.axes.len()).partition(|&i| !matches!(self.axes[i], 'B' | 'C'));
            for (set, m) in [(main, &mf[..]), (extra, &[][..])] {
                if set.is_empty() {
                    continue;
                }
                let mut zero = [None; 6];
                for i in set {
                    zero[i] = Some(0.0);
                }
                self.move_to(b, Kind::Rapid, zero, m);
            }
            moved = true;
        } else if g28 {
            let mid = target(self, &vals);
            self.move_to(b, Kind::Rapid, mid, &mf);
            let mut zero = [None; 6];
            for i in 0..self.axes.len() {
                if vals[i].is_some() {
                    zero[i] = Some(0.0);
                }
            }
            self.move_to(b, Kind::Rapid, zero, &[]);
            moved = true;
        } else if g53 {
            let kind = if self.motion == 10 {
                Kind::Linear
            } else {
                Kind::Rapid
            };
            self.move_to(b, kind, vals, &mf);
            moved = true;
        } else if let Some(g) = pocket {
            self.pocket(b, g, &vals, &mf)?;
            moved = true;
        } else if let Some(cyc) = self.cycle {
            if new_cycle || any {
                self.canned(b, cyc, new_cycle, &vals, &mf)?;
                moved = true;
            }
        } else if any
            || (matches!(self.motion, 20 | 30)
                && (self.has_centre_words(b) || b.word('R').is_some()))
        {
            // An arc with I/J/K and no end point is a full circle (HAAS 002:1450); with R it is an
            // error the arc reports (a 360° arc cannot be defined with R).
            let t = target(self, &vals);
            match self.motion {
                20 | 30 => {
                    let center = self.arc(b, &t)?;
                    let kind = if self.motion == 20 {
                        Kind::ArcCw
                    } else {
                        Kind::ArcCcw
                    };
                    for (i, v) in t.iter().enumerate() {
                        if let Some(v) = v {
                            self.machine[i] = *v;
                        }
                    }
                    self.emit(b, kind, center, &mf, None);
                }
                0 => self.move_to(b, Kind::Rapid, t, &mf),
                _ => self.move_to(b, Kind::Linear, t, &mf),
            }
            moved = true;
        }
        self.tlo_moved(&vals);
        if dwell {
            let secs = match val('P').or_else(|| val('X')) {
                Some(l) if l.point || b.word('X').is_some() => l.value(),
                Some(l) => l.value() / 1000.0,
                None => 0.0,
            };
            let m = if moved {
                Vec::new()
            } else {
                std::mem::take(&mut mf)
            };
            self.emit(b, Kind::Dwell, Vec::new(), &m, Some(secs));
            moved = true;
        }
        if !moved && (!mf.is_empty() || num('S').is_some() || num('T').is_some()) {
            self.emit(b, Kind::Aux, Vec::new(), &mf, None);
        }
        // Program flow.
        let p = num('P').map(|v| v as u32);
        let l = num('L').map_or(1, |v| v as i64);
        if ms.contains(&97) || ms.contains(&98) {
            let p = p.ok_or_else(|| run_err(b, codes::RUN_TARGET, "M97/M98 without P"))?;
            let (unit, target) = if ms.contains(&97) {
                let t = prog.units[b.unit]
                    .index
                    .get(p)
                    .ok_or_else(|| run_err(b, codes::RUN_TARGET, format!("no block N{p}")))?;
                (b.unit, t)
            } else {
                let u = *prog
                    .library
                    .get(&p)
                    .ok_or_else(|| run_err(b, codes::RUN_TARGET, format!("no program O{p}")))?;
                (u, prog.units[u].start)
            };
            if self.frames.len() >= 64 {
                return Err(run_err(
                    b,
                    codes::RUN_LIMIT,
                    "calls nested deeper than 64 levels",
                ));
            }
            if l > 0 {
                self.frames.push(Frame {
                    unit,
                    pc: target,
                    target,
                    repeat: l,
                    level: None,
                });
            }
        } else if ms.contains(&99) {
            if self.frames.len() > 1 {
                if let Some(fr) = self.frames.last_mut()
                    && fr.repeat > 1
                {
                    fr.repeat -= 1;
                    fr.pc = fr.target;
                    self.restart_locals();
                    return Ok(());
                }
                self.pop_frame();
                // M99 P<n>: the caller continues at its block N<n> instead of the block after the call.
                if let Some(n) = p {
                    let fr = self
                        .frames
                        .last_mut()
                        .ok_or_else(|| run_err(b, codes::RUN_TARGET, "M99 P without a caller"))?;
                    fr.pc = prog.units[fr.unit].index.get(n).ok_or_else(|| {
                        run_err(
                            b,
                            codes::RUN_TARGET,
                            format!("M99 P{n}: no block N{n} in the calling program"),
                        )
                    })?;
                }
            } else if let Some(n) = p {
                // M99 P<n> in the main program jumps to its block N<n>.
                let fr = self
                    .frames
                    .last_mut()
                    .ok_or_else(|| run_err(b, codes::RUN_TARGET, "no program"))?;
                fr.pc = prog.units[fr.unit].index.get(n).ok_or_else(|| {
                    run_err(
                        b,
                        codes::RUN_TARGET,
                        format!("M99 P{n}: no block N{n} in this program"),
                    )
                })?;
            } else {
                // M99 in the main program loops forever on a control; a plan stops here.
                self.ended = true;
            }
        }
        if ms.contains(&30) || ms.contains(&2) {
            self.cancel_tlo();
            // The FANUC-style G52 shift ends with the program (HAAS spec §9.4).
            self.local = [0.0; 6];
        }
        if (ms.contains(&30) || ms.contains(&2)) && self.frames.len() == 1 {
            self.ended = true;
        }
        Ok(())
    }
}
