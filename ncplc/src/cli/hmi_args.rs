//! The `--hmi` options of `ncplc run`, turned into the controller's web-HMI settings.

use std::net::SocketAddr;

use clap::builder::TypedValueParser as _;
use std::path::PathBuf;

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
    /// The controller's web-HMI settings when `--hmi` was given (the controller starts it).
    pub fn settings(&self) -> Option<controller::settings::Hmi> {
        self.hmi.map(|addr| controller::settings::Hmi {
            addr,
            readonly: self.hmi_readonly,
            token_file: self.hmi_token_file.clone(),
            allow_hosts: self.hmi_allow_host.clone(),
            allow_origins: self.hmi_allow_origin.clone(),
            tls: match (&self.hmi_tls_cert, &self.hmi_tls_key) {
                (Some(cert), Some(key)) => Some(hmi::security::tls::TlsFiles {
                    cert: cert.clone(),
                    key: key.clone(),
                }),
                _ => None,
            },
            limits: hmi::security::limits::Limits {
                max_body: self.hmi_max_body,
                max_clients: self.hmi_max_clients,
                ws_max_message: self.hmi_ws_max_message,
                ws_rate: self.hmi_ws_rate,
                idle: hmi::security::limits::Limits::default().idle,
            },
        })
    }
}
