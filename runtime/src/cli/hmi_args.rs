//! The `--hmi` options of `ncplc run` and starting the web HMI from them.

use std::net::SocketAddr;

use clap::builder::TypedValueParser as _;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use crate::hmi_link::kernel_cnc::KernelCnc;
use crate::hmi_link::{HmiLink, catalog, image_cnc::ImageCnc};
use crate::machine::Machine;
use crate::sim::HandshakeCounts;

/// A part run's kernel and its partprograms' texts (name, text), for the Machine page.
pub type PartKernel = (Arc<Mutex<cnc::Cnc>>, Vec<(String, String)>);

/// The web HMI options.
#[derive(Debug, Clone, clap::Args)]
pub struct HmiArgs {
    /// Serve the web HMI (default 127.0.0.1:8080); every request needs the session token of
    /// the address printed at start (docs/hmi-security.md).
    #[arg(long, value_name = "ADDR:PORT", num_args = 0..=1, default_missing_value = "127.0.0.1:8080")]
    pub hmi: Option<SocketAddr>,
    /// The HMI only watches: everyone is a viewer (writes, forces, commands and the power-flow
    /// switch are refused).
    #[arg(long, requires = "hmi")]
    pub hmi_readonly: bool,
    /// Read the HMI's tokens from this file, one `ROLE TOKEN` a line (viewer, operator,
    /// integrator), or a single token with every right; otherwise one integrator token is
    /// generated and printed in the start URL.
    #[arg(long, value_name = "FILE", requires = "hmi")]
    pub hmi_token_file: Option<PathBuf>,
    /// Another name the HMI answers to in the `Host` header (`NAME` or `NAME:PORT`; repeatable).
    #[arg(long, value_name = "NAME", requires = "hmi")]
    pub hmi_allow_host: Vec<String>,
    /// Another origin whose pages may change the machine or open the WebSocket
    /// (`http://panel.lan:8080`; repeatable).
    #[arg(long, value_name = "ORIGIN", requires = "hmi")]
    pub hmi_allow_origin: Vec<String>,
    /// Serve HTTPS with this certificate chain (PEM).
    #[arg(long, value_name = "FILE", requires_all = ["hmi", "hmi_tls_key"])]
    pub hmi_tls_cert: Option<PathBuf>,
    /// The private key of --hmi-tls-cert (PEM).
    #[arg(long, value_name = "FILE", requires_all = ["hmi", "hmi_tls_cert"])]
    pub hmi_tls_key: Option<PathBuf>,
    /// Largest request body in bytes.
    #[arg(long, value_name = "BYTES", requires = "hmi", default_value_t = hmi::security::limits::Limits::default().max_body)]
    pub hmi_max_body: usize,
    /// Most connections open at once.
    #[arg(long, value_name = "N", requires = "hmi", default_value_t = hmi::security::limits::Limits::default().max_clients,
          value_parser = clap::value_parser!(u16).range(1..).map(usize::from))]
    pub hmi_max_clients: usize,
    /// Largest WebSocket message from a client in bytes.
    #[arg(long, value_name = "BYTES", requires = "hmi", default_value_t = hmi::security::limits::Limits::default().ws_max_message)]
    pub hmi_ws_max_message: usize,
    /// Most WebSocket messages per second from one client.
    #[arg(long, value_name = "N", requires = "hmi", default_value_t = hmi::security::limits::Limits::default().ws_rate)]
    pub hmi_ws_rate: u32,
    /// Start with power flow on the Program page (switchable at run time: `POST /api/flow`, the
    /// page's toggle): every statement also writes its result into a flow area (costs scan time:
    /// +27 % instructions per tick on the 10,000-statement scan benchmark).
    #[arg(long, requires = "hmi")]
    pub hmi_flow: bool,
}

impl HmiArgs {
    /// Starts the HMI when `--hmi` was given; `kernel` is the CNC kernel of a part run with the
    /// partprograms' texts (name, text), which then drives the Machine page.
    pub fn start(
        &self,
        machine: &Machine,
        source: &[u8],
        tick_ms: u32,
        counts: Option<HandshakeCounts>,
        kernel: Option<PartKernel>,
        flow: crate::hmi_link::flow_switch::FlowSwitch,
    ) -> Result<Option<HmiLink>, String> {
        let Some(addr) = self.hmi else {
            return Ok(None);
        };
        let tokens = match &self.hmi_token_file {
            Some(path) => {
                let t = std::fs::read_to_string(path)
                    .map_err(|e| format!("error: --hmi-token-file {}: {e}", path.display()))?;
                hmi::Tokens::parse(&t)
                    .map_err(|e| format!("error: --hmi-token-file {}:{e}", path.display()))?
            }
            None => hmi::Tokens::generate().map_err(|e| format!("error: HMI token: {e}"))?,
        };
        let tls = match (&self.hmi_tls_cert, &self.hmi_tls_key) {
            (Some(cert), Some(key)) => Some(hmi::security::tls::TlsFiles {
                cert: cert.clone(),
                key: key.clone(),
            }),
            _ => None,
        };
        let processes: Vec<u8> = if machine.signals.processes.is_empty() {
            vec![1]
        } else {
            machine
                .signals
                .processes
                .iter()
                .map(|p| p.process)
                .collect()
        };
        let image = ImageCnc::new(&machine.interface, &processes, counts);
        let cnc: Box<dyn crate::hmi_link::Cnc> = match kernel {
            Some((k, sources)) => Box::new(KernelCnc::new(k, image, &sources)),
            None => Box::new(image),
        };
        let defaults = hmi::security::limits::Limits::default();
        let config = hmi::ServerConfig {
            addr,
            tokens: tokens.clone(),
            readonly: self.hmi_readonly,
            allow_hosts: self.hmi_allow_host.clone(),
            allow_origins: self.hmi_allow_origin.clone(),
            tls: tls.clone(),
            limits: hmi::security::limits::Limits {
                max_body: self.hmi_max_body,
                max_clients: self.hmi_max_clients,
                ws_max_message: self.hmi_ws_max_message,
                ws_rate: self.hmi_ws_rate,
                idle: defaults.idle,
            },
        };
        let link = HmiLink::start(
            config,
            catalog::build(machine, source),
            cnc,
            tick_ms,
            Some(flow),
        )
        .map_err(|e| format!("error: {e}"))?;
        let bound = link.running.addr;
        let scheme = if tls.is_some() { "https" } else { "http" };
        match (&self.hmi_token_file, tokens.first()) {
            (None, Some(t)) => eprintln!("hmi: {scheme}://{bound}/?token={t}"),
            _ => {
                let (v, o, i) = tokens.counts();
                eprintln!(
                    "hmi: {scheme}://{bound}/  (open it with ?token=YOUR_TOKEN; the token file gives {v} viewer, {o} operator, {i} integrator)"
                )
            }
        }
        if !hmi::is_loopback(&bound) && tls.is_none() {
            eprintln!(
                "hmi: warning: {bound} is reachable from the network and the HMI speaks plain HTTP: anyone on the network path can read the session token and the machine's state, and with the token write, force and start the machine; give --hmi-tls-cert and --hmi-tls-key (docs/hmi-security.md)"
            );
        }
        if self.hmi_readonly {
            eprintln!("hmi: read-only");
        }
        Ok(Some(link))
    }
}
