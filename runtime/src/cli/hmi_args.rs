//! The `--hmi` options of `ncplc run` and starting the web HMI from them.

use std::net::SocketAddr;
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
    /// Serve the web HMI (default 127.0.0.1:8080; a non-loopback address needs the access token).
    #[arg(long, value_name = "ADDR:PORT", num_args = 0..=1, default_missing_value = "127.0.0.1:8080")]
    pub hmi: Option<SocketAddr>,
    /// The HMI only watches: writes, forces and commands are refused.
    #[arg(long, requires = "hmi")]
    pub hmi_readonly: bool,
    /// Read the HMI access token from this file (otherwise one is generated and printed for a
    /// non-loopback address).
    #[arg(long, value_name = "FILE", requires = "hmi")]
    pub hmi_token_file: Option<PathBuf>,
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
        let token = match &self.hmi_token_file {
            Some(path) => {
                let t = std::fs::read_to_string(path)
                    .map_err(|e| format!("error: --hmi-token-file {}: {e}", path.display()))?;
                let t = t.trim().to_string();
                if t.is_empty() {
                    return Err(format!(
                        "error: --hmi-token-file {}: the file is empty",
                        path.display()
                    ));
                }
                Some(t)
            }
            None if !hmi::auth::is_loopback(&addr) => {
                Some(hmi::auth::generate_token().map_err(|e| format!("error: HMI token: {e}"))?)
            }
            None => None,
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
        let config = hmi::ServerConfig {
            addr,
            token: token.clone(),
            readonly: self.hmi_readonly,
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
        match &token {
            Some(t) if self.hmi_token_file.is_none() => {
                eprintln!("hmi: http://{bound}/?token={t}  (access token {t})")
            }
            _ => eprintln!("hmi: http://{bound}/"),
        }
        if self.hmi_readonly {
            eprintln!("hmi: read-only");
        }
        Ok(Some(link))
    }
}
