//! The `Host` allow-list: what stops a DNS-rebinding page (a foreign name resolving to this
//! machine) from talking to the HMI from the operator's own browser.
//!
//! Allowed: `localhost`, `127.0.0.1`, `[::1]`, the bound address and the `--hmi-allow-host`
//! names, each with the bound port (or without a port when the port is the scheme's default);
//! an allow-host entry that names a port must match it exactly. A server bound to every
//! interface (`0.0.0.0`, `[::]`) also takes any IP literal (no DNS name is involved, so nothing
//! can rebind it). Names compare without case.

use std::net::{IpAddr, SocketAddr};

/// The names a server answers to.
#[derive(Debug, Clone)]
pub struct HostList {
    port: u16,
    default_port: u16,
    any_ip: bool,
    names: Vec<String>,
    /// `--hmi-allow-host` entries with an explicit port: (name, port).
    exact: Vec<(String, u16)>,
}

impl HostList {
    /// The list for a server bound to `bound`, serving TLS or not, with the extra `allowed`
    /// names (`NAME` or `NAME:PORT`).
    pub fn new(bound: SocketAddr, tls: bool, allowed: &[String]) -> HostList {
        let mut names: Vec<String> = vec!["localhost".into(), "127.0.0.1".into(), "::1".into()];
        if !bound.ip().is_unspecified() {
            names.push(bound.ip().to_string());
        }
        let mut exact = Vec::new();
        for a in allowed {
            match split(a) {
                Some((n, Some(p))) => exact.push((n, p)),
                Some((n, None)) => names.push(n),
                None => names.push(a.to_ascii_lowercase()),
            }
        }
        HostList {
            port: bound.port(),
            default_port: if tls { 443 } else { 80 },
            any_ip: bound.ip().is_unspecified(),
            names,
            exact,
        }
    }

    /// True when a request with this `Host` header may go on.
    pub fn allows(&self, host: &str) -> bool {
        let Some((name, port)) = split(host) else {
            return false;
        };
        if let Some(p) = port
            && self.exact.iter().any(|(n, ep)| *n == name && *ep == p)
        {
            return true;
        }
        let port_ok = match port {
            Some(p) => p == self.port,
            None => self.port == self.default_port,
        };
        port_ok && (self.names.contains(&name) || (self.any_ip && name.parse::<IpAddr>().is_ok()))
    }
}

/// A `Host` value split into its lower-case name (an IPv6 literal without brackets) and port;
/// `None` when it is not a host at all.
pub fn split(host: &str) -> Option<(String, Option<u16>)> {
    let host = host.trim();
    if host.is_empty() || host.contains(['/', '@', '?', '#', ' ']) {
        return None;
    }
    let (name, port) = if let Some(rest) = host.strip_prefix('[') {
        let (v6, after) = rest.split_once(']')?;
        v6.parse::<std::net::Ipv6Addr>().ok()?;
        let port = match after {
            "" => None,
            p => Some(p.strip_prefix(':')?),
        };
        (v6.to_string(), port)
    } else {
        match host.rsplit_once(':') {
            Some((n, p)) => (n.to_string(), Some(p)),
            None => (host.to_string(), None),
        }
    };
    if name.is_empty() || (name.contains(':') && !host.starts_with('[')) {
        return None;
    }
    let port = match port {
        Some(p) => Some(p.parse::<u16>().ok()?),
        None => None,
    };
    Some((name.to_ascii_lowercase(), port))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn list(bound: &str, allowed: &[&str]) -> HostList {
        let allowed: Vec<String> = allowed.iter().map(|s| s.to_string()).collect();
        HostList::new(bound.parse().expect("addr"), false, &allowed)
    }

    #[test]
    fn loopback_names_with_the_bound_port_pass_and_foreign_names_do_not() {
        let l = list("127.0.0.1:8080", &[]);
        for ok in [
            "127.0.0.1:8080",
            "localhost:8080",
            "LOCALHOST:8080",
            "[::1]:8080",
        ] {
            assert!(l.allows(ok), "{ok}");
        }
        for bad in [
            "attacker.example:8080",
            "attacker.example",
            "127.0.0.1:8081",
            "127.0.0.1",
            "localhost.attacker.example:8080",
            "",
            "127.0.0.1:8080/x",
            "user@127.0.0.1:8080",
            "[::1:8080",
            "::1:8080",
            "127.0.0.1:99999",
            "10.0.0.5:8080",
        ] {
            assert!(!l.allows(bad), "{bad}");
        }
    }

    #[test]
    fn allowed_names_and_the_default_port() {
        let l = list("10.0.0.5:80", &["hmi.shop.lan", "Panel:9000"]);
        assert!(l.allows("10.0.0.5"));
        assert!(l.allows("10.0.0.5:80"));
        assert!(l.allows("hmi.shop.lan"));
        assert!(l.allows("HMI.shop.lan:80"));
        assert!(l.allows("panel:9000"));
        assert!(!l.allows("panel:80"));
        assert!(!l.allows("10.0.0.6"));
        assert!(!l.allows("other.shop.lan"));
    }

    #[test]
    fn an_unspecified_bind_takes_ip_literals_but_no_foreign_name() {
        let l = list("0.0.0.0:8080", &[]);
        assert!(l.allows("192.168.1.20:8080"));
        assert!(l.allows("[fe80::1]:8080"));
        assert!(l.allows("localhost:8080"));
        assert!(!l.allows("0.0.0.0.attacker.example:8080"));
        assert!(!l.allows("192.168.1.20:8081"));
    }
}
