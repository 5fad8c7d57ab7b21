//! The servers of a controller: the web HMI (crate `hmi`, through [`crate::hmi_link`]) and the
//! extension point for others ([`Server`]: an OPC UA server, …). The Modbus HMI sits in front of the
//! I/O instead ([`crate::io::with_modbus_hmi`]).
//!
//! A server is started with a [`Start`]: the machine, the logic tick and, in a part run, the
//! CNC kernel ([`PartKernel`]); operator commands go to that kernel through [`kernel_command`],
//! the web HMI's path (the same `apply_command`, recorded in the trace the same way).
//!
//! **Invariant:** the scan never waits for a server: [`Server::after_tick`] runs on the scan thread
//! and must only copy (into a triple buffer, a `watch`) and drain requests with `try_recv`, as
//! `hmi_link` does; a command is applied there, at the tick boundary, never from a server task.

use std::sync::{Arc, Mutex};

use runtime::online::Note;
use runtime::scheduler::{Event, Scheduler};
use sim::HandshakeCounts;

use crate::hmi_link::flow_switch::FlowSwitch;
use crate::hmi_link::kernel_cnc::KernelCnc;
use crate::hmi_link::{HmiLink, catalog, image_cnc::ImageCnc};
use crate::machine::Machine;
use crate::settings::Hmi;

/// What a server is started with.
pub struct Start<'a> {
    /// The machine.
    pub machine: &'a Machine,
    /// The logic tick (ms).
    pub tick_ms: u32,
    /// A part run's kernel and its programs' texts (None without `--program`/`--mdi`).
    pub kernel: Option<PartKernel>,
    /// The PLC program loaded for the first tick (its variables and their image offsets).
    pub meta: Arc<dyn runtime::program::ProgramMeta>,
}

/// A server beside the scan, given the scheduler after every tick (to publish its image and apply
/// requests at the tick boundary) and every event. Added with [`crate::Builder::server`].
pub trait Server: Send {
    /// Called once, after the controller is assembled and before the first tick.
    fn start(&mut self, start: Start<'_>) -> Result<(), String>;
    /// An event of the tick just run (alarm, cleared alarm, online change).
    fn on_event(&mut self, _event: &Event, _tick: u64) {}
    /// An online-change note (compiled, rejected, error).
    fn on_note(&mut self, _note: &Note) {}
    /// A PLC message raised or cleared by the tick just run (docs/plc-messages.md).
    fn on_message(&mut self, _message: &crate::plc_messages::MessageEvent) {}
    /// After every tick, on the scan thread: publish (copy only) and apply requests.
    fn after_tick(&mut self, sched: &mut Scheduler);
}

/// A part run's kernel and its partprograms' texts (name, text), for the Machine page.
pub type PartKernel = (Arc<Mutex<cnc::Cnc>>, Vec<(String, String)>);

/// Gives operator command `command` for `process` to a part run's kernel at a tick boundary, the
/// web HMI's way ([`crate::hmi_link::kernel_cnc::apply_command`]), and records it in the trace with
/// the `role` that sent it, so a replay gives it to its kernel at the same tick. The tick it was
/// applied at, or the kernel's reason for refusing it. Call it on the scan thread only (from
/// [`Server::after_tick`]).
pub fn kernel_command(
    sched: &mut Scheduler,
    kernel: &Mutex<cnc::Cnc>,
    process: u8,
    command: &hmi::Command,
    role: hmi::Role,
) -> Result<u64, String> {
    let applied_at = sched.tick_count();
    {
        let mut c = kernel
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        crate::hmi_link::kernel_cnc::apply_command(&mut c, process, command)?;
    }
    sched.record_command(trace::OperatorCommand {
        process,
        command: command.clone(),
        role: Some(role),
    });
    Ok(applied_at)
}

/// The session tokens of the HMI: read from `token_file` (`ROLE TOKEN` lines, or one token with
/// every right), else one integrator token generated from the OS's CSPRNG.
pub fn hmi_token(hmi: &Hmi) -> Result<hmi::Tokens, String> {
    match &hmi.token_file {
        Some(path) => {
            let t = diag::read_config(path)
                .map_err(|e| format!("error: --hmi-token-file {}: {e}", path.display()))?;
            hmi::Tokens::parse(&t)
                .map_err(|e| format!("error: --hmi-token-file {}:{e}", path.display()))
        }
        None => hmi::Tokens::generate().map_err(|e| format!("error: HMI token: {e}")),
    }
}

/// What the web HMI shows besides the program: the simulated CNC's counts or a part run's kernel.
pub struct HmiInputs<'a> {
    /// The PLC source (for the catalog's source lines).
    pub source: &'a [u8],
    /// The logic tick.
    pub tick_ms: u32,
    /// The simulated CNC's handshake counts.
    pub counts: Option<HandshakeCounts>,
    /// A part run's kernel with its programs' texts.
    pub kernel: Option<PartKernel>,
    /// The run-time power-flow switch.
    pub flow: FlowSwitch,
}

/// Starts the web HMI with `tokens` (see [`hmi_token`]) and says on stderr where it listens.
pub fn start_hmi(
    hmi: &Hmi,
    tokens: hmi::Tokens,
    machine: &Machine,
    inputs: HmiInputs<'_>,
) -> Result<HmiLink, String> {
    let processes = machine.process_numbers();
    let image = ImageCnc::new(&machine.interface, &processes, inputs.counts);
    let cnc: Box<dyn crate::hmi_link::Cnc> = match inputs.kernel {
        Some((k, sources)) => Box::new(KernelCnc::new(k, image, &sources)),
        None => Box::new(image),
    };
    let config = hmi::ServerConfig {
        addr: hmi.addr,
        tokens: tokens.clone(),
        readonly: hmi.readonly,
        allow_hosts: hmi.allow_hosts.clone(),
        allow_origins: hmi.allow_origins.clone(),
        tls: hmi.tls.clone(),
        limits: hmi.limits,
    };
    let link = HmiLink::start(
        config,
        catalog::build(machine, inputs.source),
        cnc,
        inputs.tick_ms,
        Some(inputs.flow),
    )
    .map_err(|e| format!("error: {e}"))?;
    let bound = link.running.addr;
    let scheme = if hmi.tls.is_some() { "https" } else { "http" };
    match (&hmi.token_file, tokens.first()) {
        (None, Some(t)) => eprintln!("hmi: {scheme}://{bound}/?token={t}"),
        _ => {
            let (v, o, i) = tokens.counts();
            eprintln!(
                "hmi: {scheme}://{bound}/  (open it with ?token=YOUR_TOKEN; the token file gives {v} viewer, {o} operator, {i} integrator)"
            )
        }
    }
    if !hmi::is_loopback(&bound) && hmi.tls.is_none() {
        eprintln!(
            "hmi: warning: {bound} is reachable from the network and the HMI speaks plain HTTP: anyone on the network path can read the session token and the machine's state, and with the token write, force and start the machine; give --hmi-tls-cert and --hmi-tls-key (docs/hmi-security.md)"
        );
    }
    if hmi.readonly {
        eprintln!("hmi: read-only");
    }
    Ok(link)
}
