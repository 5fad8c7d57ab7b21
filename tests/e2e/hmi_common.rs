//! Shared by the HMI end-to-end tests: start `ncplc run --hmi 127.0.0.1:0`, find the bound
//! address and the session token in the start URL it prints, talk HTTP/1.1 to it (with the token
//! as a Bearer header), stop it with SIGTERM (it then finishes its trace).

#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use crate::e2e_common::Ncplc;

/// The workspace root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// A running `ncplc run --hmi`.
pub struct Hmi {
    pub child: Child,
    pub addr: String,
    /// The token of the start URL (none when the run reads a token file).
    pub token: Option<String>,
    pub stderr: mpsc::Receiver<String>,
}

/// The address and token of a start line `hmi: http://ADDR/?token=T`.
pub fn start_line(line: &str) -> Option<(String, Option<String>)> {
    let rest = line
        .strip_prefix("hmi: http://")
        .or_else(|| line.strip_prefix("hmi: https://"))?;
    let addr = rest.split('/').next().unwrap_or_default().to_string();
    let token = rest
        .split_whitespace()
        .next()
        .and_then(|url| url.split_once("?token="))
        .map(|(_, t)| t.to_string());
    Some((addr, token))
}

impl Hmi {
    /// Starts the lathe with the HMI on a free loopback port; `extra` are more `run` arguments.
    pub fn start(machine: &Path, extra: &[&str]) -> Hmi {
        let mut child = Ncplc::run(machine)
            // A loaded CI machine overruns now and then; these tests are not about timing.
            .args(["--hmi", "127.0.0.1:0", "--overrun-limit", "0"])
            .args(extra)
            .command()
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("ncplc starts");
        let err = child.stderr.take().expect("stderr");
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(err).lines().map_while(Result::ok) {
                let _ = tx.send(line);
            }
        });
        let mut seen = Vec::new();
        loop {
            match rx.recv_timeout(Duration::from_secs(60)) {
                Ok(line) => {
                    if let Some((addr, token)) = start_line(&line) {
                        return Hmi {
                            child,
                            addr,
                            token,
                            stderr: rx,
                        };
                    }
                    seen.push(line);
                }
                Err(_) => {
                    let _ = child.kill();
                    let _ = child.wait();
                    panic!("ncplc did not start the HMI:\n{}", seen.join("\n"));
                }
            }
        }
    }

    /// One HTTP request with the start URL's token; returns (status, body).
    pub fn http(&self, method: &str, path: &str, body: Option<&str>) -> (u16, String) {
        http(&self.addr, method, path, body, self.token.as_deref())
    }

    /// A WebSocket of `path` with the start URL's token.
    pub fn ws(&self, path: &str) -> Ws {
        let auth = format!(
            "Authorization: Bearer {}\r\n",
            self.token.as_deref().unwrap_or_default()
        );
        Ws::try_connect_with(&self.addr, path, &auth).unwrap_or_else(|answer| panic!("{answer}"))
    }

    /// Waits until `GET /api/status` reports at least `tick`.
    pub fn wait_tick(&self, tick: u64) {
        for _ in 0..600 {
            let (_, body) = self.http("GET", "/api/status", None);
            let v: serde_json::Value = serde_json::from_str(&body).unwrap_or_default();
            if v["tick"].as_u64().unwrap_or(0) >= tick {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        panic!("the scan did not reach tick {tick}");
    }

    /// Stops the run with SIGTERM and returns its remaining stderr.
    pub fn stop(mut self) -> String {
        // SAFETY: kill(2) on our own child's pid.
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM);
        }
        let status = self.child.wait().expect("wait");
        let rest: Vec<String> = self.stderr.try_iter().collect();
        assert!(
            status.success(),
            "ncplc failed: {status}\n{}",
            rest.join("\n")
        );
        rest.join("\n")
    }
}

impl Drop for Hmi {
    /// A test that fails midway leaves no `ncplc run` behind.
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// One HTTP/1.1 request with `Connection: close`; returns (status, body).
pub fn http(
    addr: &str,
    method: &str,
    path: &str,
    body: Option<&str>,
    token: Option<&str>,
) -> (u16, String) {
    let auth = token.map_or(String::new(), |t| format!("Authorization: Bearer {t}\r\n"));
    let r = raw(addr, method, path, &auth, body);
    (r.status, r.body)
}

/// An answer: status, head (status line and headers) and body.
#[derive(Debug)]
pub struct Answer {
    pub status: u16,
    pub head: String,
    pub body: String,
}

impl Answer {
    /// The value of header `name` (case-insensitive), if present.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.head.lines().find_map(|l| {
            let (k, v) = l.split_once(':')?;
            k.eq_ignore_ascii_case(name).then(|| v.trim())
        })
    }

    /// The body as JSON.
    pub fn json(&self) -> serde_json::Value {
        serde_json::from_str(&self.body).unwrap_or_default()
    }
}

/// One HTTP/1.1 request with `Connection: close` and the extra `headers` (each ending in
/// `\r\n`); `Host: ADDR` unless `headers` give a Host.
pub fn raw(addr: &str, method: &str, path: &str, headers: &str, body: Option<&str>) -> Answer {
    let mut s = TcpStream::connect(addr).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(10))).ok();
    let body = body.unwrap_or("");
    let host = if headers.to_ascii_lowercase().contains("host:") {
        String::new()
    } else {
        format!("Host: {addr}\r\n")
    };
    let request = format!(
        "{method} {path} HTTP/1.1\r\n{host}Connection: close\r\n{headers}Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    );
    // One write; a server that refuses a large body may answer and close after the headers, so a
    // failed send only counts when no answer came.
    let sent = s.write_all(request.as_bytes());
    let mut resp = Vec::new();
    let _ = s.read_to_end(&mut resp);
    if resp.is_empty()
        && let Err(e) = sent
    {
        panic!("send: {e:?}");
    }
    let resp = String::from_utf8_lossy(&resp).into_owned();
    let status = resp
        .split(' ')
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0);
    let (head, body) = resp.split_once("\r\n\r\n").unwrap_or((&resp, ""));
    Answer {
        status,
        head: head.to_string(),
        body: body.to_string(),
    }
}

/// A copy of the simulated lathe in which nobody presses CYCLE START during a part run (its
/// `sim.toml` keeps the power-on inputs and drops the operator's scripted panel presses), so
/// that the HMI is the operator.
pub fn operator_lathe() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let sim = dir.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    let cut = text
        .find("# The operator presses CYCLE START.")
        .expect("the lathe's sim.toml presses CYCLE START in its part run");
    std::fs::write(&sim, &text[..cut]).expect("write sim.toml");
    dir
}

fn copy_dir(from: &Path, to: &Path) {
    for e in std::fs::read_dir(from).expect("read_dir") {
        let e = e.expect("entry");
        let name = e.file_name();
        if name == "traces" || name == "retain.bin" {
            continue;
        }
        let dst = to.join(&name);
        if e.file_type().expect("file type").is_dir() {
            std::fs::create_dir_all(&dst).expect("mkdir");
            copy_dir(&e.path(), &dst);
        } else {
            std::fs::copy(e.path(), dst).expect("copy");
        }
    }
}

/// `GET /api/status` as JSON.
pub fn status(hmi: &Hmi) -> serde_json::Value {
    let (_, body) = hmi.http("GET", "/api/status", None);
    serde_json::from_str(&body).unwrap_or_default()
}

/// Polls `GET /api/status` every 20 ms until `probe` holds (at most `secs`); returns that status.
pub fn wait_status(
    hmi: &Hmi,
    what: &str,
    secs: u64,
    probe: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    let deadline = std::time::Instant::now() + Duration::from_secs(secs);
    loop {
        let s = status(hmi);
        if probe(&s) {
            return s;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "timed out waiting for {what}; last status: {s}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// `ncplc replay MACHINE TRACE EXTRA…`: (success, its stdout and stderr).
pub fn replay(machine: &Path, trace: &Path, extra: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(["replay".as_ref(), machine.as_os_str(), trace.as_os_str()])
        .args(extra)
        .output()
        .expect("replay");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

/// A minimal WebSocket client of `/ws` (std only): the upgrade, unmasked server frames read,
/// masked text frames sent.
pub struct Ws(TcpStream);

impl Ws {
    /// Connects to `path` (e.g. `/ws?ack=1`) of the HMI at `addr`.
    pub fn connect(addr: &str, path: &str) -> Ws {
        Ws::try_connect(addr, path).unwrap_or_else(|answer| panic!("{answer}"))
    }

    /// [`Ws::connect`], or the server's whole answer when it does not upgrade.
    pub fn try_connect(addr: &str, path: &str) -> Result<Ws, String> {
        Ws::try_connect_with(addr, path, "")
    }

    /// [`Ws::try_connect`] with extra request headers (each ending in `\r\n`).
    pub fn try_connect_with(addr: &str, path: &str, headers: &str) -> Result<Ws, String> {
        let mut s = TcpStream::connect(addr).expect("connect");
        write!(
            s,
            "GET {path} HTTP/1.1\r\nHost: {addr}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
             {headers}Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"
        )
        .expect("upgrade request");
        let mut head = Vec::new();
        let mut b = [0u8; 1];
        while !head.ends_with(b"\r\n\r\n") {
            s.read_exact(&mut b).expect("upgrade answer");
            head.push(b[0]);
        }
        if !head.starts_with(b"HTTP/1.1 101") {
            let mut rest = Vec::new();
            s.set_read_timeout(Some(Duration::from_secs(2)))
                .expect("timeout");
            let _ = s.read_to_end(&mut rest);
            head.extend(rest);
            return Err(String::from_utf8_lossy(&head).into_owned());
        }
        Ok(Ws(s))
    }

    /// The next text frame's `tick`, or None when none arrives within `wait`.
    pub fn next_tick(&mut self, wait: Duration) -> Option<u64> {
        self.0.set_read_timeout(Some(wait)).expect("timeout");
        let mut h = [0u8; 2];
        if self.0.read_exact(&mut h).is_err() {
            return None;
        }
        // Once a frame has begun, read it whole.
        self.0
            .set_read_timeout(Some(Duration::from_secs(10)))
            .expect("timeout");
        let mut n = u64::from(h[1] & 0x7F);
        if n == 126 {
            let mut l = [0u8; 2];
            self.0.read_exact(&mut l).expect("length");
            n = u64::from(u16::from_be_bytes(l));
        } else if n == 127 {
            let mut l = [0u8; 8];
            self.0.read_exact(&mut l).expect("length");
            n = u64::from_be_bytes(l);
        }
        let mut body = vec![0u8; usize::try_from(n).expect("size")];
        self.0.read_exact(&mut body).expect("frame");
        let v: serde_json::Value = serde_json::from_slice(&body).expect("a JSON snapshot");
        v["tick"].as_u64()
    }

    /// Sends a (masked) text frame.
    pub fn send(&mut self, text: &str) {
        let _ = self.try_send(text);
    }

    /// Sends a (masked) text frame of any length; false when the server has closed.
    pub fn try_send(&mut self, text: &str) -> bool {
        let mask = [0x12u8, 0x34, 0x56, 0x78];
        let mut f = vec![0x81];
        match text.len() {
            n if n < 126 => f.push(0x80 | n as u8),
            n if n <= 0xFFFF => {
                f.push(0x80 | 126);
                f.extend_from_slice(&(n as u16).to_be_bytes());
            }
            n => {
                f.push(0x80 | 127);
                f.extend_from_slice(&(n as u64).to_be_bytes());
            }
        }
        f.extend_from_slice(&mask);
        f.extend(text.bytes().enumerate().map(|(i, b)| b ^ mask[i % 4]));
        self.0.write_all(&f).is_ok()
    }

    /// Reads frames until a close frame; its code and reason (None when the connection ends
    /// without one within `wait`).
    pub fn close_frame(&mut self, wait: Duration) -> Option<(u16, String)> {
        self.0.set_read_timeout(Some(wait)).expect("timeout");
        loop {
            let mut h = [0u8; 2];
            self.0.read_exact(&mut h).ok()?;
            let mut n = u64::from(h[1] & 0x7F);
            if n == 126 {
                let mut l = [0u8; 2];
                self.0.read_exact(&mut l).ok()?;
                n = u64::from(u16::from_be_bytes(l));
            } else if n == 127 {
                let mut l = [0u8; 8];
                self.0.read_exact(&mut l).ok()?;
                n = u64::from_be_bytes(l);
            }
            let mut body = vec![0u8; usize::try_from(n).ok()?];
            self.0.read_exact(&mut body).ok()?;
            if h[0] & 0x0F == 0x8 && body.len() >= 2 {
                let code = u16::from_be_bytes([body[0], body[1]]);
                return Some((code, String::from_utf8_lossy(&body[2..]).into_owned()));
            }
        }
    }
}
