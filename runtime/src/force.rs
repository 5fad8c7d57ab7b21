//! HMI writes and forces with CODESYS semantics: a *write* goes into the image once, before the
//! next scan, and the program may overwrite it; a *force* goes into the image before **and** after
//! every scan until it is removed, so the outputs always publish the forced value.
//!
//! The scheduler applies the writes and the before-scan forces right after the input latch, where
//! the trace recorder sees them as inputs; the after-scan forces that changed the image are handed
//! back so that the recorder can keep them (the trace's `forced`), and a replay stays exact.

use packets::Signal;

use trace::SignalValue;

/// The force table and the pending one-shot writes.
#[derive(Debug, Clone, Default)]
pub struct Forces {
    /// Active forces, one per storage bit/byte, in image order.
    table: Vec<SignalValue>,
    /// Writes waiting for the next scan, in arrival order.
    pending: Vec<SignalValue>,
}

/// The order of the table: image byte, then bit (the byte itself last).
fn key(s: &Signal) -> (usize, u8) {
    (s.image_byte(), s.bit().unwrap_or(8))
}

impl Forces {
    /// Writes `value` into `signal` once, before the next scan.
    pub fn write_once(&mut self, signal: Signal, value: u8) {
        self.pending.push((signal, value));
    }

    /// Forces `signal` to `value` (replacing an earlier force of the same storage).
    pub fn force(&mut self, signal: Signal, value: u8) {
        match self
            .table
            .binary_search_by_key(&key(&signal), |(s, _)| key(s))
        {
            Ok(i) => self.table[i] = (signal, value),
            Err(i) => self.table.insert(i, (signal, value)),
        }
    }

    /// Removes the force of `signal`'s storage; false when it was not forced.
    pub fn unforce(&mut self, signal: &Signal) -> bool {
        match self
            .table
            .binary_search_by_key(&key(signal), |(s, _)| key(s))
        {
            Ok(i) => {
                self.table.remove(i);
                true
            }
            Err(_) => false,
        }
    }

    /// Removes every force; returns how many there were.
    pub fn unforce_all(&mut self) -> usize {
        let n = self.table.len();
        self.table.clear();
        n
    }

    /// The active forces, in image order.
    pub fn forced(&self) -> &[SignalValue] {
        &self.table
    }

    /// Before the scan: the pending writes (then forgotten), then every force.
    pub fn apply_before(&mut self, image: &mut [u8]) {
        for (s, v) in self.pending.drain(..) {
            s.write(image, v);
        }
        for (s, v) in &self.table {
            s.write(image, *v);
        }
    }

    /// After the scan: every force; those the logic had changed are appended to `changed`.
    pub fn apply_after(&self, image: &mut [u8], changed: &mut Vec<SignalValue>) {
        for (s, v) in &self.table {
            if s.read(image) != *v {
                s.write(image, *v);
                changed.push((*s, *v));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sig(s: &str) -> Signal {
        s.parse().expect("signal")
    }

    #[test]
    fn a_write_applies_once_and_a_force_before_and_after_every_scan() {
        let mut f = Forces::default();
        let mut img = vec![0u8; packets::PACKETS_LEN];
        f.write_once(sig("I0A3"), 1);
        f.force(sig("U4A0"), 1);
        f.apply_before(&mut img);
        assert_eq!((sig("I0A3").read(&img), sig("U4A0").read(&img)), (1, 1));
        // The "logic" clears both; after the scan only the force comes back, and is reported.
        sig("I0A3").write(&mut img, 0);
        sig("U4A0").write(&mut img, 0);
        let mut changed = Vec::new();
        f.apply_after(&mut img, &mut changed);
        assert_eq!(changed, vec![(sig("U4A0"), 1)]);
        assert_eq!((sig("I0A3").read(&img), sig("U4A0").read(&img)), (0, 1));
        // Next scan: the write is gone, the force stays; an unchanged force is not reported.
        f.apply_before(&mut img);
        assert_eq!(sig("I0A3").read(&img), 0);
        changed.clear();
        f.apply_after(&mut img, &mut changed);
        assert!(changed.is_empty());
    }

    #[test]
    fn forces_are_kept_per_storage_in_image_order() {
        let mut f = Forces::default();
        f.force(sig("W14K0"), 80);
        f.force(sig("U4A0"), 1);
        f.force(sig("I4A0"), 0); // same storage as U4A0: replaces it
        assert_eq!(f.forced(), &[(sig("I4A0"), 0), (sig("W14K0"), 80)]);
        assert!(f.unforce(&sig("U4A0")));
        assert!(!f.unforce(&sig("U4A0")));
        assert_eq!(f.unforce_all(), 1);
        assert!(f.forced().is_empty());
    }
}
