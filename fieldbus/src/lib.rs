//! Packet-A I/O over Modbus TCP (client and HMI server) and CANopen (SocketCAN, virtual bus, cannelloni UDP).
//!
//! The runtime's scan loop talks to every driver through [`packets::PacketIo`]. This crate reads the
//! machine's I/O map (`<machine>/io.toml`, [`map`] and [`validate`]), and [`open`] starts the driver the
//! command line chose: the Modbus TCP remote-I/O client ([`modbus::client`]) or the CANopen master
//! ([`canopen::master`]). [`start_hmi`] wraps any driver (the simulated one too) with the Modbus TCP
//! server for an HMI or SCADA ([`modbus::server`]). Drivers never block the scan: their network tasks
//! run on a private tokio runtime and exchange images through lock-free buffers ([`exchange`]).
//! When the scan thread runs `SCHED_FIFO`, a driver moves its I/O threads to `SCHED_FIFO` ten
//! below it at its first latch ([`rt`]), whichever was started first; the Modbus client also puts
//! output writes on the wire from the scan thread itself (one non-blocking `send`,
//! [`modbus::writer`]). Measured in `BENCHMARKS.md`.
//!
//! # Wiring it into `ncplc run`
//! ```no_run
//! use std::path::Path;
//! use fieldbus::{DeclaredConnectors, IoKind};
//!
//! let machine = Path::new("plc-programs/lathe");
//! // From IOCFIL: INx → inputs, OUx → outputs.
//! let declared = DeclaredConnectors { inputs: vec![0, 1], outputs: vec![4, 5] };
//! let kind: IoKind = "modbus".parse().expect("sim | modbus | canopen");
//! let io = fieldbus::open(kind, machine, &declared).map_err(|diags| diags.len()).expect("valid map");
//! // Optional HMI/SCADA server around any driver (returns `io` unchanged without `[hmi]`).
//! let mut io = fieldbus::start_hmi(machine, &declared, io).map_err(|d| d.len()).expect("hmi");
//! let mut image = vec![0u8; packets::PACKETS_LEN];
//! for tick in 0..3 {
//!     io.latch_inputs(tick, &mut image);
//!     // … scan …
//!     io.publish_outputs(tick, &image);
//!     for alarm in io.take_alarms() {
//!         eprintln!("{}: {}", alarm.device, alarm.message);
//!     }
//! }
//! io.safe_state();
//! ```

pub mod affinity;
pub mod canopen;
pub mod exchange;
pub mod health;
pub mod map;
pub mod modbus;
pub mod prefault;
pub mod rt;
pub mod tick_io;
pub mod validate;

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use diag::Diagnostic;
use packets::PacketIo;

pub use map::{DeclaredAxis, DeclaredConnectors, IoMap};
pub use validate::{codes, load_map, load_map_with_axes, parse_map, parse_map_with_axes};

/// Which packet-A I/O `ncplc run --io` uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum IoKind {
    /// The runtime's built-in simulated I/O (the default; needs no map).
    #[default]
    Sim,
    /// Modbus TCP remote I/O as described by `[[modbus.device]]` in `io.toml`.
    Modbus,
    /// A CANopen master as described by `[canopen]` in `io.toml`.
    Canopen,
}

impl IoKind {
    /// The names `--io` accepts, in order.
    pub const NAMES: [&'static str; 3] = ["sim", "modbus", "canopen"];
}

impl fmt::Display for IoKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            IoKind::Sim => "sim",
            IoKind::Modbus => "modbus",
            IoKind::Canopen => "canopen",
        })
    }
}

/// The text given to `--io` is not one of [`IoKind::NAMES`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown I/O kind `{0}` (expected sim, modbus or canopen)")]
pub struct IoKindError(pub String);

impl FromStr for IoKind {
    type Err = IoKindError;

    /// Parses `sim`, `modbus` or `canopen` (case-insensitive); works as a clap value parser.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "sim" => Ok(IoKind::Sim),
            "modbus" => Ok(IoKind::Modbus),
            "canopen" => Ok(IoKind::Canopen),
            _ => Err(IoKindError(s.to_string())),
        }
    }
}

fn whole_file(code: u32, message: String, hint: &str) -> Vec<Diagnostic> {
    vec![Diagnostic::error(code, "io.toml", 0..0, message).with_hint(hint)]
}

/// Reads and validates `<machine_dir>/io.toml` and starts the driver for `kind`.
///
/// `declared` are the packet-A connectors IOCFIL declares (`INx`, `OUx`); mappings onto other
/// connectors are errors. Warnings of a valid map are dropped here (`load_map` returns them, for
/// `ncplc check`). [`IoKind::Sim`] is an error (code 3099): the runtime owns the simulated I/O.
pub fn open(
    kind: IoKind,
    machine_dir: &Path,
    declared: &DeclaredConnectors,
) -> Result<Box<dyn PacketIo>, Vec<Diagnostic>> {
    if kind == IoKind::Sim {
        return Err(whole_file(
            codes::SIM,
            "the simulated I/O is built into the runtime, not the fieldbus crate".into(),
            "call fieldbus::open only for --io modbus or --io canopen",
        ));
    }
    let (map, diags) = load_map(machine_dir, declared);
    let Some(map) = map else { return Err(diags) };
    open_map(kind, &map)
}

/// Starts the driver for `kind` from an already validated map.
pub fn open_map(kind: IoKind, map: &IoMap) -> Result<Box<dyn PacketIo>, Vec<Diagnostic>> {
    let start_err = |e: std::io::Error| {
        whole_file(
            codes::START,
            format!("the {kind} driver cannot start: {e}"),
            "check the addresses and interfaces in io.toml",
        )
    };
    match kind {
        IoKind::Sim => Err(whole_file(
            codes::SIM,
            "the simulated I/O is built into the runtime".into(),
            "",
        )),
        IoKind::Modbus => {
            if map.modbus.is_empty() {
                return Err(whole_file(
                    codes::NO_DEVICES,
                    "io.toml defines no Modbus device".into(),
                    "add a [[modbus.device]] table",
                ));
            }
            let io = modbus::client::ModbusIo::start_pinned(&map.modbus, &map.io_cpus)
                .map_err(start_err)?;
            Ok(Box::new(io))
        }
        IoKind::Canopen => {
            let Some(cfg) = map.canopen.as_ref().filter(|c| !c.nodes.is_empty()) else {
                return Err(whole_file(
                    codes::NO_DEVICES,
                    "io.toml defines no CANopen node".into(),
                    "add a [canopen] table with [[canopen.node]] entries",
                ));
            };
            let io = start_canopen(cfg, &map.io_cpus, None).map_err(start_err)?;
            Ok(Box::new(io))
        }
    }
}

/// Reads and validates `<machine_dir>/io.toml` and starts its CANopen master with the CiA 402
/// drives clocked by `timing` (a part run's kernel orders them through
/// [`canopen::master::CanopenIo::drives`]). On the `virtual` transport, `machine` gives the
/// simulated drive of (process, axis) the machine behind it (home switch, zero impulses; axis
/// units), so that it can be homed.
pub fn open_canopen(
    machine_dir: &Path,
    declared: &DeclaredConnectors,
    timing: canopen::drive::DriveTiming,
    machine: &dyn Fn(u32, char) -> Option<canopen::drive_sim::SimMachine>,
) -> Result<canopen::master::CanopenIo, Vec<Diagnostic>> {
    let (map, diags) = load_map(machine_dir, declared);
    let Some(mut map) = map else {
        return Err(diags);
    };
    if let Some(c) = map.canopen.as_mut() {
        for d in &mut c.drives {
            d.simulate.machine = machine(d.process, d.axis);
        }
    }
    let Some(cfg) = map.canopen.as_ref().filter(|c| !c.nodes.is_empty()) else {
        return Err(whole_file(
            codes::NO_DEVICES,
            "io.toml defines no CANopen node".into(),
            "add a [canopen] table with [[canopen.node]] entries",
        ));
    };
    if timing.lockstep && cfg.transport != map::TransportConfig::Virtual {
        return Err(whole_file(
            codes::START,
            "virtual time runs only on the virtual bus: real drives keep real time".into(),
            "drop --virtual-time, or set [canopen] transport = \"virtual\" for simulated drives",
        ));
    }
    start_canopen(cfg, &map.io_cpus, Some(timing)).map_err(|e| {
        // A drive that refused its start-up has its own code (3077), naming node, object, abort.
        if let Some(d) = e
            .get_ref()
            .and_then(|i| i.downcast_ref::<canopen::drive::startup::DriveStartError>())
        {
            let span = cfg
                .drives
                .iter()
                .find(|c| Some(c.node_id) == d.node())
                .map_or(0..0, |c| c.span.clone());
            // Located in io.toml's text as it was read (a file changed since reads as unlocated).
            let diag = d.diagnostic(span);
            return vec![match diag::read_config(&machine_dir.join("io.toml")) {
                Ok(text) => {
                    let index = diag::LineIndex::new(&text);
                    diag.locate_in(&text, &index)
                }
                Err(_) => diag,
            }];
        }
        whole_file(
            codes::START,
            format!("the canopen driver cannot start: {e}"),
            "check the drives and nodes in io.toml (docs/drives.md: start-up)",
        )
    })
}

/// Starts the CANopen master on the configured transport, with its CiA 402 drives clocked by
/// `timing` (None: one SYNC per 10 ms tick; nothing orders them, so they stay disabled). The
/// `virtual` transport also starts one simulated CiA 401 node per configured node and one
/// simulated CiA 402 drive per drive on the same in-process bus (a machine without hardware);
/// the nodes' terminals are then wired to packet A ([`canopen::master::CanopenIo::sim_wiring`]).
/// The master's threads are pinned to `io_cpus` (empty = unpinned).
pub fn start_canopen(
    cfg: &map::CanopenConfig,
    io_cpus: &[usize],
    timing: Option<canopen::drive::DriveTiming>,
) -> std::io::Result<canopen::master::CanopenIo> {
    use canopen::master::CanopenIo;
    match &cfg.transport {
        map::TransportConfig::Virtual => {
            let drives: Vec<_> = cfg
                .drives
                .iter()
                .map(|d| (d.node_id, d.simulate, d.counts_per_unit))
                .collect();
            let lockstep = timing.is_some_and(|t| t.lockstep);
            // In lock-step the I/O nodes' heartbeat runs on the SYNCs, as the drives' does.
            let period_us = match timing {
                Some(t) if t.lockstep => {
                    let p = canopen::master::sync_period(&t, !drives.is_empty());
                    u32::try_from(p.as_micros()).unwrap_or(u32::MAX).max(1)
                }
                _ => 0,
            };
            let states: Vec<_> = cfg
                .nodes
                .iter()
                .map(|n| {
                    let state = canopen::node_sim::Cia401Node::new_state(period_us);
                    state
                        .lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner)
                        .silent_at_sync = n.simulate.silent_at_sync;
                    (n.node_id, state)
                })
                .collect();
            let spawned = states.clone();
            let mut io = CanopenIo::start_with_drives(cfg, io_cpus, timing, move || async move {
                let bus = canopen::virtual_bus::VirtualBus::new();
                for (id, state) in spawned {
                    // The node lives as long as the master's runtime.
                    std::mem::forget(canopen::node_sim::Cia401Node::spawn_with(
                        bus.port(),
                        id,
                        state,
                    ));
                }
                for (id, hooks, counts) in drives {
                    let node = canopen::drive_sim::Cia402Node::spawn(bus.port(), id);
                    {
                        let mut st = node.state();
                        st.fault_at_sync = hooks.fault;
                        st.heartbeat_stop_at_sync = hooks.heartbeat_stop;
                        st.refuse_enable = hooks.refuse_enable;
                        st.sdo_abort = hooks.sdo_abort;
                        st.sync_heartbeat = lockstep;
                        st.machine = hooks.machine.map(|m| m.scaled(counts));
                        st.max_speed = hooks.max_speed;
                    }
                    // The drive lives as long as the master's runtime.
                    std::mem::forget(node);
                }
                Ok(bus.port())
            })?;
            io.set_sim_wiring(canopen::sim_wiring::SimWiring::new(cfg, &states));
            Ok(io)
        }
        map::TransportConfig::SocketCan { interface } => {
            let name = interface.clone();
            CanopenIo::start_with_drives(cfg, io_cpus, timing, move || async move {
                canopen::socketcan_bus::SocketCanBus::open(&name)
            })
        }
        map::TransportConfig::Cannelloni { local, remote } => {
            let (l, r) = (*local, *remote);
            CanopenIo::start_with_drives(cfg, io_cpus, timing, move || {
                canopen::cannelloni::UdpBus::bind(l, r)
            })
        }
    }
}

/// Wraps `inner` with the HMI/SCADA Modbus TCP server when `<machine_dir>/io.toml` has an `[hmi]`
/// table; returns `inner` unchanged when there is no `io.toml` or no `[hmi]`.
pub fn start_hmi(
    machine_dir: &Path,
    declared: &DeclaredConnectors,
    inner: Box<dyn PacketIo>,
) -> Result<Box<dyn PacketIo>, Vec<Diagnostic>> {
    start_hmi_at(machine_dir, declared, inner, None)
}

/// [`start_hmi`], listening on `bind` instead of the `[hmi] bind` of io.toml when given
/// (`ncplc run --modbus-hmi ADDR:PORT`); `bind` without an `[hmi]` table is an error (3060).
pub fn start_hmi_at(
    machine_dir: &Path,
    declared: &DeclaredConnectors,
    inner: Box<dyn PacketIo>,
    bind: Option<std::net::SocketAddr>,
) -> Result<Box<dyn PacketIo>, Vec<Diagnostic>> {
    start_hmi_listening(machine_dir, declared, inner, bind).map(|(io, _)| io)
}

/// The I/O with the HMI server in front, and the address the server took (`None`: no server).
pub type Listening = (Box<dyn PacketIo>, Option<std::net::SocketAddr>);

/// [`start_hmi_at`], also returning the address the server took (`None`: no server), so that a
/// caller who bound port 0 can tell its users.
pub fn start_hmi_listening(
    machine_dir: &Path,
    declared: &DeclaredConnectors,
    inner: Box<dyn PacketIo>,
    bind: Option<std::net::SocketAddr>,
) -> Result<Listening, Vec<Diagnostic>> {
    let no_hmi = |bind: Option<std::net::SocketAddr>, inner| match bind {
        None => Ok((inner, None)),
        Some(b) => Err(whole_file(
            codes::START,
            format!("--modbus-hmi {b}: io.toml has no [hmi] table to serve"),
            "add an [hmi] table with the holding-register windows the HMI may write",
        )),
    };
    if !machine_dir.join("io.toml").is_file() {
        return no_hmi(bind, inner);
    }
    let (map, diags) = load_map(machine_dir, declared);
    let Some(map) = map else { return Err(diags) };
    let Some(mut cfg) = map.hmi else {
        return no_hmi(bind, inner);
    };
    if let Some(b) = bind {
        cfg.bind = b;
    }
    match modbus::server::HmiIo::start(inner, &cfg) {
        Ok(h) => {
            let addr = h.local_addr();
            Ok((Box::new(h), Some(addr)))
        }
        Err(e) => Err(whole_file(
            codes::START,
            format!("the HMI server cannot listen on {}: {e}", cfg.bind),
            "choose a free address with [hmi] bind = \"127.0.0.1:1502\" or --modbus-hmi 127.0.0.1:1503",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn io_kind_parses_and_prints_the_cli_names() {
        for name in IoKind::NAMES {
            assert_eq!(name.parse::<IoKind>().expect("known").to_string(), name);
        }
        assert_eq!("MODBUS".parse::<IoKind>(), Ok(IoKind::Modbus));
        assert_eq!("can".parse::<IoKind>(), Err(IoKindError("can".into())));
        assert_eq!(IoKind::default(), IoKind::Sim);
    }

    #[test]
    fn open_sim_is_refused_with_its_code() {
        let err = open(
            IoKind::Sim,
            Path::new("/nonexistent"),
            &DeclaredConnectors::default(),
        )
        .err()
        .expect("refused");
        assert_eq!(err[0].code, codes::SIM);
    }

    #[test]
    fn open_without_a_map_reports_the_missing_file() {
        let dir = tempfile::tempdir().expect("tempdir");
        let err = open(IoKind::Modbus, dir.path(), &DeclaredConnectors::default())
            .err()
            .expect("no map");
        assert_eq!(err.len(), 1);
        assert_eq!(err[0].code, codes::UNREADABLE);
    }
}
