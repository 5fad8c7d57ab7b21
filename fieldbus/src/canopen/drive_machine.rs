//! The machine behind a simulated CiA 402 drive: where the drive's position 0 stands on the
//! machine's scale, the home switch and the encoder's zero impulses (one every mark pitch, at
//! its multiples on the machine's scale), in drive units.
//!
//! Invariant: a mark is met once per crossing: [`SimMachine::mark_between`] excludes the start
//! of a move and includes its end, so consecutive moves never report the same crossing twice.

/// The machine behind a simulated drive, in drive units (counts).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SimMachine {
    /// The machine position where the drive's position 0 stands.
    pub start: f64,
    /// The home switch: its edge on the machine's scale, and true when it is pressed below the
    /// edge (else at or above it).
    pub home_switch: Option<(f64, bool)>,
    /// The encoder's zero impulse every this many counts on the machine's scale (at its
    /// multiples); 0: none.
    pub mark_pitch: f64,
}

impl SimMachine {
    /// The same machine with its lengths multiplied by `k` (axis units to counts).
    pub fn scaled(self, k: f64) -> SimMachine {
        SimMachine {
            start: self.start * k,
            home_switch: self.home_switch.map(|(e, below)| (e * k, below)),
            mark_pitch: self.mark_pitch * k,
        }
    }

    /// The home switch is pressed at machine position `p`.
    pub fn pressed(&self, p: f64) -> bool {
        self.home_switch
            .is_some_and(|(edge, below)| if below { p <= edge } else { p >= edge })
    }

    /// The first zero impulse met moving from machine position `from` to `to` (excluding
    /// `from`, including `to`), if any.
    pub fn mark_between(&self, from: f64, to: f64) -> Option<f64> {
        let pitch = self.mark_pitch;
        if pitch <= 0.0 || from == to {
            return None;
        }
        let mark = if to > from {
            ((from / pitch).floor() + 1.0) * pitch
        } else {
            ((from / pitch).ceil() - 1.0) * pitch
        };
        let within = if to > from { mark <= to } else { mark >= to };
        within.then_some(mark)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mark_is_met_once_in_either_direction() {
        let m = SimMachine {
            start: -500_000.0,
            home_switch: Some((30_000.0, false)),
            mark_pitch: 50_000.0,
        };
        assert_eq!(m.mark_between(-10.0, 0.0), Some(0.0));
        assert_eq!(m.mark_between(0.0, 10.0), None);
        assert_eq!(m.mark_between(10.0, -10.0), Some(0.0));
        assert_eq!(m.mark_between(120_000.0, 20_000.0), Some(100_000.0));
        assert_eq!(m.mark_between(-49_999.0, 149_000.0), Some(0.0));
        assert_eq!(m.mark_between(1.0, 49_999.0), None);
        assert!(m.pressed(30_000.0) && !m.pressed(29_999.0));
        let s = m.scaled(0.5);
        assert_eq!(
            (s.start, s.home_switch, s.mark_pitch),
            (-250_000.0, Some((15_000.0, false)), 25_000.0)
        );
    }
}
