//! The `--hmi` options of `ncplc run`, turned into the controller's web-HMI settings.

use std::net::SocketAddr;
use std::path::PathBuf;

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
    /// The controller's web-HMI settings when `--hmi` was given (the controller starts it).
    pub fn settings(&self) -> Option<controller::settings::Hmi> {
        self.hmi.map(|addr| controller::settings::Hmi {
            addr,
            readonly: self.hmi_readonly,
            token_file: self.hmi_token_file.clone(),
        })
    }
}
