//! The replay's output diff, touching only what changed.
//!
//! [`OutputTracker`] walks every written byte each tick. Written signals all lie in the packets,
//! so [`OutputWatch`] keeps a shadow of the span of image bytes that holds them and compares that
//! span as one slice (a `memcmp`); only when it differs (an input or an output changed) does the
//! tracker walk its bytes. The records are exactly the tracker's.

use packets::Signal;

use trace::SignalValue;
use trace::recorder::OutputTracker;

/// An [`OutputTracker`] behind a whole-span equality check.
#[derive(Debug, Clone)]
pub struct OutputWatch {
    tracker: OutputTracker,
    start: usize,
    /// The span's bytes at the last walk (zero before tick 0, like the tracker's values).
    shadow: Vec<u8>,
}

impl OutputWatch {
    /// A watch over `written` (the program's written signals).
    pub fn new(written: &[Signal]) -> OutputWatch {
        let start = written.iter().map(Signal::image_byte).min().unwrap_or(0);
        let end = written
            .iter()
            .map(|s| s.image_byte() + 1)
            .max()
            .unwrap_or(0);
        OutputWatch {
            tracker: OutputTracker::new(written),
            start,
            shadow: vec![0; end.saturating_sub(start)],
        }
    }

    /// Appends the written signals whose value changed since the last call (as
    /// [`OutputTracker::diff`] does).
    pub fn diff(&mut self, image: &[u8], out: &mut Vec<SignalValue>) {
        let span = self.start..self.start + self.shadow.len();
        match image.get(span) {
            Some(now) if now == self.shadow.as_slice() => {}
            Some(now) => {
                self.shadow.copy_from_slice(now);
                self.tracker.diff(image, out);
            }
            None => self.tracker.diff(image, out),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit::sig;

    #[test]
    fn reports_what_the_tracker_reports_and_nothing_for_input_only_changes() {
        let written = [sig("U4A0"), sig("U4A9"), sig("W100K2")];
        let mut watch = OutputWatch::new(&written);
        let mut image = vec![0u8; packets::PACKETS_LEN];
        let mut out = Vec::new();
        watch.diff(&image, &mut out);
        assert!(out.is_empty());
        sig("U4A9").write(&mut image, 1);
        sig("W100K2").write(&mut image, 7);
        watch.diff(&image, &mut out);
        assert_eq!(out, vec![(sig("U4A9"), 1), (sig("W100K2"), 7)]);
        out.clear();
        // An input inside the watched span changes: the tracker runs and finds no output.
        sig("I5A3").write(&mut image, 1);
        watch.diff(&image, &mut out);
        assert!(out.is_empty());
        sig("U4A9").write(&mut image, 0);
        watch.diff(&image, &mut out);
        assert_eq!(out, vec![(sig("U4A9"), 0)]);
    }
}
