//! The Machine Tools values as functions of the packet image: what the CNC tells the logic
//! through the interface map (MODE, CYCLE, HOLD, FOV, ROV, SOV) and the stack-light outputs,
//! mapped onto the OPC 40501-1 enumerations. Pure functions, tested on their own.
//!
//! **Invariant:** every mode byte has a mapping (an unknown one is `Other`), so a value node
//! never goes stale.

use packets::Signal;

/// The NC mode byte (MODE: 0 IDLE, 1 AUTO, 2 STEP, 3 MDI, 4 MANU, 5 MANJ, 6 HOME) as the
/// MachineTool `ChannelMode` (0 Automatic, 1 MdaMdi, 2 JogManual, 3 JogIncrement, 6 Reference,
/// 7 Other).
pub fn channel_mode(mode: u8) -> i32 {
    match mode {
        1 | 2 => 0,
        3 => 1,
        4 => 2,
        5 => 3,
        6 => 6,
        _ => 7,
    }
}

/// The NC mode byte as the MachineTool `MachineOperationMode` (0 Manual, 1 Automatic, 2 Setup,
/// 5 Other): AUTO, STEP and MDI run programs (Automatic), MANU and MANJ jog (Manual), HOME
/// references the axes (Setup).
pub fn operation_mode(mode: u8) -> i32 {
    match mode {
        1..=3 => 1,
        4 | 5 => 0,
        6 => 2,
        _ => 5,
    }
}

/// The MachineTool `ChannelState` (0 Active, 1 Interrupted, 2 Reset) from CYCLE and HOLD: a feed
/// hold interrupts, a running cycle is active, anything else is the reset state.
pub fn channel_state(cycle: bool, hold: bool) -> i32 {
    match (cycle, hold) {
        (_, true) => 1,
        (true, false) => 0,
        (false, false) => 2,
    }
}

/// The states of the `ProductionStateMachineType` the active program takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgramState {
    /// No cycle has run yet.
    Initializing,
    /// The cycle runs.
    Running,
    /// Feed hold.
    Interrupted,
    /// The cycle ran and ended.
    Ended,
}

impl ProgramState {
    /// The state's browse name (its `CurrentState` text).
    pub fn name(self) -> &'static str {
        match self {
            ProgramState::Initializing => "Initializing",
            ProgramState::Running => "Running",
            ProgramState::Interrupted => "Interrupted",
            ProgramState::Ended => "Ended",
        }
    }

    /// The numeric id of the state object in the MachineTool namespace.
    pub fn type_node(self) -> u32 {
        match self {
            ProgramState::Initializing => 135,
            ProgramState::Running => 138,
            ProgramState::Interrupted => 139,
            ProgramState::Ended => 140,
        }
    }

    /// The next state after a tick with `cycle` and `hold`.
    pub fn next(self, cycle: bool, hold: bool) -> ProgramState {
        match (cycle, hold, self) {
            (_, true, _) => ProgramState::Interrupted,
            (true, false, _) => ProgramState::Running,
            (false, false, ProgramState::Initializing) => ProgramState::Initializing,
            (false, false, _) => ProgramState::Ended,
        }
    }
}

/// The value of an optional signal in `image` (0 when the map has no such signal).
pub fn read(signal: Option<Signal>, image: &[u8]) -> u8 {
    signal.map_or(0, |s| s.read(image))
}

/// The binary little-endian dword whose first byte is `signal` (0 when the map has none, or
/// when it is a bit or runs past the image).
pub fn dword(signal: Option<Signal>, image: &[u8]) -> u32 {
    let Some(s) = signal.filter(|s| s.bit().is_none()) else {
        return 0;
    };
    let at = s.image_byte();
    image
        .get(at..at + 4)
        .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dword_is_read_little_endian_from_its_first_byte() {
        let mut image = vec![0u8; packets::PACKETS_LEN];
        let scode: Signal = "W4K0".parse().expect("signal");
        let at = scode.image_byte();
        image[at..at + 4].copy_from_slice(&[0x58, 0x02, 0, 0]);
        assert_eq!(dword(Some(scode), &image), 600);
        assert_eq!(dword(None, &image), 0);
        let bit: Signal = "I4K0".parse().expect("signal");
        assert_eq!(dword(Some(bit), &image), 0);
        let last: Signal = "W15T3".parse().expect("signal");
        assert_eq!(dword(Some(last), &image), 0, "past the image's end");
    }

    #[test]
    fn modes_map_onto_the_machine_tool_enumerations() {
        let modes: Vec<(i32, i32)> = (0..=7)
            .map(|m| (channel_mode(m), operation_mode(m)))
            .collect();
        assert_eq!(
            modes,
            vec![
                (7, 5),
                (0, 1),
                (0, 1),
                (1, 1),
                (2, 0),
                (3, 0),
                (6, 2),
                (7, 5)
            ]
        );
        assert_eq!(channel_state(true, false), 0);
        assert_eq!(channel_state(true, true), 1);
        assert_eq!(channel_state(false, false), 2);
    }

    #[test]
    fn the_program_state_follows_cycle_and_hold() {
        use ProgramState::*;
        let mut s = Initializing;
        let mut seen = Vec::new();
        for (cycle, hold) in [
            (false, false),
            (true, false),
            (true, true),
            (true, false),
            (false, false),
            (false, false),
        ] {
            s = s.next(cycle, hold);
            seen.push(s);
        }
        assert_eq!(
            seen,
            vec![Initializing, Running, Interrupted, Running, Ended, Ended]
        );
    }
}
