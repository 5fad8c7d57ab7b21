//! One MEFI block: substitution, declarations, arithmetic, modal functions, tables, transformations,
//! motion, dwell, program flow and the active fixed cycle, in the order of parameters-cycles §10.

use super::{Exec, Snapshot, V, run_err};
use crate::arith::NPARAM;
use crate::ast::Val;
use crate::canon::{Kind, MFunc, Plane};
use crate::codes;
use crate::exec::RunError;
use crate::geom::Target;
use crate::groups::mefi_m_group;
use crate::program::UnitKind;

impl Exec<'_> {
    #[allow(clippy::too_many_lines)]
    pub(super) fn block(&mut self, bi: usize) -> Result<(), RunError> {
        let prog = self.prog;
        let b = &prog.blocks[bi];
        self.rc.check()?;
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
        let mut run_in = None;
        for w in &b.words {
            let v = match w.val {
                Val::Lit(l) => V::Lit(l),
                Val::Expr(_) => continue,
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
                'E' => run_in = Some(v.mm()),
                'H' | 'P' => {}
                a => {
                    if let Some(i) = self.geo.axes.iter().position(|c| *c == a)
                        && i < naxes
                    {
                        axes[i] = Some(v.mm());
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
                14..=16 => {
                    let (first, second) = prog
                        .machine
                        .plane_341_axes(g)
                        .map_err(|m| run_err(b, codes::RUN_PLANE_AXIS, m))?;
                    self.modal.plane = Plane::Extra {
                        g: g as u8,
                        first,
                        second,
                    };
                }
                40..=42 => self.modal.comp = g,
                53..=57 => {
                    self.modal.offset = usize::from(g - 53);
                    self.geo.select_offset(&self.st, self.modal.offset);
                }
                58 | 59 => block_offset = Some(usize::from(g - 53)),
                94..=97 => {
                    self.modal.feed_mode = g;
                    self.modal.css = g >= 96;
                }
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
                9 => {
                    self.modal.helix = true;
                    self.modal.smooth = false;
                }
                98 | 24 => {
                    self.modal.helix = false;
                    self.modal.smooth = false;
                }
                23 => {
                    self.modal.helix = false;
                    self.modal.smooth = true;
                }
                10 => lift = true,
                26..=29 | 5..=7 => {}
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
        if let Some(v) = f {
            // F is one modal address: a G33 block without F cuts with the lead of the last F (the
            // lathe cycles G84-G87 program `FR26` in a G00/G90 block and `G33 IR27 ZR31` after it).
            // Thread lead in mm/rev: with a point mm, without a point µm (as G95), a parameter r µm.
            self.modal.lead = Some(match v {
                V::Lit(l) if l.point => l.value(),
                V::Lit(l) => l.value() / 1000.0,
                V::R(r) => r as f64 / 1000.0,
            });
        }
        if let Some(v) = f.filter(|_| self.modal.motion != 33) {
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
        if (amp.is_some() || d.is_some()) && !g92 {
            let e = usize::try_from(self.modal.d).unwrap_or(0).min(99);
            let entry = self.st.corrections[e];
            let lengths =
                crate::length::mefi_lengths(prog.machine.length_method, self.modal.amp, &entry)
                    .map_err(|m| run_err(b, codes::RUN_RANGE, m))?;
            self.geo.set_lengths(&lengths);
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
        // Whether the block interpolates a path (the last branch below), decided here so that a
        // word the block would ignore stops the plan before the block is emitted.
        let interpolated = !(g92 || g93 || lift || g30 || transform.is_some())
            && (any_axis
                || (matches!(self.modal.motion, 2 | 3) && ijk.iter().any(Option::is_some)));
        super::words::check(
            b,
            &super::words::Done {
                motion: self.modal.motion,
                interpolated,
                dwell,
                flow,
            },
        )?;
        if self.modal.feed_mode == 97 && any_axis && matches!(self.modal.motion, 1..=3) {
            // The feed in mm/min would follow the spindle speed every tick; the planner's feed is
            // fixed per block.
            return Err(run_err(
                b,
                codes::RUN_BAD_G,
                "G97 (constant cutting speed with feed per revolution) is not implemented for \
                 feed moves; use G96 (feed per minute)"
                    .to_string(),
            ));
        }
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
            self.emit(b, Kind::Rapid, Vec::new(), None, &mfuncs, None);
            moved = true;
        } else if interpolated {
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
                        let sweep = if !(1e-9..=std::f64::consts::TAU - 1e-9).contains(&sweep) {
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
                        None,
                    );
                }
                0 => {
                    self.geo.linear(&tgt, &self.st);
                    self.emit(b, Kind::Rapid, Vec::new(), None, &mfuncs, None);
                }
                _ => {
                    let start = self.geo.machine;
                    self.geo.linear(&tgt, &self.st);
                    let feed = if motion == 33 {
                        self.modal.lead.zip(self.modal.s).map(|(l, s)| l * s)
                    } else {
                        self.feed()
                    };
                    let ej = (run_in, ijk[1]);
                    // G33 I: the start angle after the spindle's zero pulse, degrees (000:916).
                    let angle = (motion == 33).then(|| ijk[0].unwrap_or(0.0));
                    if !(motion == 33 && self.thread_run(b, start, ej, feed, &mfuncs, angle)?) {
                        self.emit(b, Kind::Linear, Vec::new(), feed, &mfuncs, angle);
                    }
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
            self.emit(b, Kind::Aux, Vec::new(), None, &mfuncs, None);
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
            Some(70)
                if !self
                    .frames
                    .last()
                    .is_some_and(|f| prog.units[f.unit].kind == UnitKind::Main) =>
            {
                self.ret(bi)?;
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
}

impl Exec<'_> {
    /// A G33 block with run-in `E` / run-out `J` (`ej`): emits the thread from `start` to the current
    /// (programmed) end in up to three segments ([`crate::thread`]), each with the start angle
    /// `angle`; false when the block has neither.
    fn thread_run(
        &mut self,
        b: &crate::program::CBlock,
        start: [f64; 6],
        ej: (Option<f64>, Option<f64>),
        feed: Option<f64>,
        mfuncs: &[MFunc],
        angle: Option<f64>,
    ) -> Result<bool, RunError> {
        if ej == (None, None) {
            return Ok(false);
        }
        let dia = std::array::from_fn(|i| self.geo.diameter && self.geo.axes.get(i) == Some(&'X'));
        let need = (ej.1.is_some(), ej.0.is_some());
        let mc8 = self.prog.machine.thread_constant;
        let pts = crate::thread::slopes(mc8, &self.st.r, need)
            .and_then(|sl| crate::thread::split(start, self.geo.machine, dia, ej, sl))
            .map_err(|m| run_err(b, codes::RUN_THREAD, m))?;
        let last = pts.len().saturating_sub(1);
        for (k, p) in pts.into_iter().enumerate() {
            self.geo.move_machine(p, &self.st, self.modal.offset);
            let m: Vec<MFunc> = mfuncs
                .iter()
                .filter(|m| if m.before { k == 0 } else { k == last })
                .cloned()
                .collect();
            self.emit(b, Kind::Linear, Vec::new(), feed, &m, angle);
        }
        Ok(true)
    }
}
