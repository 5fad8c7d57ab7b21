//! The state of one process in LinuxCNC's split (machine power × mode × interpreter), and the one
//! table that says which operator or PLC command is allowed in which state ([`decide`]).
//!
//! Rules (issue 11 §2, LinuxCNC `emcTaskIssueCommand`): a reset is always allowed; with the machine
//! off nothing but reset and mode selection is; no mode change while axes move or while a program
//! is active (running or paused); AUTO, STEP and MDI need every axis that has a homing cycle homed;
//! START needs a mode that runs something and, in AUTO and STEP, a selected program; MDI text only in
//! MDI mode with the interpreter idle; jogs only in MANU/MANJ with the interpreter idle; homing
//! only in HOME.

/// Operating mode, as written to the MODE byte (W2K0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Mode {
    /// 0: no mode selected.
    Idle,
    /// 1: automatic, the selected program runs block after block.
    Auto,
    /// 2: single block: one block per START.
    Step,
    /// 3: manual data input: the typed blocks run.
    Mdi,
    /// 4: jog (continuous).
    Manu,
    /// 5: incremental jog.
    Manj,
    /// 6: homing.
    Home,
}

impl Mode {
    /// Every mode, in code order.
    pub const ALL: [Mode; 7] = [
        Mode::Idle,
        Mode::Auto,
        Mode::Step,
        Mode::Mdi,
        Mode::Manu,
        Mode::Manj,
        Mode::Home,
    ];

    /// The MODE byte value.
    pub fn code(self) -> u8 {
        self as u8
    }

    /// The mode of a MODE byte value.
    pub fn from_code(code: u8) -> Option<Mode> {
        Mode::ALL.get(usize::from(code)).copied()
    }

    /// True for the modes that execute partprogram blocks.
    pub fn runs_blocks(self) -> bool {
        matches!(self, Mode::Auto | Mode::Step | Mode::Mdi)
    }
}

/// Interpreter state of a process.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interp {
    /// No program active.
    Idle,
    /// Blocks are being executed.
    Running,
    /// Stopped at a block end (M00, M01 with USO, STEP); START continues.
    Paused,
}

/// Everything [`decide`] looks at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct State {
    /// Machine on (e-stop chain closed and no stopping alarm).
    pub on: bool,
    /// The mode.
    pub mode: Mode,
    /// The interpreter.
    pub interp: Interp,
    /// Some axis of the process moves (program, jog or homing).
    pub moving: bool,
    /// Every axis with a homing cycle is homed.
    pub homed: bool,
    /// A program is selected (AUTO/STEP).
    pub program: bool,
}

/// A command to a process, from the operator channel or the PLC's request signals.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    /// Select a mode.
    SetMode(Mode),
    /// Cycle start (also resumes a paused program).
    Start,
    /// Feed hold requested by the operator.
    Hold,
    /// Reset: stop, clear strobes, back to the program start.
    Reset,
    /// Run typed blocks.
    Mdi,
    /// Jog an axis.
    Jog,
}

impl Command {
    /// Every command kind (with every mode for `SetMode`), for exhaustive tests.
    pub fn all() -> Vec<Command> {
        let mut v: Vec<Command> = Mode::ALL.iter().map(|m| Command::SetMode(*m)).collect();
        v.extend([
            Command::Start,
            Command::Hold,
            Command::Reset,
            Command::Mdi,
            Command::Jog,
        ]);
        v
    }
}

/// Why a command is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum Reject {
    /// The machine is off (e-stop or a stopping alarm).
    #[error("the machine is off")]
    MachineOff,
    /// Axes are moving.
    #[error("can't switch mode while axes move")]
    Moving,
    /// A program is running or paused.
    #[error("can't do that while a program is active (reset first)")]
    ProgramActive,
    /// Homing is incomplete.
    #[error("can't run blocks when not homed")]
    NotHomed,
    /// The mode does not accept the command.
    #[error("not allowed in this mode")]
    WrongMode,
    /// No program is selected.
    #[error("no program selected")]
    NoProgram,
    /// Nothing runs.
    #[error("no program is running")]
    NotRunning,
}

/// Allow or reject `cmd` in state `s`: the whole rule table of the process.
pub fn decide(s: &State, cmd: Command) -> Result<(), Reject> {
    if cmd == Command::Reset {
        return Ok(());
    }
    if !s.on && !matches!(cmd, Command::SetMode(_)) {
        return Err(Reject::MachineOff);
    }
    let active = s.interp != Interp::Idle;
    match cmd {
        Command::Reset => Ok(()),
        Command::SetMode(m) => {
            if m == s.mode {
                Ok(())
            } else if s.moving {
                Err(Reject::Moving)
            } else if active {
                Err(Reject::ProgramActive)
            } else if m.runs_blocks() && !s.homed {
                Err(Reject::NotHomed)
            } else {
                Ok(())
            }
        }
        Command::Start => match s.mode {
            Mode::Auto | Mode::Step if !s.program => Err(Reject::NoProgram),
            Mode::Auto | Mode::Step | Mode::Mdi if !s.homed => Err(Reject::NotHomed),
            Mode::Auto | Mode::Step | Mode::Mdi => Ok(()),
            Mode::Home if active => Err(Reject::ProgramActive),
            Mode::Home => Ok(()),
            Mode::Idle | Mode::Manu | Mode::Manj => Err(Reject::WrongMode),
        },
        Command::Hold => {
            if s.interp == Interp::Running {
                Ok(())
            } else {
                Err(Reject::NotRunning)
            }
        }
        Command::Mdi => {
            if s.mode != Mode::Mdi {
                Err(Reject::WrongMode)
            } else if active {
                Err(Reject::ProgramActive)
            } else if !s.homed {
                Err(Reject::NotHomed)
            } else {
                Ok(())
            }
        }
        Command::Jog => {
            if !matches!(s.mode, Mode::Manu | Mode::Manj) {
                Err(Reject::WrongMode)
            } else if active {
                Err(Reject::ProgramActive)
            } else {
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests;
