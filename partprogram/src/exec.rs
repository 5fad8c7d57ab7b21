//! The MEFI executor: runs a compiled [`Program`] block by block and emits canonical blocks.
//!
//! Order inside one block (parameters-cycles spec §10): substitute `<addr>R<n>` with the parameter
//! values from before the block; apply the block's declarations; run G26–G29 (native code or the
//! reference interpreter); update modal state; move; run the active fixed cycle; transfer control
//! (G71/G72 calls, G73/`GR<n>` jumps, G70 return, M02/M30 end).

mod block;
mod comp;
mod flow;
mod words;

use crate::arith::{ArithError, ArithState, NPARAM};
use crate::canon::{Canon, Kind, MFunc, Plane};
use crate::codes;
use crate::geom::Geometry;
use crate::jit::{RegionCount, RegionExit};
use crate::lexer::Lit;
use crate::program::{CBlock, Program, UnitKind};
use crate::radius::Compensator;
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
    /// Constant cutting speed (KŘR) on: G96 (feed per minute) or G97 (feed per revolution).
    pub css: bool,
    pub s: Option<f64>,
    pub t: Option<i64>,
    pub d: i64,
    pub amp: i64,
    /// Helix on (G09) until G98.
    pub helix: bool,
    /// Smooth block connection G23 (group 2) until G24, G98 or G09: off means every block ends
    /// with a stop ramp ([`Canon::exact_stop`]).
    pub smooth: bool,
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
    /// G73 jump counters, one slot per block of the unit ([`crate::jit::region::IDLE`]: none).
    counters: Vec<i64>,
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
            V::Lit(l) => l.milli() / 1000,
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
    /// Radius compensation between the executor and `out`.
    rc: Compensator,
    executed: u64,
    ended: bool,
    /// True when the canonical blocks are only checked ([`check`]): `out` is emptied after each
    /// block, so the run holds the look-ahead of the compensation, not the plan.
    discard: bool,
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

fn limit_err(b: &CBlock, max_blocks: u64) -> RunError {
    run_err(
        b,
        codes::RUN_LIMIT,
        format!("more than {max_blocks} blocks executed: endless loop?"),
    )
}

/// Plans `prog`: runs it and returns its canonical blocks.
pub fn plan(prog: &Program, opts: PlanOptions) -> Result<Plan, (Vec<Canon>, RunError)> {
    let mut ex = Exec::new(prog, opts);
    ex.out.reserve_exact(crate::run::plan_capacity(prog, &opts));
    let done = ex.run().and_then(|()| ex.rc.finish(&mut ex.out));
    // Without the spare room of the last doubling (up to as much again): a part run holds its plans.
    ex.out.shrink_to_fit();
    match done {
        Ok(()) => Ok(Plan {
            blocks: ex.out,
            params: ex.st.r,
            executed: ex.executed,
            messages: std::mem::take(&mut ex.st.messages),
            macro_vars: Vec::new(),
        }),
        Err(e) => Err((ex.out, e)),
    }
}

/// Runs `prog` as [`plan`] does, keeping none of its canonical blocks: the run-time error
/// [`plan`] would give, or the number of blocks executed.
pub fn check(prog: &Program, opts: PlanOptions) -> Result<u64, RunError> {
    let mut ex = Exec::new(prog, opts);
    ex.discard = true;
    ex.run().and_then(|()| ex.rc.finish(&mut ex.out))?;
    Ok(ex.executed)
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
        st.corrections = m.corrections.rows();
        st.offsets = m.zero_offsets.rows;
        st.g_groups[1] = plane.g();
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
                css: false,
                s: None,
                t: None,
                d: 0,
                amp: 0,
                helix: false,
                smooth: false,
                lift: None,
                lead: None,
            },
            geo: {
                let mut g = Geometry::new(&m.axes(), m.diameter_x);
                g.machine = opts.start;
                g.prog = opts.start;
                g
            },
            frames: vec![Frame {
                unit: 0,
                pc: prog.units.first().map_or(0, |u| u.start),
                counters: flow::idle_counters(prog.units.first()),
                repeat: 1,
                cycle: None,
            }],
            out: Vec::new(),
            rc: Compensator::new(opts.radius),
            executed: 0,
            ended: false,
            discard: false,
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
            let (mut bi, end) = (fr.pc, unit.end);
            if let Some(ri) = self.region_at(bi) {
                // A parameter-only region runs natively and returns the first block it does not
                // handle; that block is interpreted at once (re-entering the region with it would
                // return it again).
                bi = self.run_region(ri, bi)?;
                if bi >= end {
                    if let Some(fr) = self.frames.last_mut() {
                        fr.pc = bi;
                    }
                    continue;
                }
            }
            if let Some(fr) = self.frames.last_mut() {
                fr.pc = bi + 1;
            }
            self.executed += 1;
            if self.executed > self.opts.max_blocks {
                return Err(limit_err(&self.prog.blocks[bi], self.opts.max_blocks));
            }
            self.block(bi)?;
        }
        Ok(())
    }

    /// The native region for block `bi` when the native back end may run it now: not while a fixed
    /// cycle is active (it runs after every block) or radius compensation is on (it looks at the
    /// blocks between motions).
    fn region_at(&self, bi: usize) -> Option<usize> {
        if self.opts.backend != Backend::Native
            || self.modal.cycle.is_some()
            || self.modal.comp != 40
        {
            return None;
        }
        self.prog.native.as_ref()?.region_at(bi)
    }

    /// Runs region `ri` from block `bi`; returns the next block to interpret.
    fn run_region(&mut self, ri: usize, bi: usize) -> Result<usize, RunError> {
        let (Some(native), Some(fr)) = (self.prog.native.as_ref(), self.frames.last_mut()) else {
            return Ok(bi);
        };
        let mut count = RegionCount {
            executed: self.executed,
            max_blocks: self.opts.max_blocks,
            block_skip: self.opts.block_skip,
        };
        let exit = native.run_region(ri, bi, &mut self.st, &mut fr.counters, &mut count);
        let before = std::mem::replace(&mut self.executed, count.executed);
        if self.executed > before {
            // Every interpreted block ends with this export; the geometry is unchanged in a region.
            self.geo.export_programmed(&mut self.st);
        }
        let blocks = &self.prog.blocks;
        match exit {
            RegionExit::Next(n) => Ok(n),
            RegionExit::Arith(b, e) => Err(arith_err(&blocks[b], e)),
            RegionExit::Limit(b) => Err(limit_err(&blocks[b], self.opts.max_blocks)),
        }
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

    fn run_arith(&mut self, b: &CBlock, ops: u8, literal: bool) -> Result<(), RunError> {
        if literal
            && self.opts.backend == Backend::Native
            && let (Some(fi), Some(native)) = (b.native, self.prog.native.as_ref())
        {
            let rc = native.call(fi, &mut self.st);
            return if rc == 0 {
                Ok(())
            } else {
                Err(arith_err(b, ArithError::from_code(rc)))
            };
        }
        let words: Vec<i64> = self.st.r[5..5 + usize::from(ops)].to_vec();
        self.st.exec_seq(&words).map_err(|e| arith_err(b, e))
    }

    fn sync_groups(&mut self, gs: &[(u16, bool)]) {
        for &(g, _) in gs {
            if let Some(grp) = crate::groups::mefi_g_group(g)
                && let Some(slot) = self.st.g_groups.get_mut(usize::from(grp))
            {
                *slot = g;
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
        thread: Option<f64>,
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
            thread: thread.is_some(),
            thread_angle: thread.unwrap_or(0.0),
            exact_stop: !self.modal.smooth,
            tolerance: None,
            css: self.css(),
            feed_g94: self.modal.feed_mode == 94,
            modal: self.block_modal(),
        };
        let ctx = self.comp_ctx(b);
        self.rc.push(c, &ctx, &mut self.out);
        if self.discard {
            self.out.clear();
        }
    }

    /// The block's modal record: G90/G91, G94–G97, the zero offset G53–G57, G40–G42 with D.
    fn block_modal(&self) -> crate::canon::BlockModal {
        crate::canon::BlockModal {
            distance: if self.modal.abs { 90 } else { 91 },
            feed_mode: u8::try_from(self.modal.feed_mode).unwrap_or(94),
            work: u8::try_from(53 + self.modal.offset).unwrap_or(0),
            work_p: 0,
            cutter: u8::try_from(self.modal.comp).unwrap_or(40),
            d: self.modal.d,
            length: 0,
            h: 0,
            contour: self.modal.smooth,
        }
    }

    /// KŘR of the block: S is the cutting speed in tenths of m/min (000:1239).
    fn css(&self) -> Option<crate::canon::Css> {
        let s = self.modal.s.filter(|_| self.modal.css)?;
        Some(crate::canon::Css {
            m_min: s / 10.0,
            max_rpm: None,
            origin: self.geo.origin(),
            diameter: self.geo.diameter,
        })
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
            thread_angle: 0.0,
            exact_stop: !self.modal.smooth,
            tolerance: None,
            css: self.css(),
            feed_g94: self.modal.feed_mode == 94,
            modal: self.block_modal(),
        };
        let ctx = self.comp_ctx(b);
        self.rc.push(c, &ctx, &mut self.out);
        if self.discard {
            self.out.clear();
        }
    }
}
