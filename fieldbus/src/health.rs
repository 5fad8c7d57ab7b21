//! Per-device health as the scan sees it: fresh frames keep a device healthy, a reported fault or
//! too many ticks without a fresh frame make it lost, and each change raises or clears an alarm.
//!
//! The I/O tasks publish frames that carry a sequence number (bumped on every good exchange) and a
//! [`Fault`]. The scan side ([`Health::tick`]) runs once per latch, so the alarm comes within the
//! configured number of ticks even when the I/O task itself is stuck.

use packets::IoAlarm;

/// Why a device is not answering (carried from the I/O task to the scan in every frame).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Fault {
    /// No fault: the frame is good.
    #[default]
    None,
    /// Not connected yet, or the connection attempt failed.
    Connect,
    /// A request timed out.
    Timeout,
    /// The connection broke or the device sent something that is not Modbus.
    Io,
    /// The device answered with a Modbus exception.
    Exception,
    /// The answer did not match the request (wrong length, wrong function).
    Protocol,
    /// A CANopen node's heartbeat did not come within its heartbeat time.
    HeartbeatLost,
    /// A CANopen node left the operational state.
    NotOperational,
    /// Configuration by SDO at start failed.
    Sdo,
}

impl Fault {
    /// Every fault, in the order of [`Fault::code`].
    const ALL: [Fault; 9] = [
        Fault::None,
        Fault::Connect,
        Fault::Timeout,
        Fault::Io,
        Fault::Exception,
        Fault::Protocol,
        Fault::HeartbeatLost,
        Fault::NotOperational,
        Fault::Sdo,
    ];

    /// A small number that carries the fault through an atomic (inverse of [`Fault::from_code`]).
    pub fn code(self) -> u8 {
        self as u8
    }

    /// The fault numbered `code`; an unknown number reads as [`Fault::Io`].
    pub fn from_code(code: u8) -> Fault {
        Fault::ALL
            .get(usize::from(code))
            .copied()
            .unwrap_or(Fault::Io)
    }

    /// English text for alarms.
    pub fn text(self) -> &'static str {
        match self {
            Fault::None => "answering",
            Fault::Connect => "cannot connect",
            Fault::Timeout => "request timed out",
            Fault::Io => "connection lost or garbage received",
            Fault::Exception => "answered with a Modbus exception",
            Fault::Protocol => "answer does not match the request",
            Fault::HeartbeatLost => "heartbeat lost",
            Fault::NotOperational => "node is not operational",
            Fault::Sdo => "SDO configuration failed",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Starting,
    Healthy,
    Lost,
}

/// The scan-side health state machine of one device.
#[derive(Debug, Clone)]
pub struct Health {
    name: String,
    alarm_ticks: u32,
    state: State,
    stale: u32,
    last_seq: u64,
}

impl Health {
    /// A device that has not answered yet; it is lost after `alarm_ticks` ticks without an answer.
    pub fn new(name: &str, alarm_ticks: u32) -> Self {
        Health {
            name: name.to_string(),
            alarm_ticks: alarm_ticks.max(1),
            state: State::Starting,
            stale: 0,
            last_seq: 0,
        }
    }

    /// True while the device's inputs are valid.
    pub fn healthy(&self) -> bool {
        self.state == State::Healthy
    }

    /// True once the device has been declared lost (and has not come back).
    pub fn lost(&self) -> bool {
        self.state == State::Lost
    }

    /// Advances one tick with the newest frame's sequence number and fault; returns the alarm to
    /// raise or clear, if the state changed.
    pub fn tick(&mut self, seq: u64, fault: Fault) -> Option<IoAlarm> {
        let fresh = seq != self.last_seq && fault == Fault::None;
        if fresh {
            self.last_seq = seq;
            self.stale = 0;
        } else {
            self.stale = self.stale.saturating_add(1);
        }
        let good = fault == Fault::None && self.stale < self.alarm_ticks && self.last_seq != 0;
        let lost_reason = if fault != Fault::None {
            fault.text()
        } else {
            "no answer"
        };
        match (self.state, good) {
            (State::Healthy, true) | (State::Lost, false) => None,
            (State::Starting, true) | (State::Lost, true) => {
                let was_lost = self.state == State::Lost;
                self.state = State::Healthy;
                was_lost.then(|| IoAlarm {
                    device: self.name.clone(),
                    message: "answering again".into(),
                    cleared: true,
                })
            }
            (State::Starting, false) if fault == Fault::None && self.stale < self.alarm_ticks => {
                None
            }
            (State::Starting | State::Healthy, false) => {
                let ticks = self.stale;
                self.state = State::Lost;
                let message = if fault != Fault::None {
                    lost_reason.to_string()
                } else {
                    format!("no answer for {ticks} ticks")
                };
                Some(IoAlarm {
                    device: self.name.clone(),
                    message,
                    cleared: false,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lost_after_exactly_alarm_ticks_without_a_fresh_frame_and_cleared_on_return() {
        let mut h = Health::new("rio", 3);
        assert_eq!(h.tick(0, Fault::None), None);
        assert_eq!(h.tick(1, Fault::None), None);
        assert!(h.healthy());
        assert_eq!(h.tick(1, Fault::None), None);
        assert_eq!(h.tick(1, Fault::None), None);
        let a = h.tick(1, Fault::None).expect("third stale tick raises");
        assert_eq!(
            (a.device.as_str(), a.message.as_str(), a.cleared),
            ("rio", "no answer for 3 ticks", false)
        );
        assert!(!h.healthy());
        assert_eq!(h.tick(1, Fault::None), None, "raised once");
        let c = h.tick(2, Fault::None).expect("clears");
        assert!(c.cleared);
        assert!(h.healthy());
    }

    #[test]
    fn fault_codes_round_trip() {
        for f in Fault::ALL {
            assert_eq!(Fault::from_code(f.code()), f);
        }
        assert_eq!(Fault::Timeout.code(), 2);
        assert_eq!(Fault::from_code(200), Fault::Io);
    }

    #[test]
    fn a_reported_fault_is_lost_at_once_with_its_reason() {
        let mut h = Health::new("rio", 10);
        h.tick(1, Fault::None);
        let a = h.tick(1, Fault::Timeout).expect("fault raises at once");
        assert_eq!(a.message, "request timed out");
        assert!(!h.healthy());
    }

    #[test]
    fn a_device_that_never_answers_is_reported_after_alarm_ticks() {
        let mut h = Health::new("rio", 2);
        assert_eq!(h.tick(0, Fault::None), None);
        assert!(h.tick(0, Fault::None).is_some());
        let mut h = Health::new("rio", 5);
        assert_eq!(
            h.tick(0, Fault::Connect).map(|a| a.message),
            Some("cannot connect".to_string())
        );
    }
}
