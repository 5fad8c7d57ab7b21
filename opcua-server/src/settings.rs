//! What `ncplc run --opcua [ADDR:PORT]` asks of the OPC UA server: where it listens and who may
//! connect. Plain data and the parsing of the endpoint text; nothing here opens a socket.
//!
//! **Invariant:** a [`Settings`] always holds a concrete socket address (`opc.tcp://` stripped,
//! the host resolved to an IP literal), so the server's endpoint URL and its loopback check agree.

use std::net::{IpAddr, SocketAddr};
use std::path::PathBuf;

/// The default endpoint (`--opcua` without a value).
pub const DEFAULT_ENDPOINT: &str = "opc.tcp://127.0.0.1:4840";

/// The OPC UA server's settings.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Settings {
    /// Where it listens.
    pub addr: SocketAddr,
    /// The users file (`ROLE USER PASSWORD` lines), required off loopback.
    pub users: Option<PathBuf>,
    /// The partprogram the run was given (`--program`): the active program's name.
    pub program: Option<String>,
}

/// Why an endpoint text was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EndpointError {
    /// Not `[opc.tcp://]IP:PORT`.
    #[error(
        "--opcua {0}: expected [opc.tcp://]IP:PORT, e.g. opc.tcp://127.0.0.1:4840 or 0.0.0.0:4840"
    )]
    Malformed(String),
}

/// Parses `opc.tcp://IP:PORT` or `IP:PORT` (`localhost` is taken as 127.0.0.1).
pub fn parse_endpoint(text: &str) -> Result<SocketAddr, EndpointError> {
    let bare = text.strip_prefix("opc.tcp://").unwrap_or(text);
    let bare = bare.strip_suffix('/').unwrap_or(bare);
    let bare = match bare.strip_prefix("localhost:") {
        Some(port) => format!("127.0.0.1:{port}"),
        None => bare.to_string(),
    };
    bare.parse::<SocketAddr>()
        .map_err(|_| EndpointError::Malformed(text.to_string()))
}

/// True when only this host can reach `ip` (127.0.0.0/8, ::1).
pub fn is_loopback(ip: IpAddr) -> bool {
    ip.is_loopback()
}

/// The endpoint URL clients use for `addr`.
pub fn endpoint_url(addr: SocketAddr) -> String {
    format!("opc.tcp://{addr}/")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_parse_with_and_without_the_scheme() {
        let want: SocketAddr = "127.0.0.1:4840".parse().expect("literal");
        assert_eq!(parse_endpoint(DEFAULT_ENDPOINT), Ok(want));
        assert_eq!(parse_endpoint("127.0.0.1:4840"), Ok(want));
        assert_eq!(parse_endpoint("opc.tcp://localhost:4840/"), Ok(want));
        assert_eq!(
            parse_endpoint("opc.tcp://[::1]:4841").map(|a| a.port()),
            Ok(4841)
        );
        assert_eq!(
            parse_endpoint("http://127.0.0.1:4840"),
            Err(EndpointError::Malformed("http://127.0.0.1:4840".into()))
        );
        assert!(parse_endpoint("127.0.0.1").is_err());
        assert_eq!(endpoint_url(want), "opc.tcp://127.0.0.1:4840/");
    }
}
