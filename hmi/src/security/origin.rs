//! The `Origin` check on state-changing requests and WebSocket upgrades: what stops a page of
//! another site, open in the operator's browser, from posting to the HMI or streaming its state
//! (cross-site request forgery, cross-site WebSocket hijacking).
//!
//! A browser sends `Origin` on every POST, PUT, DELETE and WebSocket upgrade. It must be this
//! server's own origin (the scheme it serves and the `Host` the request names, a default port
//! written or not) or one of the `--hmi-allow-origin` values; anything else, `null` included, is
//! refused. A request without `Origin` comes from a program, not a page, and goes on (it still
//! needs its token).

/// The origins a server accepts besides its own.
#[derive(Debug, Clone, Default)]
pub struct OriginList {
    allowed: Vec<String>,
}

/// An origin split into scheme, lower-case host and port (the scheme's default when not written).
#[derive(Debug, Clone, PartialEq, Eq)]
struct Parsed {
    scheme: String,
    host: String,
    port: u16,
}

fn parse(origin: &str) -> Option<Parsed> {
    let (scheme, rest) = origin.split_once("://")?;
    let scheme = scheme.to_ascii_lowercase();
    let default = match scheme.as_str() {
        "http" => 80,
        "https" => 443,
        _ => return None,
    };
    let (host, port) = super::host::split(rest)?;
    Some(Parsed {
        scheme,
        host,
        port: port.unwrap_or(default),
    })
}

impl OriginList {
    /// The list of `--hmi-allow-origin` values (`http://panel.shop.lan:8080`).
    pub fn new(allowed: &[String]) -> OriginList {
        OriginList {
            allowed: allowed.to_vec(),
        }
    }

    /// Why an allow-origin value is not an origin, if it is not.
    pub fn invalid(value: &str) -> Option<String> {
        parse(value).is_none().then(|| {
            format!(
                "`{value}` is not an origin (scheme://host[:port], e.g. http://panel.shop.lan:8080)"
            )
        })
    }

    /// True when a request carrying `origin`, sent to `host` of a server speaking TLS or not,
    /// may go on.
    pub fn allows(&self, origin: &str, host: &str, tls: bool) -> bool {
        let Some(o) = parse(origin) else {
            return false;
        };
        if self.allowed.iter().any(|a| parse(a).as_ref() == Some(&o)) {
            return true;
        }
        let scheme = if tls { "https" } else { "http" };
        match super::host::split(host) {
            Some((h, p)) => {
                let own = Parsed {
                    scheme: scheme.into(),
                    host: h,
                    port: p.unwrap_or(if tls { 443 } else { 80 }),
                };
                o == own
            }
            None => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_own_origin_and_the_allowed_ones_pass() {
        let l = OriginList::new(&["http://panel.shop.lan:9000".into()]);
        let host = "127.0.0.1:8080";
        assert!(l.allows("http://127.0.0.1:8080", host, false));
        assert!(l.allows("HTTP://127.0.0.1:8080", host, false));
        assert!(l.allows("http://panel.shop.lan:9000", host, false));
        for bad in [
            "http://attacker.example",
            "http://localhost:8080",
            "https://127.0.0.1:8080",
            "http://127.0.0.1:8081",
            "null",
            "",
            "file://",
            "http://127.0.0.1:8080/path",
            "http://panel.shop.lan",
        ] {
            assert!(!l.allows(bad, host, false), "{bad}");
        }
        assert!(l.allows("https://hmi.lan", "hmi.lan:443", true));
        assert!(l.allows("https://hmi.lan:443", "hmi.lan", true));
        assert!(!l.allows("http://hmi.lan", "hmi.lan", true));
        assert!(OriginList::invalid("panel.shop.lan").is_some());
        assert!(OriginList::invalid("http://panel.shop.lan:9000").is_none());
    }
}
