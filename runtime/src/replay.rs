//! Replaying a trace: re-apply its inputs in virtual time and compare the outputs.
//!
//! Replay starts from a fresh image (packet T from the configuration, no retained data), writes
//! each record's inputs at the start of its tick, scans, and diffs the written signals, exactly as
//! `ncplc run --record` produced them. Values an HMI force put back after the scan (`forced`) are
//! written after the replay's scan too.

use crate::image::Image;
use crate::program::Loaded;
use crate::trace::compare::{Comparator, report};
use crate::trace::recorder::OutputTracker;
use crate::trace::{TickRecord, Trace};

/// The result of a replay.
#[derive(Debug)]
pub struct Replay {
    /// Output comparison.
    pub comparator: Comparator,
    /// What the replay produced: the trace's inputs with the replay's outputs, one record per tick
    /// with changes (the `--update` form of the trace, which also keeps the end marker).
    pub actual: Trace,
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

/// Replays `trace` through `loaded`, starting from packet T = `t_init`; `progress` is called every
/// 65,536 ticks with the ticks done.
pub fn replay(
    trace: &Trace,
    mut loaded: Loaded,
    t_init: &[u8],
    mut progress: impl FnMut(u64),
) -> Replay {
    let mut image = Image::new(loaded.meta.image_len(), t_init);
    loaded.meta.init_image(image.bytes_mut());
    let mut tracker = OutputTracker::new(&loaded.meta.written_signals());
    let mut cmp = Comparator::new(20);
    let mut actual = Trace {
        tick_ms: trace.tick_ms,
        ticks: Vec::new(),
    };
    let mut outs = Vec::new();
    let mut next = trace.ticks.iter().peekable();
    let total = trace.len_ticks();
    let none: &[(packets::Signal, u8)] = &[];
    for t in 0..total {
        let rec = next.next_if(|r| r.t == t);
        if let Some(r) = rec {
            for (s, v) in &r.inputs {
                s.write(image.bytes_mut(), *v);
            }
        }
        loaded.logic.tick(image.bytes_mut());
        let forced = rec.map_or(none, |r| r.forced.as_slice());
        for (s, v) in forced {
            s.write(image.bytes_mut(), *v);
        }
        outs.clear();
        tracker.diff(image.bytes(), &mut outs);
        let expected = rec.map_or(none, |r| r.outputs.as_slice());
        cmp.tick(t, expected, &outs);
        let inputs = rec.map_or(none, |r| r.inputs.as_slice());
        if !outs.is_empty() || !inputs.is_empty() || !forced.is_empty() || t + 1 == total {
            actual.ticks.push(TickRecord {
                t,
                inputs: inputs.to_vec(),
                outputs: outs.clone(),
                forced: forced.to_vec(),
            });
        }
        if t & 0xffff == 0xffff {
            progress(t + 1);
        }
    }
    Replay {
        comparator: cmp,
        actual,
    }
}
