//! The CNC side of the M/S/T four-phase handshake (docs/plc-interface-map.md §2).
//!
//! 1. the CNC writes the code, and in the next image sets the strobe;
//! 2. the logic sets FIN; 3. the CNC sees FIN = 1 and clears the strobe;
//! 4. the logic clears FIN; the CNC sends the next function only after it saw FIN = 0.
//!
//! A strobe not answered within the timeout raises one alarm naming the function; a general reset
//! clears the strobe and forgets the queued functions.

use std::collections::VecDeque;

/// Which strobe a function uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// Miscellaneous function, MCODE in BCD.
    M,
    /// Spindle speed, SCODE binary.
    S,
    /// Tool number, TCODE in 8-decade BCD.
    T,
}

impl Kind {
    /// The function's name as the operator sees it (`M03`, `S1200`, `T5`).
    pub fn name(self, code: u32) -> String {
        match self {
            Kind::M => format!("M{code:02}"),
            Kind::S => format!("S{code}"),
            Kind::T => format!("T{code}"),
        }
    }
}

/// The phase of one strobe channel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Nothing in progress.
    Idle,
    /// The code is written; the strobe rises in the next image.
    CodeWritten {
        /// The function's code.
        code: u32,
    },
    /// The strobe is up, waiting for FIN.
    Strobe {
        /// The function's code.
        code: u32,
        /// Tick at which the strobe rose.
        since: u64,
        /// The timeout alarm was raised.
        alarmed: bool,
    },
    /// The strobe is down, waiting for FIN = 0.
    WaitFinLow,
}

/// What the channel drives this tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Drive {
    /// The code to present, when one is presented.
    pub code: Option<u32>,
    /// The strobe.
    pub strobe: bool,
}

/// One strobe channel (M, S or T).
#[derive(Debug, Clone)]
pub struct Channel {
    kind: Kind,
    timeout_ticks: u64,
    queue: VecDeque<u32>,
    phase: Phase,
    /// Completed functions (for tests and status).
    pub done: u64,
}

/// A handshake message for the operator.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Note {
    /// The strobe was not answered in time.
    Timeout(String),
    /// A late FIN arrived for a function that had timed out.
    Recovered(String),
}

impl Channel {
    /// A channel whose strobes time out after `timeout_ticks` (0: never).
    pub fn new(kind: Kind, timeout_ticks: u64) -> Channel {
        Channel {
            kind,
            timeout_ticks,
            queue: VecDeque::new(),
            phase: Phase::Idle,
            done: 0,
        }
    }

    /// Queues a function.
    pub fn issue(&mut self, code: u32) {
        self.queue.push_back(code);
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// True when nothing is queued or in progress.
    pub fn idle(&self) -> bool {
        self.phase == Phase::Idle && self.queue.is_empty()
    }

    /// Advances one tick: `fin` is the logic's FIN from the last published outputs, `reset` the
    /// general reset. Returns what to drive and possibly a note for the operator.
    pub fn step(&mut self, tick: u64, fin: bool, reset: bool) -> (Drive, Option<Note>) {
        if reset {
            self.queue.clear();
            self.phase = Phase::Idle;
            return (
                Drive {
                    code: None,
                    strobe: false,
                },
                None,
            );
        }
        let mut note = None;
        self.phase = match self.phase {
            Phase::Idle => match self.queue.pop_front() {
                Some(code) => Phase::CodeWritten { code },
                None => Phase::Idle,
            },
            Phase::CodeWritten { code } => Phase::Strobe {
                code,
                since: tick,
                alarmed: false,
            },
            Phase::Strobe {
                code,
                since,
                alarmed,
            } => {
                if fin {
                    self.done += 1;
                    if alarmed {
                        note = Some(Note::Recovered(self.kind.name(code)));
                    }
                    Phase::WaitFinLow
                } else if !alarmed && self.timeout_ticks > 0 && tick - since >= self.timeout_ticks {
                    note = Some(Note::Timeout(self.kind.name(code)));
                    Phase::Strobe {
                        code,
                        since,
                        alarmed: true,
                    }
                } else {
                    Phase::Strobe {
                        code,
                        since,
                        alarmed,
                    }
                }
            }
            Phase::WaitFinLow => {
                if fin {
                    Phase::WaitFinLow
                } else {
                    Phase::Idle
                }
            }
        };
        let drive = match self.phase {
            Phase::CodeWritten { code } => Drive {
                code: Some(code),
                strobe: false,
            },
            Phase::Strobe { code, .. } => Drive {
                code: Some(code),
                strobe: true,
            },
            Phase::Idle | Phase::WaitFinLow => Drive {
                code: None,
                strobe: false,
            },
        };
        (drive, note)
    }
}

/// `value` in BCD, `digits` decimal digits (higher digits dropped).
pub fn bcd(value: u32, digits: u32) -> u32 {
    let mut v = value;
    let mut out = 0u32;
    for i in 0..digits.min(8) {
        out |= (v % 10) << (4 * i);
        v /= 10;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_phases_in_order() {
        let mut ch = Channel::new(Kind::M, 0);
        ch.issue(3);
        ch.issue(5);
        let d = |code, strobe| Drive { code, strobe };
        assert_eq!(ch.step(0, false, false).0, d(Some(3), false));
        assert_eq!(ch.step(1, false, false).0, d(Some(3), true));
        assert_eq!(ch.step(2, false, false).0, d(Some(3), true));
        assert_eq!(ch.step(3, true, false).0, d(None, false)); // FIN seen: strobe cleared
        assert_eq!(ch.step(4, true, false).0, d(None, false)); // waiting for FIN = 0
        assert_eq!(ch.phase(), Phase::WaitFinLow);
        assert_eq!(ch.step(5, false, false).0, d(None, false));
        assert_eq!(ch.step(6, false, false).0, d(Some(5), false)); // next function
        assert_eq!(ch.done, 1);
    }

    #[test]
    fn timeout_names_the_function_once_and_reset_clears() {
        let mut ch = Channel::new(Kind::M, 3);
        ch.issue(91);
        ch.step(0, false, false);
        ch.step(1, false, false);
        assert_eq!(ch.step(3, false, false).1, None);
        assert_eq!(
            ch.step(4, false, false).1,
            Some(Note::Timeout("M91".into()))
        );
        assert_eq!(ch.step(5, false, false).1, None);
        ch.issue(3);
        assert_eq!(
            ch.step(6, false, true).0,
            Drive {
                code: None,
                strobe: false
            }
        );
        assert!(ch.idle());
    }

    #[test]
    fn bcd_encodes_decimal_digits() {
        assert_eq!(bcd(91, 2), 0x91);
        assert_eq!(bcd(3, 2), 0x03);
        assert_eq!(bcd(12345678, 8), 0x1234_5678);
        assert_eq!(bcd(123, 2), 0x23);
    }
}
