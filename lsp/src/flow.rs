//! Power flow as inlay hints: the values a running controller's scan computed for each statement,
//! read from its HMI (`ncplc run --hmi ADDR --hmi-flow`: `GET /api/flow`, `[line, value]` per
//! statement, and `GET /api/program`, the program it runs) and shown at the end of the lines.
//!
//! The HMI is named by the start URL the run prints (`http://ADDR/?token=T`), in the client's
//! `initializationOptions.hmi`. Read-only: only `GET`s, with the token as a Bearer header.
//! Invariants: a document whose text is not the running program's source gets no hints (the
//! line numbers would point at other statements); every request is bounded (connect, read and
//! write time-outs of [`TIMEOUT`], at most [`MAX_BODY`] bytes read), and a failure is an error
//! value, never a hang or a panic.

use std::io::{Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

use lsp_types::{InlayHint, InlayHintLabel, Position};

use crate::text::Text;

/// Time-out of each step of a request to the HMI.
pub const TIMEOUT: Duration = Duration::from_millis(500);
/// Longest answer read from the HMI.
pub const MAX_BODY: u64 = 16 << 20;

/// Why no power flow could be read.
#[derive(Debug, thiserror::Error)]
pub enum FlowError {
    /// The configured URL is not `http://HOST:PORT/…`.
    #[error(
        "initializationOptions.hmi `{0}`: expected the start URL `ncplc run --hmi` prints, http://HOST:PORT/?token=T"
    )]
    Url(String),
    /// The HMI could not be reached or did not answer in time.
    #[error("the HMI at {addr}: {source}")]
    Io {
        /// HOST:PORT.
        addr: String,
        /// The failure.
        source: std::io::Error,
    },
    /// The HMI answered with something else than 200 and JSON.
    #[error("the HMI at {addr} answered {path} with {what}")]
    Answer {
        /// HOST:PORT.
        addr: String,
        /// The path asked for.
        path: &'static str,
        /// What came back.
        what: String,
    },
}

/// What the HMI says about the running program.
#[derive(Debug, Clone, PartialEq)]
pub struct Running {
    /// The source lines of the program it runs.
    pub source: Vec<String>,
    /// `(line, value)` per statement of its last scan (empty while power flow is off).
    pub flow: Vec<(u32, f64)>,
}

/// A running controller's HMI.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Hmi {
    /// HOST:PORT.
    pub addr: String,
    /// The session token of the start URL.
    pub token: Option<String>,
}

impl Hmi {
    /// The HMI of a start URL `http://HOST:PORT/?token=T` (the token is optional).
    pub fn from_url(url: &str) -> Result<Hmi, FlowError> {
        let bad = || FlowError::Url(url.to_string());
        let rest = url.strip_prefix("http://").ok_or_else(bad)?;
        let (addr, path) = rest.split_at(rest.find(['/', '?']).unwrap_or(rest.len()));
        if addr.is_empty() || !addr.contains(':') {
            return Err(bad());
        }
        let token = path
            .split_once("token=")
            .map(|(_, t)| t.split('&').next().unwrap_or_default().to_string())
            .filter(|t| !t.is_empty());
        Ok(Hmi {
            addr: addr.to_string(),
            token,
        })
    }

    /// `GET path` as JSON.
    fn get(&self, path: &'static str) -> Result<serde_json::Value, FlowError> {
        let io = |source| FlowError::Io {
            addr: self.addr.clone(),
            source,
        };
        let answer = |what: String| FlowError::Answer {
            addr: self.addr.clone(),
            path,
            what,
        };
        let sock = self
            .addr
            .to_socket_addrs()
            .map_err(io)?
            .next()
            .ok_or_else(|| answer("no address".into()))?;
        let mut s = TcpStream::connect_timeout(&sock, TIMEOUT).map_err(io)?;
        s.set_read_timeout(Some(TIMEOUT)).map_err(io)?;
        s.set_write_timeout(Some(TIMEOUT)).map_err(io)?;
        let auth = self
            .token
            .as_ref()
            .map(|t| format!("Authorization: Bearer {t}\r\n"))
            .unwrap_or_default();
        let req = format!(
            "GET {path} HTTP/1.0\r\nHost: {}\r\n{auth}Connection: close\r\n\r\n",
            self.addr
        );
        s.write_all(req.as_bytes()).map_err(io)?;
        let mut raw = Vec::new();
        s.take(MAX_BODY).read_to_end(&mut raw).map_err(io)?;
        let text = String::from_utf8_lossy(&raw);
        let (head, body) = text
            .split_once("\r\n\r\n")
            .ok_or_else(|| answer("no HTTP answer".into()))?;
        let status = head.split_whitespace().nth(1).unwrap_or_default();
        if status != "200" {
            return Err(answer(format!("status {status}")));
        }
        serde_json::from_str(body).map_err(|e| answer(format!("no JSON ({e})")))
    }

    /// The running program's source lines and the power flow of its last scan.
    pub fn read(&self) -> Result<Running, FlowError> {
        let src = self.get("/api/program")?;
        let lines = src["lines"]
            .as_array()
            .map(|l| {
                l.iter()
                    .map(|x| x["text"].as_str().unwrap_or_default().to_string())
                    .collect()
            })
            .unwrap_or_default();
        let flow = self.get("/api/flow")?;
        let flow = flow["flow"]
            .as_array()
            .map(|f| {
                f.iter()
                    .filter_map(|p| {
                        let line = u32::try_from(p.get(0)?.as_u64()?).ok()?;
                        Some((line, p.get(1)?.as_f64()?))
                    })
                    .collect()
            })
            .unwrap_or_default();
        Ok(Running {
            source: lines,
            flow,
        })
    }
}

/// A value as the hint shows it: whole numbers without a fraction.
fn show(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v}")
    }
}

/// The hints for `text` on lines `first..=last` (0-based) from the running program's `source`
/// lines and its `flow`: one per line, the value of the line's last statement (a line's inline
/// timers come before its own statement). None when `text` is not the running source.
pub fn hints(
    text: &Text,
    source: &[String],
    flow: &[(u32, f64)],
    first: u32,
    last: u32,
) -> Vec<InlayHint> {
    let mine: Vec<&str> = text.as_str().lines().collect();
    // The controller reads the file without its byte-order mark.
    let same = mine.len() == source.len()
        && mine.iter().zip(source).enumerate().all(|(i, (a, b))| {
            let a = if i == 0 {
                a.trim_start_matches('\u{FEFF}')
            } else {
                a
            };
            a.trim_end_matches('\r') == b.trim_end_matches('\r')
        });
    if !same {
        return Vec::new();
    }
    let mut out: Vec<InlayHint> = Vec::new();
    for &(line, value) in flow {
        let Some(l) = line.checked_sub(1).filter(|l| (first..=last).contains(l)) else {
            continue;
        };
        let chars = mine
            .get(l as usize)
            .map_or(0, |s| s.trim_end_matches('\r').encode_utf16().count());
        let hint = InlayHint {
            position: Position::new(l, u32::try_from(chars).unwrap_or(u32::MAX)),
            label: InlayHintLabel::String(format!("= {}", show(value))),
            kind: None,
            text_edits: None,
            tooltip: None,
            padding_left: Some(true),
            padding_right: None,
            data: None,
        };
        match out.last_mut() {
            Some(h) if h.position.line == l => *h = hint,
            _ => out.push(hint),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_start_url_names_the_hmi() {
        let h = Hmi::from_url("http://127.0.0.1:8080/?token=abc").expect("url");
        assert_eq!(h.addr, "127.0.0.1:8080");
        assert_eq!(h.token.as_deref(), Some("abc"));
        let h = Hmi::from_url("http://localhost:9").expect("url");
        assert_eq!((h.addr.as_str(), h.token), ("localhost:9", None));
        assert!(Hmi::from_url("https://x:1/").is_err());
        assert!(Hmi::from_url("http:///?token=a").is_err());
    }

    fn label(h: &InlayHint) -> &str {
        match &h.label {
            InlayHintLabel::String(s) => s,
            InlayHintLabel::LabelParts(_) => "",
        }
    }

    #[test]
    fn a_hint_per_line_at_its_end_only_for_the_running_source() {
        let text = Text::new("DEF A = I0A0\nU4A0 = A\nV1 = TON(A, 10ms) + 2\n".into());
        let source: Vec<String> = text.as_str().lines().map(str::to_string).collect();
        // Line 3: the inline timer's value first, then the statement's.
        let flow = [(2, 1.0), (3, 0.0), (3, 2.5)];
        let h = hints(&text, &source, &flow, 0, 10);
        assert_eq!(h.len(), 2);
        assert_eq!(h[0].position, Position::new(1, 8));
        assert_eq!(label(&h[0]), "= 1");
        assert_eq!(h[1].position, Position::new(2, 21));
        assert_eq!(label(&h[1]), "= 2.5");
        // Only the lines asked for.
        assert_eq!(hints(&text, &source, &flow, 2, 2).len(), 1);
        // An edited text is not the running program.
        let edited = Text::new("DEF A = I0A0\nU4A0 = /A\nV1 = TON(A, 10ms) + 2\n".into());
        assert!(hints(&edited, &source, &flow, 0, 10).is_empty());
    }

    #[test]
    fn an_hmi_that_is_not_there_is_an_error_in_bounded_time() {
        // A port nobody listens on (bound, then closed).
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        let h = Hmi::from_url(&format!("http://127.0.0.1:{port}/?token=t")).expect("url");
        let t = std::time::Instant::now();
        assert!(matches!(h.read(), Err(FlowError::Io { .. })));
        assert!(t.elapsed() < TIMEOUT * 4);
    }
}
