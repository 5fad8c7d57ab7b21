//! The publisher's stage of the tick-to-client latency, for the latency bench (cargo feature
//! `latency`: `cargo build --release -p ncplc --features opcua-server/latency`): for every frame,
//! the time from the scan's copy (the frame's wall-clock stamp, the values' server timestamp) to
//! the moment the publisher has set its values — which is also when the stack has sampled them,
//! since `set_values` hands every changed value to its monitored items' queues at once. A
//! histogram of 0.1 ms buckets (the last one open), printed on stderr when the server stops:
//! `opcua: latency apply: N frames, p50 … ms, p99 … ms, max … ms`.
//!
//! **Invariant:** fixed memory whatever the run's length; without the feature nothing is recorded
//! and nothing printed (the publisher calls [`Stages::applied`], which is empty then).

/// Bucket width in µs.
#[cfg(feature = "latency")]
const BUCKET_US: i64 = 100;
/// Buckets (the last holds everything from 100 ms on).
#[cfg(feature = "latency")]
const BUCKETS: usize = 1001;

/// The publisher's stage recorder.
#[derive(Debug, Default)]
pub struct Stages {
    /// Frames per bucket (`BUCKETS` of them from the first frame on).
    #[cfg(feature = "latency")]
    counts: Vec<u64>,
    #[cfg(feature = "latency")]
    max_us: i64,
}

/// µs since the Unix epoch, now.
#[cfg(feature = "latency")]
fn now_us() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_micros()).unwrap_or(i64::MAX))
}

impl Stages {
    /// The frame copied at `wall_us` (µs since the Unix epoch) has been applied now.
    #[cfg_attr(not(feature = "latency"), allow(unused_variables))]
    pub fn applied(&mut self, wall_us: i64) {
        #[cfg(feature = "latency")]
        self.record(now_us().saturating_sub(wall_us));
    }

    /// Counts one delay of `us` µs.
    #[cfg(feature = "latency")]
    pub fn record(&mut self, us: i64) {
        let us = us.max(0);
        if self.counts.is_empty() {
            self.counts = vec![0; BUCKETS];
        }
        let at = usize::try_from(us / BUCKET_US).map_or(BUCKETS - 1, |i| i.min(BUCKETS - 1));
        if let Some(c) = self.counts.get_mut(at) {
            *c += 1;
        }
        self.max_us = self.max_us.max(us);
    }

    /// The frames counted, and the upper edge in ms of the bucket holding quantile `q`.
    #[cfg(feature = "latency")]
    pub fn quantile_ms(&self, q: f64) -> (u64, f64) {
        let n: u64 = self.counts.iter().sum();
        // The sample of index ⌊q n⌋ (0-based), as the bench script takes its percentiles.
        let want = (q * n as f64) as u64;
        let mut below = 0u64;
        for (i, c) in self.counts.iter().enumerate() {
            below += c;
            if below > want {
                return (n, ((i as i64 + 1) * BUCKET_US) as f64 / 1e3);
            }
        }
        (n, self.max_us as f64 / 1e3)
    }

    /// The summary line.
    #[cfg(feature = "latency")]
    pub fn summary(&self) -> String {
        let (n, p50) = self.quantile_ms(0.5);
        let (_, p99) = self.quantile_ms(0.99);
        format!(
            "opcua: latency apply: {n} frames, p50 {p50:.1} ms, p99 {p99:.1} ms, max {:.1} ms",
            self.max_us as f64 / 1e3
        )
    }
}

#[cfg(feature = "latency")]
impl Drop for Stages {
    fn drop(&mut self) {
        eprintln!("{}", self.summary());
    }
}

#[cfg(all(test, feature = "latency"))]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_bucket_edges_and_the_max_is_exact() {
        let mut s = Stages::default();
        // 98 frames at 0.05 ms, one at 1.25 ms, one at 250 ms (past the last edge).
        for _ in 0..98 {
            s.record(50);
        }
        s.record(1_250);
        s.record(250_000);
        assert_eq!(s.quantile_ms(0.5), (100, 0.1));
        // Index 99 of 100 (⌊0.99 × 100⌋) is the 250 ms frame, in the open last bucket.
        assert_eq!(s.quantile_ms(0.99), (100, 100.1));
        assert_eq!(s.quantile_ms(0.98), (100, 1.3));
        assert_eq!(
            s.summary(),
            "opcua: latency apply: 100 frames, p50 0.1 ms, p99 100.1 ms, max 250.0 ms"
        );
        std::mem::forget(s);
    }
}
