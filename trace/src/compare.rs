//! Comparing a replay's outputs with a trace's expectations, and the divergence report.
//!
//! Both sides are delta records; the comparator keeps each side's current value per signal and
//! checks, at every tick where either side changed a signal, whether the two values agree. A signal
//! is reported when it starts to differ (not again while it keeps differing).

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use packets::Signal;

use super::{SignalValue, TickRecord, text::format_record};

/// One point where the replay departs from the trace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Divergence {
    /// The tick.
    pub t: u64,
    /// The signal.
    pub signal: Signal,
    /// The trace's value at the end of the tick.
    pub expected: u8,
    /// The replay's value at the end of the tick.
    pub actual: u8,
}

/// Incremental output comparison.
#[derive(Debug, Default)]
pub struct Comparator {
    expected: HashMap<Signal, u8>,
    actual: HashMap<Signal, u8>,
    open: HashSet<Signal>,
    first: Vec<Divergence>,
    keep: usize,
    total: u64,
}

impl Comparator {
    /// A comparator that keeps the first `keep` divergences.
    pub fn new(keep: usize) -> Comparator {
        Comparator {
            keep,
            ..Comparator::default()
        }
    }

    /// Compares tick `t`: the trace's output changes and the replay's.
    pub fn tick(&mut self, t: u64, expected: &[SignalValue], actual: &[SignalValue]) {
        if expected.is_empty() && actual.is_empty() {
            return;
        }
        for &(s, v) in expected {
            self.expected.insert(s, v);
        }
        for &(s, v) in actual {
            self.actual.insert(s, v);
        }
        for &(s, _) in expected.iter().chain(actual) {
            let e = self.expected.get(&s).copied().unwrap_or(0);
            let a = self.actual.get(&s).copied().unwrap_or(0);
            if e == a {
                self.open.remove(&s);
            } else if self.open.insert(s) {
                self.total += 1;
                if self.first.len() < self.keep {
                    self.first.push(Divergence {
                        t,
                        signal: s,
                        expected: e,
                        actual: a,
                    });
                }
            }
        }
    }

    /// True when nothing diverged.
    pub fn identical(&self) -> bool {
        self.total == 0
    }

    /// The first divergences, in tick order.
    pub fn divergences(&self) -> &[Divergence] {
        &self.first
    }

    /// How many divergences there were in all.
    pub fn total(&self) -> u64 {
        self.total
    }
}

/// A readable report: the first divergences, then the trace's and the replay's records around the
/// first one (`context` ticks before and after).
pub fn report(
    cmp: &Comparator,
    expected: &[TickRecord],
    actual: &[TickRecord],
    context: u64,
) -> String {
    let mut s = String::new();
    let Some(first) = cmp.divergences().first() else {
        return "outputs identical\n".into();
    };
    let _ = writeln!(
        s,
        "replay diverges from the trace ({} divergence(s)); first ones:",
        cmp.total()
    );
    let _ = writeln!(
        s,
        "  {:>8}  {:<8}  {:>8}  {:>8}",
        "tick", "signal", "expected", "actual"
    );
    for d in cmp.divergences() {
        let _ = writeln!(
            s,
            "  {:>8}  {:<8}  {:>8}  {:>8}",
            d.t,
            d.signal.to_string(),
            d.expected,
            d.actual
        );
    }
    let lo = first.t.saturating_sub(context);
    let hi = first.t.saturating_add(context);
    let window = |recs: &[TickRecord]| -> Vec<String> {
        let mut line = String::new();
        recs.iter()
            .filter(|r| r.t >= lo && r.t <= hi)
            .map(|r| {
                format_record(r, &mut line);
                line.clone()
            })
            .collect()
    };
    let _ = writeln!(s, "context, ticks {lo}..={hi}:");
    let _ = writeln!(s, "  trace (expected):");
    for l in window(expected) {
        let _ = writeln!(s, "    {l}");
    }
    let _ = writeln!(s, "  replay (actual):");
    for l in window(actual) {
        let _ = writeln!(s, "    {l}");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sig(s: &str) -> Signal {
        s.parse().expect("signal")
    }

    #[test]
    fn divergence_is_reported_once_until_it_heals() {
        let mut c = Comparator::new(10);
        c.tick(0, &[(sig("U4A0"), 1)], &[(sig("U4A0"), 1)]);
        assert!(c.identical());
        c.tick(3, &[(sig("U4A0"), 0)], &[]);
        c.tick(4, &[], &[(sig("U4A1"), 1)]);
        c.tick(5, &[], &[(sig("U4A0"), 0)]);
        c.tick(6, &[(sig("U4A0"), 1)], &[]);
        assert_eq!(
            c.divergences(),
            &[
                Divergence {
                    t: 3,
                    signal: sig("U4A0"),
                    expected: 0,
                    actual: 1
                },
                Divergence {
                    t: 4,
                    signal: sig("U4A1"),
                    expected: 0,
                    actual: 1
                },
                Divergence {
                    t: 6,
                    signal: sig("U4A0"),
                    expected: 1,
                    actual: 0
                },
            ]
        );
        assert_eq!(c.total(), 3);
    }

    #[test]
    fn report_shows_the_first_divergence_and_context() {
        let mut c = Comparator::new(10);
        let exp = vec![TickRecord {
            nodes_lost: Vec::new(),
            commands: Vec::new(),
            drives: Vec::new(),
            t: 2,
            inputs: vec![(sig("I0A0"), 1)],
            outputs: vec![(sig("U4A0"), 1)],
            forced: vec![],
            positions: Vec::new(),
        }];
        let act = vec![TickRecord {
            nodes_lost: Vec::new(),
            commands: Vec::new(),
            drives: Vec::new(),
            t: 3,
            inputs: vec![],
            outputs: vec![(sig("U4A0"), 1)],
            forced: vec![],
            positions: Vec::new(),
        }];
        c.tick(2, &exp[0].outputs, &[]);
        c.tick(3, &[], &act[0].outputs);
        let r = report(&c, &exp, &act, 2);
        assert_eq!(
            r,
            "replay diverges from the trace (1 divergence(s)); first ones:\n\
             \x20     tick  signal    expected    actual\n\
             \x20        2  U4A0             1         0\n\
             context, ticks 0..=4:\n\
             \x20 trace (expected):\n\
             \x20   {\"t\":2,\"in\":{\"I0A0\":1},\"out\":{\"U4A0\":1}}\n\
             \x20 replay (actual):\n\
             \x20   {\"t\":3,\"out\":{\"U4A0\":1}}\n"
        );
    }
}
