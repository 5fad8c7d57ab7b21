//! The OPC UA server of ncplc (`ncplc run --opcua [ADDR:PORT]`, issue 25), on async-opcua: the
//! packet signals and the PLC's names as variables (docs/opcua.md), beside the scan as a
//! [`controller::servers::Server`].
//!
//! **Invariant:** the scan's side is [`handoff::ScanSide::after_tick`]: a copy of the packets into
//! a wait-free ring and a `try_recv` loop for accepted writes. The address space, its lock and
//! every client request live on the server's own thread ([`server`]); the scan never waits.

pub mod auth;
pub mod config;
pub mod derive;
pub mod handoff;
pub mod latency;
pub mod limits;
pub mod machine_tool;
pub mod node_manager;
pub mod nodesets;
pub mod publisher;
pub mod server;
pub mod settings;
pub mod signals;
pub mod space;
pub mod users;
pub mod values;
pub mod variables;
pub mod window;

use controller::machine::Machine;
use controller::servers::{Server, Start};
use runtime::scheduler::{Event, Scheduler};

pub use settings::{DEFAULT_ENDPOINT, Settings, parse_endpoint};

/// The OPC UA server as one of a controller's servers.
pub struct OpcuaServer {
    settings: Settings,
    limits: limits::Limits,
    scan: Option<handoff::ScanSide>,
    running: Option<server::Running>,
}

impl OpcuaServer {
    /// A server that starts with the controller.
    pub fn new(settings: Settings) -> OpcuaServer {
        OpcuaServer {
            settings,
            limits: limits::Limits::default(),
            scan: None,
            running: None,
        }
    }

    /// The address it listens on, once started.
    pub fn local_addr(&self) -> Option<std::net::SocketAddr> {
        self.running.as_ref().map(|r| r.addr)
    }
}

/// The named signals of `machine`: interface-map names and the program's `DEF` aliases
/// (name, address, meaning, from the program).
fn named_signals(
    machine: &Machine,
) -> Result<Vec<(String, packets::Signal, String, bool)>, String> {
    let source = machine.read_source().map_err(|e| format!("error: {e}"))?;
    let catalog = controller::hmi_link::catalog::build(machine, &source);
    Ok(catalog
        .names
        .into_iter()
        .map(|n| (n.name, n.signal, n.meaning, n.origin == "program"))
        .collect())
}

/// What the Machine Tools instance shows of `machine`.
fn model_inputs(
    machine: &Machine,
    tables: config::Tables,
    program: Option<String>,
    commands: bool,
) -> machine_tool::Inputs {
    let processes = machine.process_numbers();
    let role = |p: u8, r: &str| machine.interface.role(p, r).map(|s| s.signal);
    machine_tool::Inputs {
        name: machine.dir.file_name().map_or_else(
            || "machine".to_string(),
            |n| n.to_string_lossy().into_owned(),
        ),
        identification: tables.identification.unwrap_or_default(),
        processes: processes
            .into_iter()
            .map(|p| machine_tool::ProcessRoles {
                process: p,
                cycle: role(p, "CYCLE"),
                hold: role(p, "HOLD"),
                mode: role(p, "MODE"),
                fov: role(p, "FOV"),
                rov: role(p, "ROV"),
                sov: role(p, "SOV"),
                scode: role(p, "SCODE"),
            })
            .collect(),
        lamps: tables.stacklight,
        program,
        commands,
    }
}

impl Server for OpcuaServer {
    fn start(&mut self, start: Start<'_>) -> Result<(), String> {
        let Start {
            machine,
            tick_ms,
            kernel,
            meta,
        } = start;
        let window = window::Window::load(&machine.dir, &machine.declared_connectors())
            .map_err(|d| render_map_errors(&machine.dir, &d))?;
        let tables = config::load(&machine.dir).map_err(|d| render_map_errors(&machine.dir, &d))?;
        let table = signals::table(&named_signals(machine)?, &window);
        let users = match &self.settings.users {
            Some(path) => {
                let text = diag::read_config(path)
                    .map_err(|e| format!("error: --opcua-users {}: {e}", path.display()))?;
                users::Users::parse(&text)
                    .map_err(|e| format!("error: --opcua-users {}:{e}", path.display()))?
            }
            None => users::Users::default(),
        };
        let loopback = settings::is_loopback(self.settings.addr.ip());
        if !loopback && users.is_empty() {
            return Err(format!(
                "error: --opcua {}: off loopback the server refuses anonymous sessions; give --opcua-users FILE (docs/opcua.md)",
                self.settings.addr
            ));
        }
        let (mut scan, side) = handoff::pair();
        scan.kernel = kernel.map(|(k, _)| k);
        scan.vars = variables::Layout::of(runtime::compiled::base_program(meta.as_ref()));
        if !scan.vars.left_out.is_empty() {
            eprintln!(
                "opcua: warning: {} PLC variables lie past the first {} bytes of variables and are not served: {}",
                scan.vars.left_out.len(),
                variables::VARS_MAX,
                scan.vars.left_out.join(", ")
            );
        }
        let running = server::start(
            server::Plan {
                addr: self.settings.addr,
                machine_dir: &machine.dir,
                table,
                tick_ms,
                limits: self.limits,
                model: model_inputs(
                    machine,
                    tables,
                    self.settings.program.clone(),
                    scan.kernel.is_some(),
                ),
                users,
                vars: scan.vars.clone(),
            },
            side,
        )
        .map_err(|e| format!("error: {e}"))?;
        let security = if loopback {
            "security None, loopback"
        } else {
            "Basic256Sha256 Sign and SignAndEncrypt, users only"
        };
        eprintln!(
            "opcua: {} ({security})",
            settings::endpoint_url(running.addr)
        );
        self.scan = Some(scan);
        self.running = Some(running);
        Ok(())
    }

    fn on_event(&mut self, event: &Event, tick: u64) {
        let (Some(s), note) = (&self.scan, event) else {
            return;
        };
        // A send only fails once the server has stopped: nothing is waiting for the alarm then.
        let _ = match note {
            Event::Alarm(a) => s.alarms.send((true, a.clone(), tick)),
            Event::Cleared(a) => s.alarms.send((false, a.clone(), tick)),
            Event::Swapped { .. } => Ok(()),
        };
    }

    fn on_message(&mut self, m: &controller::plc_messages::MessageEvent) {
        if let Some(s) = &self.scan {
            // A send only fails once the server has stopped.
            let _ = s.messages.send(handoff::MessageNote {
                raised: m.raised,
                process: m.entry.process,
                text: m.entry.text.clone(),
                severity: m.entry.severity,
                tick: m.tick,
            });
        }
    }

    fn after_tick(&mut self, sched: &mut Scheduler) {
        if let Some(s) = &mut self.scan {
            s.after_tick(sched);
        }
    }
}

/// io.toml's diagnostics rendered with its lines.
fn render_map_errors(dir: &std::path::Path, diagnostics: &[diag::Diagnostic]) -> String {
    let mut sources = diag::Sources::new();
    if let Ok(text) = diag::read_config(&dir.join("io.toml")) {
        for d in diagnostics {
            sources.add(d.file.clone(), text.clone());
        }
    }
    runtime::render::render_diagnostics(diagnostics, &sources)
}
