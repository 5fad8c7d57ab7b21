//! The CiA 402 power state machine: statusword decoding, the controlword the master sends for a
//! request, and the transitions a drive makes on a controlword (used by the simulated drive).
//!
//! Statusword patterns (bits 0–3, 5, 6) and controlword commands (bits 0–3, 7) follow CiA 402
//! (IEC 61800-7-201) tables; the master walks a drive up one transition per SYNC (Shutdown →
//! Switch on → Enable operation) so it never skips a state a real drive requires.

/// Controlword commands (object `6040h`).
pub mod cw {
    /// Shutdown (transitions 2, 6, 8): to *Ready to switch on*.
    pub const SHUTDOWN: u16 = 0x06;
    /// Switch on (3) / disable operation (5): to *Switched on*.
    pub const SWITCH_ON: u16 = 0x07;
    /// Enable operation (4, 16): to *Operation enabled*.
    pub const ENABLE_OPERATION: u16 = 0x0F;
    /// Disable voltage (7, 9, 10, 12): to *Switch on disabled*.
    pub const DISABLE_VOLTAGE: u16 = 0x00;
    /// Quick stop (7, 10, 11): to *Quick stop active* from *Operation enabled*.
    pub const QUICK_STOP: u16 = 0x02;
    /// Fault reset bit: its rising edge leaves *Fault* (15).
    pub const FAULT_RESET: u16 = 0x80;
}

/// Statusword bit 3: fault.
pub const SW_FAULT: u16 = 0x0008;
/// Statusword bit 9: remote (the drive follows the controlword).
pub const SW_REMOTE: u16 = 0x0200;

/// A state of the CiA 402 power state machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum State {
    /// Not ready to switch on (initialising).
    #[default]
    NotReadyToSwitchOn,
    /// Switch on disabled (power stage off, waiting for Shutdown).
    SwitchOnDisabled,
    /// Ready to switch on.
    ReadyToSwitchOn,
    /// Switched on (power stage on, no torque).
    SwitchedOn,
    /// Operation enabled (following the targets).
    OperationEnabled,
    /// Quick stop active (stopped, holding).
    QuickStopActive,
    /// Fault reaction active.
    FaultReactionActive,
    /// Fault.
    Fault,
}

impl State {
    /// Decodes a statusword.
    pub fn from_statusword(sw: u16) -> State {
        if sw & 0x4F == 0x08 {
            State::Fault
        } else if sw & 0x4F == 0x0F {
            State::FaultReactionActive
        } else if sw & 0x4F == 0x40 {
            State::SwitchOnDisabled
        } else if sw & 0x6F == 0x21 {
            State::ReadyToSwitchOn
        } else if sw & 0x6F == 0x23 {
            State::SwitchedOn
        } else if sw & 0x6F == 0x27 {
            State::OperationEnabled
        } else if sw & 0x6F == 0x07 {
            State::QuickStopActive
        } else {
            State::NotReadyToSwitchOn
        }
    }

    /// The statusword state bits of this state (bit 9 *remote* added), as a drive reports it.
    pub fn statusword(self) -> u16 {
        let bits = match self {
            State::NotReadyToSwitchOn => 0x00,
            State::SwitchOnDisabled => 0x40,
            State::ReadyToSwitchOn => 0x21,
            State::SwitchedOn => 0x23,
            State::OperationEnabled => 0x27,
            State::QuickStopActive => 0x07,
            State::FaultReactionActive => 0x0F,
            State::Fault => 0x08,
        };
        bits | SW_REMOTE
    }

    /// True in *Fault* and *Fault reaction active*.
    pub fn is_fault(self) -> bool {
        matches!(self, State::Fault | State::FaultReactionActive)
    }
}

/// What the controller asks of a drive this tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Request {
    /// Power the axis (walk up to *Operation enabled*).
    pub enable: bool,
    /// Quick stop (ESTOP): takes precedence over `enable`.
    pub quick_stop: bool,
    /// Fault reset (RESET): a controlword bit 7 edge while the drive is in *Fault*.
    pub fault_reset: bool,
}

/// The controlword the master sends to a drive in `state` for `req`, given the controlword it
/// sent last (for the fault-reset edge: bit 7 is set only when it was clear last time).
pub fn controlword(state: State, req: Request, last: u16) -> u16 {
    match state {
        State::Fault | State::FaultReactionActive => {
            if req.fault_reset && state == State::Fault && last & cw::FAULT_RESET == 0 {
                cw::FAULT_RESET
            } else {
                cw::DISABLE_VOLTAGE
            }
        }
        _ if req.quick_stop => cw::QUICK_STOP,
        State::QuickStopActive => cw::DISABLE_VOLTAGE,
        _ if !req.enable => cw::SHUTDOWN,
        State::NotReadyToSwitchOn | State::SwitchOnDisabled => cw::SHUTDOWN,
        State::ReadyToSwitchOn => cw::SWITCH_ON,
        State::SwitchedOn | State::OperationEnabled => cw::ENABLE_OPERATION,
    }
}

/// The state a drive in `state` goes to on controlword `word` (previous controlword `last`, for
/// the fault-reset edge). `refuse_enable` models a drive that will not enable operation.
pub fn transition(state: State, word: u16, last: u16, refuse_enable: bool) -> State {
    let reset_edge = word & cw::FAULT_RESET != 0 && last & cw::FAULT_RESET == 0;
    let disable_voltage = word & 0x02 == 0;
    let quick_stop = !disable_voltage && word & 0x04 == 0;
    let shutdown = word & 0x07 == 0x06;
    let switch_on = word & 0x0F == 0x07;
    let enable_op = word & 0x0F == 0x0F;
    match state {
        State::Fault if reset_edge => State::SwitchOnDisabled,
        State::Fault | State::FaultReactionActive => state,
        State::NotReadyToSwitchOn => State::SwitchOnDisabled,
        State::SwitchOnDisabled if shutdown => State::ReadyToSwitchOn,
        State::SwitchOnDisabled => state,
        _ if disable_voltage => State::SwitchOnDisabled,
        State::OperationEnabled if quick_stop => State::QuickStopActive,
        State::QuickStopActive if enable_op && !refuse_enable => State::OperationEnabled,
        State::QuickStopActive => state,
        _ if quick_stop => State::SwitchOnDisabled,
        _ if shutdown => State::ReadyToSwitchOn,
        State::ReadyToSwitchOn if switch_on || enable_op => State::SwitchedOn,
        State::SwitchedOn if enable_op && !refuse_enable => State::OperationEnabled,
        State::OperationEnabled if switch_on => State::SwitchedOn,
        _ => state,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [State; 8] = [
        State::NotReadyToSwitchOn,
        State::SwitchOnDisabled,
        State::ReadyToSwitchOn,
        State::SwitchedOn,
        State::OperationEnabled,
        State::QuickStopActive,
        State::FaultReactionActive,
        State::Fault,
    ];

    #[test]
    fn every_state_survives_its_statusword_and_typical_drive_words_decode() {
        for s in ALL {
            assert_eq!(State::from_statusword(s.statusword()), s);
        }
        // Words seen from real drives: other bits (voltage enabled, target reached) set.
        assert_eq!(State::from_statusword(0x0250), State::SwitchOnDisabled);
        assert_eq!(State::from_statusword(0x0231), State::ReadyToSwitchOn);
        assert_eq!(State::from_statusword(0x1637), State::OperationEnabled);
        assert_eq!(State::from_statusword(0x0218), State::Fault);
    }

    #[test]
    fn the_master_walks_a_drive_up_one_transition_per_tick() {
        let on = Request {
            enable: true,
            ..Request::default()
        };
        let mut s = State::SwitchOnDisabled;
        let mut last = 0;
        let mut words = Vec::new();
        for _ in 0..4 {
            let w = controlword(s, on, last);
            words.push(w);
            s = transition(s, w, last, false);
            last = w;
        }
        assert_eq!(words, [0x06, 0x07, 0x0F, 0x0F]);
        assert_eq!(s, State::OperationEnabled);
        let qs = Request {
            quick_stop: true,
            ..on
        };
        assert_eq!(controlword(s, qs, last), 0x02);
        assert_eq!(transition(s, 0x02, last, false), State::QuickStopActive);
        assert_eq!(controlword(State::QuickStopActive, on, 0x02), 0x00);
        assert_eq!(controlword(s, Request::default(), last), 0x06);
        assert_eq!(transition(s, 0x06, last, false), State::ReadyToSwitchOn);
    }

    #[test]
    fn fault_reset_is_an_edge_of_bit_7() {
        let reset = Request {
            enable: true,
            fault_reset: true,
            ..Request::default()
        };
        assert_eq!(controlword(State::Fault, reset, 0x0F), 0x80);
        assert_eq!(controlword(State::Fault, reset, 0x80), 0x00);
        assert_eq!(controlword(State::Fault, Request::default(), 0x0F), 0x00);
        assert_eq!(
            transition(State::Fault, 0x80, 0x00, false),
            State::SwitchOnDisabled
        );
        assert_eq!(transition(State::Fault, 0x80, 0x80, false), State::Fault);
    }

    #[test]
    fn a_refusing_drive_stays_switched_on() {
        assert_eq!(
            transition(State::SwitchedOn, 0x0F, 0x07, true),
            State::SwitchedOn
        );
    }
}
