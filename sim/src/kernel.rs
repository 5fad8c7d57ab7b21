//! The CNC side of a part run (`ncplc run --program`): the `cnc` kernel and its plant behind a
//! [`PacketIo`], with `sim.toml`'s `[[at]]` inputs and `[[follow]]` rules for the rest of the
//! machine (panel buttons, lubrication, guards).
//!
//! Per logic tick, in `latch_inputs(t)`: first the script's inputs and follow rules (as the
//! scripted sim), then [`cnc::Cnc::step`] with the outputs published by scan t−1: it reads the
//! PLC→CNC signals, advances every process by the interpolation ticks of one logic tick, and writes
//! the CNC→PLC signals (and the plant's spindle contacts) that scan t reads. `publish_outputs(t)`
//! keeps the outputs for the next tick.
//!
//! A `[part]` table in `sim.toml` replaces the top-level `at`/`follow` lists (which belong to the
//! scripted CNC of pure logic runs). The script may not issue M/S/T (the program does) nor set a signal the kernel writes, and every
//! signal it sets must exist on the machine: a packet-A input on a connector IOCFIL declares, or a
//! K/N signal of the interface map.

use std::sync::{Arc, Mutex, PoisonError};

use characterization::axcfil::Axcfil;
use characterization::iocfil::Iocfil;
use cnc::interp::Interpolator;
use cnc::plant::PlantSignals;
use cnc::{Cnc, MachineSignals, Process, ProcessConfig, ProcessSignals, Timing};
use compiler::InterfaceMap;
use packets::{IoAlarm, Packet, PacketIo, Signal};

use super::handwheel::HandwheelSim;
use super::{CncSignals, Script, Sim, SimError};

/// Builds an interpolator for a process: (process, axes in order, start position).
pub type MakeInterp<'a> =
    &'a dyn Fn(&ProcessConfig, &[f64]) -> Result<Box<dyn Interpolator>, String>;

/// What the kernel is built from.
pub struct KernelSetup<'a> {
    /// AXCFIL.
    pub axcfil: &'a Axcfil,
    /// IOCFIL.
    pub iocfil: Option<&'a Iocfil>,
    /// The interface map.
    pub interface: &'a InterfaceMap,
    /// Packet-A input connectors IOCFIL declares.
    pub a_inputs: &'a [u16],
    /// Logic tick in ms.
    pub tick_ms: u32,
    /// The interpolator of each process.
    pub make_interp: MakeInterp<'a>,
}

/// The kernel and the scripted rest of the machine.
pub struct KernelIo {
    sim: Sim,
    hand: HandwheelSim,
    cnc: Arc<Mutex<Cnc>>,
    last_out: Vec<u8>,
    alarms: Vec<IoAlarm>,
}

fn parse(name: &str) -> Result<Signal, SimError> {
    name.parse()
        .map_err(|e| SimError::Invalid(format!("`{name}`: {e}")))
}

/// The processes and machine signals of the kernel (shared with the CLI and an HMI).
pub fn build_cnc(setup: &KernelSetup, script: &Script) -> Result<Cnc, SimError> {
    let tick_ms = u64::from(setup.tick_ms.max(1));
    let timing = Timing {
        logic_tick_s: tick_ms as f64 / 1000.0,
        strobe_timeout_ticks: script.strobe_timeout_ms.div_ceil(tick_ms),
        rabi_timeout_ticks: script.cnc.rabi_timeout_ms.div_ceil(tick_ms),
    };
    let wiring = &script.spindle;
    let plant = PlantSignals {
        at_speed: wiring.at_speed.as_deref().map(parse).transpose()?,
        stopped: wiring.stopped.as_deref().map(parse).transpose()?,
        run: wiring
            .run
            .iter()
            .map(|s| parse(s))
            .collect::<Result<_, _>>()?,
    };
    let mut processes = Vec::new();
    for cfg in ProcessConfig::all(setup.axcfil, setup.iocfil) {
        let n = cfg.number;
        let sig =
            ProcessSignals::from_roles(|role| setup.interface.role(n, role).map(|e| e.signal));
        let start = vec![0.0; cfg.axes.len()];
        let interp = (setup.make_interp)(&cfg, &start)
            .map_err(|e| SimError::Invalid(format!("process {n}: {e}")))?;
        let mut p = Process::new(cfg, sig, interp, &start, timing);
        if n == 1 {
            p.set_plant(plant.clone());
            for a in &script.axis {
                let Some(i) = p.axis_index(a.name) else {
                    return Err(SimError::Invalid(format!(
                        "[[axis]] {}: not a coordinated axis of process 1",
                        a.name
                    )));
                };
                p.place_axis(i, a.start, a.home_switch);
                if a.limit_pos.is_some() || a.limit_neg.is_some() {
                    let wired = p.limit_inputs(i);
                    if (a.limit_pos.is_some() && wired.0.is_none())
                        || (a.limit_neg.is_some() && wired.1.is_none())
                    {
                        return Err(SimError::Invalid(format!(
                            "[[axis]] {}: a limit switch without its AXCFIL MFC input",
                            a.name
                        )));
                    }
                    p.place_limit_switches(i, a.limit_pos, a.limit_neg);
                }
            }
        }
        if script.cnc.referenced {
            p.set_homed();
        }
        processes.push(p);
    }
    let machine = MachineSignals {
        reset: setup.interface.role(1, "RESET").map(|e| e.signal),
        estop: setup.interface.role(1, "ESTOP").map(|e| e.signal),
    };
    Ok(Cnc::new(processes, machine))
}

/// Every signal the CNC kernel writes in a part run: the general reset and each process's
/// CNC→PLC signals (a sim.toml may not set these).
pub fn kernel_written(
    axcfil: &Axcfil,
    iocfil: Option<&Iocfil>,
    interface: &InterfaceMap,
) -> Vec<Signal> {
    let mut written: Vec<Signal> = interface
        .role(1, "RESET")
        .map(|e| e.signal)
        .into_iter()
        .collect();
    for cfg in ProcessConfig::all(axcfil, iocfil) {
        let n = cfg.number;
        written.extend(
            ProcessSignals::from_roles(|role| interface.role(n, role).map(|e| e.signal)).written(),
        );
    }
    written
}

/// Checks the script against the machine and the kernel (see the module docs).
fn check_script(setup: &KernelSetup, script: &Script) -> Result<(), SimError> {
    let written = kernel_written(setup.axcfil, setup.iocfil, setup.interface);
    for at in &script.at {
        if !at.m.is_empty() || at.s.is_some() || at.t.is_some() {
            return Err(SimError::Invalid(format!(
                "tick {}: m, s and t come from the partprogram in a part run; remove them",
                at.tick
            )));
        }
        for name in at.set.keys() {
            let s = parse(name)?;
            if written.contains(&s) {
                return Err(SimError::Invalid(format!(
                    "tick {}: {name} is written by the CNC kernel in a part run",
                    at.tick
                )));
            }
            declared(setup, s, name)?;
        }
    }
    for f in &script.follow {
        declared(setup, parse(&f.input)?, &f.input)?;
    }
    for h in &script.handwheel {
        declared(setup, parse(&h.counter)?, &h.counter)?;
    }
    Ok(())
}

fn declared(setup: &KernelSetup, s: Signal, name: &str) -> Result<(), SimError> {
    let ok = match s.packet() {
        Packet::A => {
            let connector = s.packet_byte() / 4;
            setup.a_inputs.contains(&(connector as u16))
        }
        Packet::T => true,
        Packet::K | Packet::N => setup.interface.iter().any(|e| e.signal == s),
    };
    if ok {
        Ok(())
    } else {
        Err(SimError::Invalid(format!(
            "{name} is not a signal of this machine (packet-A inputs: IOCFIL IN connectors; K/N: the interface map)"
        )))
    }
}

impl KernelIo {
    /// The kernel I/O and the shared kernel (for programs, operator commands and status).
    pub fn new(
        setup: &KernelSetup,
        script: Script,
    ) -> Result<(KernelIo, Arc<Mutex<Cnc>>), SimError> {
        let mut script = script;
        if let Some(part) = script.part.take() {
            script.at = part.at;
            script.follow = part.follow;
            script.period = None;
        }
        let adv = |p: u8, c: u8| {
            setup
                .iocfil
                .and_then(|f| f.process(u32::from(p)))
                .and_then(|io| io.adv)
                .is_some_and(|adv| (1..=2).contains(&c) && adv[usize::from(c) - 1].is_some())
        };
        let hand = HandwheelSim::new(&script.handwheel, &mut script.at, adv)?;
        check_script(setup, &script)?;
        let mut cnc = build_cnc(setup, &script)?;
        for n in 1..=5u8 {
            if let Ok(p) = cnc.process_mut(n) {
                p.set_handwheel_counters(hand.counters(n));
            }
        }
        let signals = CncSignals {
            reset: setup
                .interface
                .role(1, "RESET")
                .map_or(CncSignals::default().reset, |e| e.signal),
            processes: Vec::new(),
        };
        let sim = Sim::new(script, signals, setup.tick_ms)?;
        let cnc = Arc::new(Mutex::new(cnc));
        Ok((
            KernelIo {
                sim,
                hand,
                cnc: Arc::clone(&cnc),
                last_out: vec![0; packets::PACKETS_LEN],
                alarms: Vec::new(),
            },
            cnc,
        ))
    }
}

impl PacketIo for KernelIo {
    fn name(&self) -> &str {
        "sim+cnc"
    }

    fn latch_inputs(&mut self, tick: u64, packets: &mut [u8]) {
        self.sim.latch_inputs(tick, packets);
        self.hand.latch(tick, packets);
        let mut cnc = self.cnc.lock().unwrap_or_else(PoisonError::into_inner);
        cnc.step(tick, &self.last_out, packets);
        for n in 1..=5u8 {
            if let Ok(p) = cnc.process_mut(n) {
                for a in p.take_new_alarms() {
                    self.alarms.push(IoAlarm {
                        device: "cnc".into(),
                        message: a.message,
                        cleared: false,
                    });
                }
            }
        }
    }

    fn publish_outputs(&mut self, tick: u64, packets: &[u8]) {
        self.sim.publish_outputs(tick, packets);
        let n = packets.len().min(self.last_out.len());
        self.last_out[..n].copy_from_slice(&packets[..n]);
    }

    fn safe_state(&mut self) {
        self.sim.safe_state();
        self.cnc
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .plc_halted();
    }

    fn take_alarms(&mut self) -> Vec<IoAlarm> {
        let mut v = self.sim.take_alarms();
        v.append(&mut self.alarms);
        v
    }
}
