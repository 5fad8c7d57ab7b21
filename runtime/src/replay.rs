//! Replaying a trace: re-apply its inputs in virtual time and compare the outputs.
//!
//! Replay starts from a fresh image (packet T from the configuration, no retained data), writes
//! each record's inputs at the start of its tick, scans, and diffs the written signals, exactly as
//! `ncplc run --record` produced them. With [`ReplayOptions::skip_idle`] the stretches in which
//! nothing can happen are jumped over ([`crate::idle_skip`]) with the same records as a
//! tick-by-tick replay; the outputs are diffed through [`crate::output_watch`].

use crate::idle_skip::IdleSkipper;
use crate::image::Image;
use crate::output_watch::OutputWatch;
use crate::program::Loaded;
use crate::trace::compare::{Comparator, report};
use crate::trace::{TickRecord, Trace};

/// The result of a replay.
#[derive(Debug)]
pub struct Replay {
    /// Output comparison.
    pub comparator: Comparator,
    /// What the replay produced: the trace's inputs with the replay's outputs, one record per tick
    /// with changes (the `--update` form of the trace, which also keeps the end marker).
    pub actual: Trace,
    /// Ticks jumped over as idle (0 for a tick-by-tick replay).
    pub skipped: u64,
    /// The image after the last tick.
    pub image: Vec<u8>,
}

impl Replay {
    /// True when the outputs are identical.
    pub fn identical(&self) -> bool {
        self.comparator.identical()
    }

    /// The divergence report, with `context` ticks around the first divergence.
    pub fn report(&self, expected: &Trace, context: u64) -> String {
        report(
            &self.comparator,
            &expected.ticks,
            &self.actual.ticks,
            context,
        )
    }
}

/// How a replay runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ReplayOptions {
    /// Jump over idle ticks ([`crate::idle_skip`]); the records are the same as tick by tick.
    pub skip_idle: bool,
    /// The replay also drives a CNC kernel (a trace of `ncplc run --program`): axes move in ticks
    /// that leave the PLC image unchanged, so no tick is ever skipped.
    pub drives_kernel: bool,
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
    mut loaded: Loaded,
    t_init: &[u8],
    options: ReplayOptions,
    mut progress: impl FnMut(u64),
) -> Replay {
    let mut image = Image::new(loaded.meta.image_len(), t_init);
    loaded.meta.init_image(image.bytes_mut());
    let mut watch = OutputWatch::new(&loaded.meta.written_signals());
    let mut skipper = loaded
        .meta
        .idle_facts()
        .filter(|_| options.skips())
        .map(|f| IdleSkipper::new(&f, image.bytes().len()));
    let mut cmp = Comparator::new(20);
    let mut actual = Trace {
        tick_ms: trace.tick_ms,
        ticks: Vec::new(),
    };
    let mut outs = Vec::new();
    let mut next = trace.ticks.iter().peekable();
    let total = trace.len_ticks();
    let none: &[(packets::Signal, u8)] = &[];
    let mut t = 0;
    while t < total {
        let rec = next.next_if(|r| r.t == t);
        let inputs = rec.map_or(none, |r| r.inputs.as_slice());
        for (s, v) in inputs {
            s.write(image.bytes_mut(), *v);
        }
        if let Some(sk) = skipper.as_mut() {
            if inputs.is_empty() {
                sk.before_quiet_tick(image.bytes());
            } else {
                sk.disturbed();
            }
        }
        loaded.logic.tick(image.bytes_mut());
        outs.clear();
        watch.diff(image.bytes(), &mut outs);
        let expected = rec.map_or(none, |r| r.outputs.as_slice());
        cmp.tick(t, expected, &outs);
        if !outs.is_empty() || !inputs.is_empty() || t + 1 == total {
            actual.ticks.push(TickRecord {
                t,
                inputs: inputs.to_vec(),
                outputs: outs.clone(),
            });
        }
        let mut step = 1;
        if let Some(sk) = skipper.as_mut() {
            if !outs.is_empty() {
                sk.disturbed();
            } else if inputs.is_empty() {
                // The ticks before the next record (the last tick always has one) carry nothing.
                let until = next.peek().map_or(total, |r| r.t);
                step += sk.after_quiet_tick(image.bytes_mut(), until.saturating_sub(t + 1));
            }
        }
        if (t + step) >> 16 != t >> 16 {
            progress(t + step);
        }
        t += step;
    }
    Replay {
        comparator: cmp,
        actual,
        skipped: skipper.map_or(0, |s| s.skipped()),
        image: image.bytes().to_vec(),
    }
}
