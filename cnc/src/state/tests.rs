use super::*;

fn every_state() -> Vec<State> {
    let mut v = Vec::new();
    for on in [false, true] {
        for mode in Mode::ALL {
            for interp in [Interp::Idle, Interp::Running, Interp::Paused] {
                for moving in [false, true] {
                    for homed in [false, true] {
                        for program in [false, true] {
                            v.push(State {
                                on,
                                mode,
                                interp,
                                moving,
                                homed,
                                program,
                            });
                        }
                    }
                }
            }
        }
    }
    v
}

/// Counts of every outcome over all 336 states × 12 commands, derived by hand in the comments.
#[test]
fn the_whole_table_has_the_hand_counted_outcomes() {
    let states = every_state();
    assert_eq!(states.len(), 2 * 7 * 3 * 2 * 2 * 2);
    let mut count = std::collections::BTreeMap::<String, usize>::new();
    for s in &states {
        for c in Command::all() {
            let key = match decide(s, c) {
                Ok(()) => "ok".to_string(),
                Err(r) => format!("{r:?}"),
            };
            *count.entry(key).or_default() += 1;
        }
    }
    // Off (168 states): Start, Hold, Mdi, Jog refused.
    assert_eq!(count["MachineOff"], 168 * 4);
    // A different mode (6 of 7) while moving (168 states).
    assert_eq!(count["Moving"], 168 * 6);
    // Mode change, not moving, program active: 112 states × 6; Start in HOME, Mdi in MDI (16 each
    // with the machine on and a program active), Jog in MANU/MANJ (32).
    assert_eq!(count["ProgramActive"], 112 * 6 + 16 + 16 + 32);
    // Reset everywhere; the rest is what remains.
    let total: usize = count.values().sum();
    assert_eq!(total, 336 * 12);
}

#[test]
fn spot_checks_of_the_rules() {
    let s = State {
        on: true,
        mode: Mode::Idle,
        interp: Interp::Idle,
        moving: false,
        homed: false,
        program: true,
    };
    assert_eq!(
        decide(&s, Command::SetMode(Mode::Auto)),
        Err(Reject::NotHomed)
    );
    assert_eq!(decide(&s, Command::SetMode(Mode::Home)), Ok(()));
    assert_eq!(decide(&s, Command::SetMode(Mode::Manu)), Ok(()));
    assert_eq!(decide(&s, Command::Start), Err(Reject::WrongMode));
    assert_eq!(decide(&s, Command::Hold), Err(Reject::NotRunning));
    let auto = State {
        mode: Mode::Auto,
        homed: true,
        ..s
    };
    assert_eq!(decide(&auto, Command::Start), Ok(()));
    assert_eq!(
        decide(
            &State {
                program: false,
                ..auto
            },
            Command::Start
        ),
        Err(Reject::NoProgram)
    );
    assert_eq!(decide(&auto, Command::Mdi), Err(Reject::WrongMode));
    assert_eq!(decide(&auto, Command::Jog), Err(Reject::WrongMode));
    let running = State {
        interp: Interp::Running,
        moving: true,
        ..auto
    };
    assert_eq!(decide(&running, Command::Hold), Ok(()));
    assert_eq!(
        decide(&running, Command::SetMode(Mode::Mdi)),
        Err(Reject::Moving)
    );
    assert_eq!(decide(&running, Command::Reset), Ok(()));
    let paused = State {
        interp: Interp::Paused,
        moving: false,
        ..auto
    };
    assert_eq!(
        decide(&paused, Command::SetMode(Mode::Manu)),
        Err(Reject::ProgramActive)
    );
    assert_eq!(decide(&paused, Command::Start), Ok(()));
    let off = State { on: false, ..auto };
    assert_eq!(decide(&off, Command::Start), Err(Reject::MachineOff));
    assert_eq!(decide(&off, Command::SetMode(Mode::Mdi)), Ok(()));
}

#[test]
fn mode_codes_round_trip() {
    for m in Mode::ALL {
        assert_eq!(Mode::from_code(m.code()), Some(m));
    }
    assert_eq!(Mode::Home.code(), 6);
    assert_eq!(Mode::from_code(7), None);
}
