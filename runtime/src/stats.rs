//! Scan-time and wake-latency histograms and the overrun counters, plus their text forms.

use hdrhistogram::Histogram;

/// Timing statistics of a run (all times in nanoseconds).
#[derive(Debug, Clone)]
pub struct Stats {
    /// Time from waking to the end of the tick (latch, scan, publish).
    pub scan: Histogram<u64>,
    /// How late the loop woke after the tick's start time.
    pub wake: Histogram<u64>,
    /// Ticks run.
    pub ticks: u64,
    /// The last tick's scan time (what an HMI samples).
    pub last_scan_ns: u64,
    /// Ticks that ended past their deadline.
    pub overruns: u64,
    /// Current run of consecutive overruns.
    pub consecutive_overruns: u32,
    /// The longest run of consecutive overruns.
    pub max_consecutive_overruns: u32,
}

impl Default for Stats {
    fn default() -> Self {
        Stats::new()
    }
}

fn histogram() -> Histogram<u64> {
    // 1 ns .. 100 s with 3 significant digits; these bounds are always valid.
    Histogram::new_with_bounds(1, 100_000_000_000, 3)
        .unwrap_or_else(|_| Histogram::new(3).unwrap_or_else(|_| unreachable!()))
}

impl Stats {
    /// Empty statistics.
    pub fn new() -> Stats {
        Stats {
            scan: histogram(),
            wake: histogram(),
            ticks: 0,
            last_scan_ns: 0,
            overruns: 0,
            consecutive_overruns: 0,
            max_consecutive_overruns: 0,
        }
    }

    /// Records one tick; returns the current number of consecutive overruns.
    pub fn tick(&mut self, wake_ns: u64, scan_ns: u64, overrun: bool) -> u32 {
        self.ticks += 1;
        self.last_scan_ns = scan_ns;
        self.wake.saturating_record(wake_ns.max(1));
        self.scan.saturating_record(scan_ns.max(1));
        if overrun {
            self.overruns += 1;
            self.consecutive_overruns += 1;
            self.max_consecutive_overruns =
                self.max_consecutive_overruns.max(self.consecutive_overruns);
        } else {
            self.consecutive_overruns = 0;
        }
        self.consecutive_overruns
    }

    /// Multi-line summary: tick count, overruns and p50/p99/p99.9/max of both histograms in µs.
    pub fn summary(&self) -> String {
        let line = |name: &str, h: &Histogram<u64>| {
            format!(
                "{name:<14} p50 {:>9.2} µs  p99 {:>9.2} µs  p99.9 {:>9.2} µs  max {:>9.2} µs\n",
                h.value_at_quantile(0.5) as f64 / 1e3,
                h.value_at_quantile(0.99) as f64 / 1e3,
                h.value_at_quantile(0.999) as f64 / 1e3,
                h.max() as f64 / 1e3,
            )
        };
        let mut s = format!(
            "ticks {}  overruns {} (longest run {})\n",
            self.ticks, self.overruns, self.max_consecutive_overruns
        );
        s.push_str(&line("wake latency", &self.wake));
        s.push_str(&line("scan time", &self.scan));
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overruns_count_and_reset() {
        let mut s = Stats::new();
        assert_eq!(s.tick(10, 100, true), 1);
        assert_eq!(s.tick(10, 100, true), 2);
        assert_eq!(s.tick(10, 100, false), 0);
        assert_eq!(s.tick(10, 100, true), 1);
        assert_eq!((s.ticks, s.overruns, s.max_consecutive_overruns), (4, 3, 2));
        assert_eq!(s.scan.max(), 100);
        assert!(
            s.summary()
                .starts_with("ticks 4  overruns 3 (longest run 2)\n")
        );
    }
}
