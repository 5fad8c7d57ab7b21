//! A small Chrome DevTools Protocol client for the browser tests: it starts headless Debian
//! `chromium` with a fresh profile, attaches to its page over the CDP WebSocket, and offers what
//! the tests use — navigate, run a script, read an element's text, click an element (mouse events
//! at its centre), type into an input, the page's address, a screenshot.
//!
//! Why not WebDriver (fantoccini + chromedriver, until issue 24): the WebDriver client crates
//! brought 45 crates (URL parsing with ICU, Unicode segmentation, a second HTTP stack), 10 % of a
//! clean test build's CPU; CDP needs only the WebSocket client the HMI's server already compiles.
//!
//! Invariants: one browser per test, killed when [`Browser`] drops; every call waits for its own
//! answer (events in between are skipped) and fails with the browser's message, never hangs
//! longer than [`CALL_TIMEOUT`].

use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use base64::Engine as _;
use futures_util::{SinkExt, StreamExt};
use serde_json::{Value, json};
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio::sync::Mutex;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::{MaybeTlsStream, WebSocketStream};

use crate::e2e_common::Killed;

/// Debian's Chromium.
pub const CHROMIUM: &str = "/usr/bin/chromium";

/// The longest a single CDP call may take.
pub const CALL_TIMEOUT: Duration = Duration::from_secs(30);

type Socket = WebSocketStream<MaybeTlsStream<TcpStream>>;

/// A headless Chromium and its one page.
pub struct Browser {
    /// The browser process, killed when this drops (also when [`Browser::launch`] fails half-way).
    _child: Killed,
    _profile: tempfile::TempDir,
    socket: Mutex<Socket>,
    next_id: AtomicU64,
}

impl Browser {
    /// Starts Chromium (1280×900, headless) and attaches to its page.
    pub async fn launch() -> Result<Browser, String> {
        let profile = tempfile::tempdir().map_err(|e| e.to_string())?;
        let child = Killed(
            Command::new(CHROMIUM)
                .args([
                    "--headless=new",
                    "--no-sandbox",
                    "--disable-gpu",
                    "--disable-dev-shm-usage",
                    "--disable-background-networking",
                    "--disable-component-update",
                    "--disable-sync",
                    "--no-first-run",
                    "--window-size=1280,900",
                    "--remote-debugging-port=0",
                ])
                .arg(format!("--user-data-dir={}", profile.path().display()))
                .arg("about:blank")
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .map_err(|e| format!("{CHROMIUM}: {e}"))?,
        );
        let port = devtools_port(profile.path()).await?;
        let page = page_socket_url(port).await?;
        let (socket, _) = tokio_tungstenite::connect_async(page.as_str())
            .await
            .map_err(|e| format!("CDP {page}: {e}"))?;
        Ok(Browser {
            _child: child,
            _profile: profile,
            socket: Mutex::new(socket),
            next_id: AtomicU64::new(1),
        })
    }

    /// Sends `method` with `params` and returns its result (a CDP error is an `Err`).
    pub async fn call(&self, method: &str, params: Value) -> Result<Value, String> {
        let id = self.next_id.fetch_add(1, Ordering::Relaxed);
        let mut socket = self.socket.lock().await;
        let request = json!({"id": id, "method": method, "params": params}).to_string();
        socket
            .send(Message::text(request))
            .await
            .map_err(|e| format!("{method}: {e}"))?;
        let deadline = Instant::now() + CALL_TIMEOUT;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let next = tokio::time::timeout(left, socket.next())
                .await
                .map_err(|_| format!("{method}: no answer in {CALL_TIMEOUT:?}"))?;
            let text = match next {
                Some(Ok(Message::Text(t))) => t,
                Some(Ok(_)) => continue,
                Some(Err(e)) => return Err(format!("{method}: {e}")),
                None => return Err(format!("{method}: the browser closed the connection")),
            };
            let v: Value = serde_json::from_str(&text).map_err(|e| format!("{method}: {e}"))?;
            if v["id"] != id {
                continue; // an event, or the answer to an abandoned call
            }
            if let Some(err) = v.get("error") {
                return Err(format!("{method}: {err}"));
            }
            return Ok(v["result"].clone());
        }
    }

    /// Runs `body` as the body of a function (it may `return` a value) and returns that value.
    pub async fn js(&self, body: &str) -> Result<Value, String> {
        let expression = format!("(async () => {{ {body}\n}})()");
        let r = self
            .call(
                "Runtime.evaluate",
                json!({"expression": expression, "returnByValue": true, "awaitPromise": true}),
            )
            .await?;
        if let Some(ex) = r.get("exceptionDetails") {
            let what = ex["exception"]["description"]
                .as_str()
                .unwrap_or("exception");
            return Err(format!("{body}: {what}"));
        }
        Ok(r["result"]["value"].clone())
    }

    /// Opens `url` and waits until the new document has loaded (redirects followed).
    pub async fn goto(&self, url: &str) -> Result<(), String> {
        self.js("window.__cdp_old_document = true; return null")
            .await?;
        let r = self.call("Page.navigate", json!({"url": url})).await?;
        if let Some(e) = r.get("errorText").and_then(Value::as_str) {
            return Err(format!("{url}: {e}"));
        }
        let deadline = Instant::now() + CALL_TIMEOUT;
        loop {
            let loaded = self
                .js("return !window.__cdp_old_document && document.readyState === 'complete'")
                .await;
            if loaded == Ok(Value::Bool(true)) {
                return Ok(());
            }
            if Instant::now() > deadline {
                return Err(format!("{url}: not loaded in {CALL_TIMEOUT:?}"));
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }

    /// The page's address.
    pub async fn url(&self) -> Result<String, String> {
        let v = self.js("return location.href").await?;
        v.as_str()
            .map(str::to_string)
            .ok_or(format!("location.href: {v}"))
    }

    /// The rendered text of the first element matching `css` (None: no such element).
    pub async fn text(&self, css: &str) -> Option<String> {
        let body = format!(
            "const e = document.querySelector({}); return e ? e.innerText : null",
            js_str(css)
        );
        self.js(&body).await.ok()?.as_str().map(str::to_string)
    }

    /// Clicks the first element matching `css` with the mouse: pressed and released at its centre
    /// (scrolled into view first), as a user's click. The point is taken only when the element
    /// itself is what lies there (a page still laying out moves it): otherwise it is asked again
    /// for up to 5 s.
    pub async fn click(&self, css: &str) -> Result<(), String> {
        let body = format!(
            "const e = document.querySelector({}); if (!e) return 'none'; \
             e.scrollIntoView({{block: 'center', inline: 'center'}}); \
             const r = e.getBoundingClientRect(); const x = r.left + r.width / 2, y = r.top + r.height / 2; \
             const at = document.elementFromPoint(x, y); \
             return at && (at === e || e.contains(at)) ? [x, y] : 'covered'",
            js_str(css)
        );
        let deadline = Instant::now() + Duration::from_secs(5);
        let (x, y) = loop {
            let at = self.js(&body).await?;
            if let (Some(x), Some(y)) = (at[0].as_f64(), at[1].as_f64()) {
                break (x, y);
            }
            if Instant::now() > deadline {
                return Err(format!("{css}: {at}"));
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        };
        for kind in ["mousePressed", "mouseReleased"] {
            self.call(
                "Input.dispatchMouseEvent",
                json!({"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1}),
            )
            .await?;
        }
        Ok(())
    }

    /// Empties the input matching `css` and types `text` into it (focus, then text input events).
    pub async fn type_into(&self, css: &str, text: &str) -> Result<(), String> {
        let body = format!(
            "const e = document.querySelector({}); if (!e) return false; e.focus(); e.value = ''; \
             e.dispatchEvent(new Event('input', {{bubbles: true}})); return true",
            js_str(css)
        );
        if self.js(&body).await? != Value::Bool(true) {
            return Err(format!("{css}: no such element"));
        }
        self.call("Input.insertText", json!({"text": text})).await?;
        Ok(())
    }

    /// A PNG of the viewport.
    pub async fn screenshot(&self) -> Result<Vec<u8>, String> {
        let r = self
            .call("Page.captureScreenshot", json!({"format": "png"}))
            .await?;
        let data = r["data"].as_str().ok_or("no screenshot data")?;
        base64::engine::general_purpose::STANDARD
            .decode(data)
            .map_err(|e| e.to_string())
    }
}

/// `s` as a JavaScript string literal.
fn js_str(s: &str) -> String {
    Value::String(s.to_string()).to_string()
}

/// The DevTools port Chromium wrote into the profile (`DevToolsActivePort`, first line).
async fn devtools_port(profile: &Path) -> Result<u16, String> {
    let file = profile.join("DevToolsActivePort");
    let deadline = Instant::now() + CALL_TIMEOUT;
    loop {
        if let Ok(text) = std::fs::read_to_string(&file)
            && let Some(port) = text.lines().next().and_then(|l| l.trim().parse().ok())
        {
            return Ok(port);
        }
        if Instant::now() > deadline {
            return Err(format!("{CHROMIUM} wrote no {}", file.display()));
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// The CDP WebSocket address of the browser's page (`GET /json/list`).
async fn page_socket_url(port: u16) -> Result<String, String> {
    let deadline = Instant::now() + CALL_TIMEOUT;
    loop {
        if let Ok(targets) = json_list(port).await
            && let Some(url) = targets.as_array().and_then(|list| {
                list.iter()
                    .find(|t| t["type"] == "page")
                    .and_then(|t| t["webSocketDebuggerUrl"].as_str())
            })
        {
            return Ok(url.to_string());
        }
        if Instant::now() > deadline {
            return Err(format!("no page target on DevTools port {port}"));
        }
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// `GET /json/list` of the DevTools HTTP endpoint (its answer carries a `Content-Length`; the
/// endpoint keeps the connection open, so the body is read to that length).
async fn json_list(port: u16) -> Result<Value, String> {
    let mut s = TcpStream::connect(("127.0.0.1", port))
        .await
        .map_err(|e| e.to_string())?;
    let request = format!("GET /json/list HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\n\r\n");
    s.write_all(request.as_bytes())
        .await
        .map_err(|e| e.to_string())?;
    let mut answer = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        let n = tokio::time::timeout(CALL_TIMEOUT, s.read(&mut buf))
            .await
            .map_err(|_| "DevTools /json/list: no answer".to_string())?
            .map_err(|e| e.to_string())?;
        if n == 0 {
            return Err("DevTools /json/list: connection closed early".into());
        }
        answer.extend_from_slice(&buf[..n]);
        let text = String::from_utf8_lossy(&answer);
        if let Some((head, body)) = text.split_once("\r\n\r\n") {
            let length = head
                .lines()
                .find_map(|l| {
                    let (k, v) = l.split_once(':')?;
                    k.eq_ignore_ascii_case("content-length")
                        .then(|| v.trim().parse::<usize>().ok())?
                })
                .ok_or("DevTools /json/list: no Content-Length")?;
            if body.len() >= length {
                return serde_json::from_str(&body[..length]).map_err(|e| e.to_string());
            }
        }
    }
}
