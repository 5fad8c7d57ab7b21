//! Axis positions in a part-run trace: the recorder's per-tick diff (an axis is written when its
//! f64 bits changed; the first tick writes every axis) and the replay's exact comparison.

use std::collections::BTreeMap;

use super::{AxisId, AxisValue};

/// Fills a list with every axis and its position bits (the kernel's drives, after its step).
pub type PositionSource = Box<dyn FnMut(&mut Vec<AxisValue>) + Send>;

/// Remembers the positions of the previous tick.
#[derive(Debug, Clone, Default)]
pub struct PositionTracker {
    prev: Vec<AxisValue>,
    cur: Vec<AxisValue>,
    started: bool,
}

impl PositionTracker {
    /// Appends to `out` the axes of `fill`'s list whose bits differ from the previous call (all of
    /// them the first time), in axis order.
    pub fn diff(&mut self, fill: impl FnOnce(&mut Vec<AxisValue>), out: &mut Vec<AxisValue>) {
        self.cur.clear();
        fill(&mut self.cur);
        self.cur.sort_by_key(|(a, _)| *a);
        for (i, &(a, bits)) in self.cur.iter().enumerate() {
            let same = self.started && self.prev.get(i) == Some(&(a, bits));
            if !same {
                out.push((a, bits));
            }
        }
        std::mem::swap(&mut self.prev, &mut self.cur);
        self.started = true;
    }
}

/// A point where the replay's axis position departs from the trace's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PositionDivergence {
    /// The tick.
    pub t: u64,
    /// The axis.
    pub axis: AxisId,
    /// The trace's position (mm or degrees).
    pub expected: f64,
    /// The replay's position.
    pub actual: f64,
}

/// Compares position changes tick by tick (like [`super::compare::Comparator`]: an axis is reported
/// when it starts to differ, not again while it keeps differing).
#[derive(Debug, Default)]
pub struct PositionComparator {
    expected: BTreeMap<AxisId, u64>,
    actual: BTreeMap<AxisId, u64>,
    open: Vec<AxisId>,
    first: Vec<PositionDivergence>,
    keep: usize,
    total: u64,
}

impl PositionComparator {
    /// A comparator that keeps the first `keep` divergences.
    pub fn new(keep: usize) -> PositionComparator {
        PositionComparator {
            keep,
            ..PositionComparator::default()
        }
    }

    /// Compares tick `t`: the trace's position changes and the replay's.
    pub fn tick(&mut self, t: u64, expected: &[AxisValue], actual: &[AxisValue]) {
        if expected.is_empty() && actual.is_empty() {
            return;
        }
        for &(a, v) in expected {
            self.expected.insert(a, v);
        }
        for &(a, v) in actual {
            self.actual.insert(a, v);
        }
        for &(a, _) in expected.iter().chain(actual) {
            let e = self.expected.get(&a).copied();
            let g = self.actual.get(&a).copied();
            if e == g {
                self.open.retain(|o| *o != a);
            } else if !self.open.contains(&a) {
                self.open.push(a);
                self.total += 1;
                if self.first.len() < self.keep {
                    let f = |v: Option<u64>| v.map_or(f64::NAN, f64::from_bits);
                    self.first.push(PositionDivergence {
                        t,
                        axis: a,
                        expected: f(e),
                        actual: f(g),
                    });
                }
            }
        }
    }

    /// True when every position agreed.
    pub fn identical(&self) -> bool {
        self.total == 0
    }

    /// The first divergences, in tick order.
    pub fn divergences(&self) -> &[PositionDivergence] {
        &self.first
    }

    /// How many divergences there were in all.
    pub fn total(&self) -> u64 {
        self.total
    }

    /// The divergences as a table (`tick axis expected actual`), empty when identical.
    pub fn report(&self) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        if self.identical() {
            return s;
        }
        let _ = writeln!(
            s,
            "axis positions diverge from the trace ({} divergence(s)); first ones:",
            self.total
        );
        let _ = writeln!(
            s,
            "  {:>8}  {:<4}  {:>24}  {:>24}",
            "tick", "axis", "expected", "actual"
        );
        for d in &self.first {
            let _ = writeln!(
                s,
                "  {:>8}  {:<4}  {:>24}  {:>24}",
                d.t,
                d.axis.to_string(),
                format!("{:?}", d.expected),
                format!("{:?}", d.actual)
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ax(s: &str) -> AxisId {
        s.parse().expect("axis")
    }

    #[test]
    fn the_first_tick_writes_every_axis_then_only_changes() {
        let mut t = PositionTracker::default();
        let mut out = Vec::new();
        let x = ax("1X");
        let z = ax("1Z");
        t.diff(|v| v.extend([(z, 0), (x, 0)]), &mut out);
        assert_eq!(out, vec![(x, 0), (z, 0)]);
        out.clear();
        t.diff(|v| v.extend([(x, 0), (z, 0)]), &mut out);
        assert!(out.is_empty());
        t.diff(|v| v.extend([(x, 0), (z, 1.5f64.to_bits())]), &mut out);
        assert_eq!(out, vec![(z, 1.5f64.to_bits())]);
    }

    #[test]
    fn a_one_ulp_difference_is_a_divergence_reported_once() {
        let x = ax("1X");
        let a = 2.0f64;
        let b = f64::from_bits(a.to_bits() + 1);
        let mut c = PositionComparator::new(5);
        c.tick(0, &[(x, a.to_bits())], &[(x, a.to_bits())]);
        assert!(c.identical());
        c.tick(4, &[], &[(x, b.to_bits())]);
        c.tick(5, &[], &[(x, 3.0f64.to_bits())]);
        c.tick(6, &[(x, 3.0f64.to_bits())], &[]);
        assert_eq!(
            c.divergences(),
            &[PositionDivergence {
                t: 4,
                axis: x,
                expected: 2.0,
                actual: b
            }]
        );
        assert_eq!(
            c.report(),
            "axis positions diverge from the trace (1 divergence(s)); first ones:\n\
             \x20     tick  axis                  expected                    actual\n\
             \x20        4  1X                         2.0        2.0000000000000004\n"
        );
        assert!("6X".parse::<AxisId>().is_err());
        assert!("1x".parse::<AxisId>().is_err());
    }
}
