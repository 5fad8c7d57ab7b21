//! Shared by the HMI end-to-end tests: start `ncplc run --hmi 127.0.0.1:0`, find the bound
//! address in its stderr, talk HTTP/1.1 to it, stop it with SIGTERM (it then finishes its trace).

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
    pub stderr: mpsc::Receiver<String>,
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
                    if let Some(rest) = line.strip_prefix("hmi: http://") {
                        let addr = rest.split('/').next().unwrap_or_default().to_string();
                        return Hmi {
                            child,
                            addr,
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

    /// One HTTP request; returns (status, body).
    pub fn http(&self, method: &str, path: &str, body: Option<&str>) -> (u16, String) {
        http(&self.addr, method, path, body, None)
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
    let mut s = TcpStream::connect(addr).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(10))).ok();
    let body = body.unwrap_or("");
    let auth = token.map_or(String::new(), |t| format!("Authorization: Bearer {t}\r\n"));
    write!(
        s,
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n{auth}Content-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    )
    .expect("send");
    let mut resp = String::new();
    s.read_to_string(&mut resp).expect("read");
    let status = resp
        .split(' ')
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0);
    let body = resp.split_once("\r\n\r\n").map_or("", |(_, b)| b);
    (status, body.to_string())
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
        let mut s = TcpStream::connect(addr).expect("connect");
        write!(
            s,
            "GET {path} HTTP/1.1\r\nHost: {addr}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n\
             Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"
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
        let mask = [0x12u8, 0x34, 0x56, 0x78];
        let mut f = vec![0x81, 0x80 | u8::try_from(text.len()).expect("short")];
        f.extend_from_slice(&mask);
        f.extend(text.bytes().enumerate().map(|(i, b)| b ^ mask[i % 4]));
        self.0.write_all(&f).expect("send");
    }
}
