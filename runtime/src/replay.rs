//! Replaying a trace: re-apply its inputs in virtual time and compare the outputs.
//!
//! Replay starts from a fresh image (packet T from the configuration, no retained data), writes
//! each record's inputs at the start of its tick, scans, and diffs the written signals, exactly as
//! `ncplc run --record` produced them. With [`ReplayOptions::skip_idle`] the stretches in which
//! nothing can happen are jumped over ([`crate::idle_skip`]) with the same records as a
//! tick-by-tick replay; the outputs are diffed through [`crate::output_watch`].
//! Values an HMI force put back after the scan (`forced`) are written after the replay's scan
//! too; a tick with forces is never skipped.
//!
//! A part-run trace (its header names the partprograms) is replayed with a [`ReplayKernel`]: the
//! CNC kernel, its plant and the operator re-run beside the logic, tick for tick as in `ncplc run`.
//! The trace's inputs are applied except the bits the kernel owns; those the kernel recomputes,
//! and the replay compares every input change (the kernel's CNC→PLC signals) and every axis
//! position with the trace, exactly (positions as f64 bits).

use std::borrow::Borrow;
use std::collections::VecDeque;

use crate::idle_skip::IdleSkipper;
use crate::image::Image;
use crate::output_watch::OutputWatch;
use crate::program::Loaded;
use trace::compare::{Comparator, report};
use trace::positions::{PositionComparator, PositionTracker};
use trace::recorder::InputDiff;
use trace::{AxisValue, OperatorCommand, SignalValue, TickRecord, Trace};

/// The CNC side a replay re-runs: a part run's kernel, plant and operator.
pub trait ReplayKernel {
    /// One mask byte per image byte of packets A, K and N: the bits the kernel writes.
    fn written_mask(&self) -> Vec<u8>;
    /// Tick `t`'s latch: the kernel steps on the outputs published last and writes `packets`.
    fn latch(&mut self, t: u64, packets: &mut [u8]);
    /// After tick `t`'s scan: the published packets (the operator acts here, as after a live tick).
    fn publish(&mut self, t: u64, packets: &[u8]);
    /// Every axis and its position bits after the latch.
    fn positions(&mut self, out: &mut Vec<AxisValue>);
    /// Before tick `t`'s latch: an operator command the recorded run's kernel accepted here.
    fn command(&mut self, t: u64, c: &OperatorCommand) -> Result<(), String>;
    /// Before tick `t`'s latch: the bus drives' feedback the recorded kernel took at this latch
    /// (the last recorded one; a run without drives has none and never gets a call).
    fn drives(&mut self, _t: u64, _feedback: &[trace::DriveSample]) {}
    /// Before tick `t`'s latch: the I/O nodes the recorded run lost at this latch.
    fn nodes_lost(&mut self, _t: u64, _lost: &[trace::NodeLoss]) {}
}

/// The result of a replay.
#[derive(Debug)]
pub struct Replay {
    /// Output comparison.
    pub comparator: Comparator,
    /// Ticks replayed (the last record's tick + 1).
    pub ticks: u64,
    /// Ticks jumped over as idle (0 for a tick-by-tick replay).
    pub skipped: u64,
    /// The image after the last tick.
    pub image: Vec<u8>,
    /// Axis position comparison (empty without a kernel).
    pub positions: PositionComparator,
    /// Recorded operator commands the replay's kernel refused (`tick N: {…} refused: why`): the
    /// run diverged before them.
    pub refused: Vec<String>,
    /// The trace's and the replay's records around the first output divergence.
    window: Context,
}

impl Replay {
    /// True when the outputs (and, with a kernel, its signals and the axis positions) are
    /// identical.
    pub fn identical(&self) -> bool {
        self.comparator.identical() && self.positions.identical() && self.refused.is_empty()
    }

    /// The divergence report, with [`ReplayOptions::context`] ticks around the first divergence.
    pub fn report(&self) -> String {
        let mut s = String::new();
        if !self.comparator.identical() {
            let w = &self.window;
            s = report(&self.comparator, &w.expected, &w.actual, w.context);
        }
        for r in &self.refused {
            s.push_str(r);
            s.push('\n');
        }
        s.push_str(&self.positions.report());
        s
    }
}

/// The records a divergence report shows: before the first divergence, those of the last
/// `context` ticks; after it, those up to `context` ticks past it. A replay of any length keeps
/// at most the records of `2 × context + 1` ticks (moved in, never copied: the trace's record
/// type `R` is the reader's own record or a reference into a trace in memory).
#[derive(Debug)]
struct Window<R> {
    context: u64,
    expected: VecDeque<R>,
    actual: VecDeque<TickRecord>,
}

impl<R: Borrow<TickRecord>> Window<R> {
    fn new(context: u64) -> Self {
        Window {
            context,
            expected: VecDeque::new(),
            actual: VecDeque::new(),
        }
    }

    /// Keeps tick `t`'s records; `first` is the first divergence's tick, if any yet.
    fn record(
        &mut self,
        t: u64,
        first: Option<u64>,
        expected: Option<R>,
        actual: Option<TickRecord>,
    ) {
        let lo = match first {
            Some(f) if t > f.saturating_add(self.context) => return,
            Some(f) => f.saturating_sub(self.context),
            None => t.saturating_sub(self.context),
        };
        while self.expected.front().is_some_and(|r| r.borrow().t < lo) {
            self.expected.pop_front();
        }
        while self.actual.front().is_some_and(|r| r.t < lo) {
            self.actual.pop_front();
        }
        self.expected.extend(expected);
        self.actual.extend(actual);
    }

    /// The records kept, as the report shows them.
    fn finish(self) -> Context {
        Context {
            context: self.context,
            expected: self.expected.iter().map(|r| r.borrow().clone()).collect(),
            actual: self.actual.into(),
        }
    }
}

/// The trace's and the replay's records around the first divergence (see [`Window`]).
#[derive(Debug, Default)]
struct Context {
    context: u64,
    expected: Vec<TickRecord>,
    actual: Vec<TickRecord>,
}

/// How a replay runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReplayOptions {
    /// Jump over idle ticks ([`crate::idle_skip`]); the records are the same as tick by tick.
    pub skip_idle: bool,
    /// The replay also drives a CNC kernel (a trace of `ncplc run --program`): axes move in ticks
    /// that leave the PLC image unchanged, so no tick is ever skipped.
    pub drives_kernel: bool,
    /// Ticks of context the divergence report shows around the first divergence (3 by default).
    pub context: u64,
}

impl Default for ReplayOptions {
    fn default() -> Self {
        ReplayOptions {
            skip_idle: false,
            drives_kernel: false,
            context: 3,
        }
    }
}

impl ReplayOptions {
    /// True when idle ticks are skipped: asked for, and no kernel is driven.
    pub fn skips(&self) -> bool {
        self.skip_idle && !self.drives_kernel
    }
}

/// Replays `trace` through `loaded` tick by tick, starting from packet T = `t_init`; `progress` is
/// called every 65,536 ticks with the ticks done.
pub fn replay(trace: &Trace, loaded: Loaded, t_init: &[u8], progress: impl FnMut(u64)) -> Replay {
    replay_with(trace, loaded, t_init, ReplayOptions::default(), progress)
}

/// [`replay`] with `options` (idle ticks skipped when [`ReplayOptions::skips`]); `progress` is
/// called at least every 65,536 ticks with the ticks done.
pub fn replay_with(
    trace: &Trace,
    loaded: Loaded,
    t_init: &[u8],
    options: ReplayOptions,
    progress: impl FnMut(u64),
) -> Replay {
    replay_keeping(trace, loaded, t_init, options, progress).0
}

/// [`replay_with`], also returning what the replay produced: the trace's inputs with the
/// replay's outputs, one record per tick with changes (the `--update` form of the trace).
pub fn replay_keeping(
    trace: &Trace,
    loaded: Loaded,
    t_init: &[u8],
    options: ReplayOptions,
    progress: impl FnMut(u64),
) -> (Replay, Trace) {
    let mut actual = Trace {
        tick_ms: trace.tick_ms,
        ticks: Vec::new(),
        part: trace.part.clone(),
    };
    let records = trace.ticks.iter().map(Ok::<_, std::convert::Infallible>);
    let keep = &mut |r: &TickRecord| {
        actual.ticks.push(r.clone());
        Ok(())
    };
    let replay = match replay_records(records, loaded, t_init, options, None, keep, progress) {
        Ok(r) => r,
        Err(never) => match never {},
    };
    (replay, actual)
}

/// Writes the trace's `inputs` into `image`, leaving the bits of `mask` (the kernel's) alone.
fn apply_masked(image: &mut [u8], inputs: &[SignalValue], mask: &[u8]) {
    for (s, v) in inputs {
        let at = s.image_byte();
        let m = mask.get(at).copied().unwrap_or(0);
        match s.bit() {
            Some(b) if m & (1 << b) == 0 => s.write(image, *v),
            Some(_) => {}
            None => {
                if let Some(slot) = image.get_mut(at) {
                    *slot = (*slot & m) | (*v & !m);
                }
            }
        }
    }
}

/// Replays the trace whose `records` arrive one at a time (in tick order, as a trace file holds
/// them) through `loaded`, re-running `kernel` beside the logic when given (a part-run trace; no
/// tick is skipped then). Each record the replay produces goes to `actual` as it is made; a
/// record that cannot be read, or an error of `actual`, ends the replay with that error. Holds one
/// record of the trace at a time (and the divergence report's window), so memory does not grow
/// with the trace.
pub fn replay_records<R: Borrow<TickRecord>, E>(
    records: impl IntoIterator<Item = Result<R, E>>,
    mut loaded: Loaded,
    t_init: &[u8],
    options: ReplayOptions,
    mut kernel: Option<&mut dyn ReplayKernel>,
    actual: &mut dyn FnMut(&TickRecord) -> Result<(), E>,
    mut progress: impl FnMut(u64),
) -> Result<Replay, E> {
    let options = ReplayOptions {
        drives_kernel: options.drives_kernel || kernel.is_some(),
        ..options
    };
    let mut image = Image::new(loaded.meta.image_len(), t_init);
    loaded.meta.init_image(image.bytes_mut());
    let mut watch = OutputWatch::new(&loaded.meta.written_signals());
    let mut skipper = loaded
        .meta
        .idle_facts()
        .filter(|_| options.skips())
        .map(|f| IdleSkipper::new(&f, image.bytes().len()));
    let mut cmp = Comparator::new(20);
    let mut window = Window::new(options.context);
    let mask = kernel
        .as_ref()
        .map(|k| k.written_mask())
        .unwrap_or_default();
    let mut input_diff = InputDiff::default();
    let mut ins: Vec<SignalValue> = Vec::new();
    let mut tracker = PositionTracker::default();
    let mut pcmp = PositionComparator::new(20);
    let mut pos: Vec<AxisValue> = Vec::new();
    let mut outs = Vec::new();
    let mut refused = Vec::new();
    let mut records = records.into_iter();
    // The next record of the trace: the replay runs up to the last record's tick.
    let mut ahead = records.next().transpose()?;
    let none: &[(packets::Signal, u8)] = &[];
    let mut drives: Vec<trace::DriveSample> = Vec::new();
    let mut t = 0;
    let mut ticks = 0;
    while let Some(next_t) = ahead.as_ref().map(|r| r.borrow().t) {
        // (A record not after the tick, which no trace file holds, applies at once.)
        let current = if next_t <= t {
            let r = ahead.take();
            ahead = records.next().transpose()?;
            r
        } else {
            None
        };
        let rec = current.as_ref().map(Borrow::borrow);
        // The last record's tick ends the replay (and always has a record).
        let last = ahead.is_none();
        let recorded_drives = rec.map_or(&[][..], |r| r.drives.as_slice());
        let recorded_lost = rec.map_or(&[][..], |r| r.nodes_lost.as_slice());
        if !recorded_drives.is_empty() {
            drives = recorded_drives.to_vec();
        }
        let mut inputs = rec.map_or(none, |r| r.inputs.as_slice());
        let commands = rec.map_or(&[][..], |r| r.commands.as_slice());
        if let Some(k) = kernel.as_deref_mut() {
            for c in commands {
                if let Err(e) = k.command(t, c) {
                    refused.push(format!("tick {t}: {} refused: {e}", command_json(c)));
                }
            }
            if !recorded_lost.is_empty() {
                k.nodes_lost(t, recorded_lost);
            }
            if !drives.is_empty() {
                k.drives(t, &drives);
            }
            input_diff.before_latch(image.bytes());
            apply_masked(image.bytes_mut(), inputs, &mask);
            k.latch(t, image.packets_mut());
            ins.clear();
            input_diff.after_latch(image.bytes(), &mut ins);
            cmp.tick(t, inputs, &ins);
            pos.clear();
            tracker.diff(|v| k.positions(v), &mut pos);
            let expected = rec.map_or(&[][..], |r| r.positions.as_slice());
            pcmp.tick(t, expected, &pos);
            inputs = &ins;
        } else {
            for (s, v) in inputs {
                s.write(image.bytes_mut(), *v);
            }
        }
        if let Some(sk) = skipper.as_mut() {
            if inputs.is_empty() {
                sk.before_quiet_tick(image.bytes());
            } else {
                sk.disturbed();
            }
        }
        loaded.logic.tick(image.bytes_mut());
        let forced = rec.map_or(none, |r| r.forced.as_slice());
        for (s, v) in forced {
            s.write(image.bytes_mut(), *v);
        }
        if let (Some(sk), false) = (skipper.as_mut(), forced.is_empty()) {
            sk.disturbed();
        }
        outs.clear();
        watch.diff(image.bytes(), &mut outs);
        let expected = rec.map_or(none, |r| r.outputs.as_slice());
        cmp.tick(t, expected, &outs);
        if let Some(k) = kernel.as_deref_mut() {
            k.publish(t, image.packets());
        }
        let made = (!outs.is_empty()
            || !inputs.is_empty()
            || !forced.is_empty()
            || !pos.is_empty()
            || !commands.is_empty()
            || !recorded_drives.is_empty()
            || !recorded_lost.is_empty()
            || last)
            .then(|| TickRecord {
                t,
                inputs: inputs.to_vec(),
                outputs: outs.clone(),
                forced: forced.to_vec(),
                positions: pos.clone(),
                commands: commands.to_vec(),
                drives: recorded_drives.to_vec(),
                nodes_lost: recorded_lost.to_vec(),
            });
        if let Some(m) = &made {
            actual(m)?;
        }
        ticks = t + 1;
        let mut step = 1;
        if let Some(sk) = skipper.as_mut() {
            if !outs.is_empty() {
                sk.disturbed();
            } else if inputs.is_empty() && forced.is_empty() {
                // The ticks before the next record (the last tick always has one) carry nothing.
                let until = ahead.as_ref().map_or(t + 1, |r| r.borrow().t);
                step += sk.after_quiet_tick(image.bytes_mut(), until.saturating_sub(t + 1));
            }
        }
        let first = cmp.divergences().first().map(|d| d.t);
        window.record(t, first, current, made);
        if (t + step) >> 16 != t >> 16 {
            progress(t + step);
        }
        t += step;
    }
    Ok(Replay {
        comparator: cmp,
        ticks,
        skipped: skipper.map_or(0, |s| s.skipped()),
        image: image.bytes().to_vec(),
        positions: pcmp,
        refused,
        window: window.finish(),
    })
}

/// A recorded command as the trace writes it.
fn command_json(c: &OperatorCommand) -> String {
    serde_json::to_string(c).unwrap_or_else(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_window_holds_the_last_context_ticks_then_freezes_after_the_first_divergence() {
        let mut w: Window<TickRecord> = Window::new(3);
        for t in 0..100_000 {
            let first = (t >= 50_000).then_some(50_000);
            w.record(
                t,
                first,
                Some(TickRecord::at(t)),
                (t % 2 == 0).then(|| TickRecord::at(t)),
            );
            // Before the divergence, never more than the records of the last 4 ticks; after it,
            // of the 7 ticks around it.
            let most = if first.is_some() { 7 } else { 4 };
            assert!(
                w.expected.len() <= most && w.actual.len() <= most,
                "tick {t}"
            );
        }
        let c = w.finish();
        let ticks = |v: &[TickRecord]| v.iter().map(|r| r.t).collect::<Vec<_>>();
        assert_eq!(ticks(&c.expected), (49_997..=50_003).collect::<Vec<_>>());
        assert_eq!(ticks(&c.actual), [49_998, 50_000, 50_002]);
    }
}
