#![no_main]
//! The web HMI's router, security checks first, on arbitrary requests: method, path (with any
//! query), headers (Host, Origin, Cookie, Authorization, Upgrade) and body chosen by the input.
//! Never a panic, never a 500, every refusal a JSON `{"error": …}`; work bounded per request.
//! A thread plays the scan and answers every request at once.

use std::sync::{Arc, OnceLock, mpsc};

use axum::body::Body;
use axum::http::Request;
use hmi::security::limits::Limits;
use hmi::security::{Guard, Role, Tokens, host, origin};
use hmi::server::{AppState, router};
use hmi::{Catalog, Demand, Envelope, ServerConfig, Snapshot};
use tower::ServiceExt;

const TOKEN: &str = "fuzz-token-0123456789";

fn state() -> &'static (tokio::runtime::Runtime, AppState) {
    static STATE: OnceLock<(tokio::runtime::Runtime, AppState)> = OnceLock::new();
    STATE.get_or_init(|| {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("runtime");
        let addr = "127.0.0.1:8080".parse().expect("addr");
        let tokens = Tokens::single(TOKEN.into(), Role::Integrator);
        let limits = Limits::default();
        let (_tx, snapshots) = tokio::sync::watch::channel(Arc::new(Snapshot::default()));
        std::mem::forget(_tx);
        let (requests, rx) = mpsc::channel::<Envelope>();
        std::thread::spawn(move || {
            for env in rx {
                let _ = env.reply.send(Ok(1));
            }
        });
        let guard = Guard {
            hosts: host::HostList::new(addr, false, &["panel.lan".into()]),
            origins: origin::OriginList::new(&["http://panel.lan:8080".into()]),
            tokens: tokens.clone(),
            readonly: false,
            tls: false,
            port: 8080,
            max_body: limits.max_body,
        };
        let state = AppState {
            config: Arc::new(ServerConfig {
                addr,
                tokens,
                readonly: false,
                allow_hosts: vec![],
                allow_origins: vec![],
                tls: None,
                limits,
            }),
            catalog: Arc::new(Catalog::default()),
            snapshots,
            requests,
            demand: Arc::new(Demand::default()),
            guard: Arc::new(guard),
        };
        (rt, state)
    })
}

const METHODS: [&str; 6] = ["GET", "POST", "DELETE", "PUT", "HEAD", "PATCH"];
const HEADERS: [&str; 6] = [
    "host",
    "origin",
    "cookie",
    "authorization",
    "upgrade",
    "content-type",
];

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    // CPU time of this thread (the router runs on it: a current-thread runtime), not the wall
    // clock: a campaign at low priority on a loaded machine saw an 11-byte request "take" 682 ms
    // of wall time while it waited for the CPU. A request that hangs is libFuzzer's -timeout.
    let started = ncplc_fuzz::CpuClock::start();
    let Some((&first, rest)) = data.split_first() else {
        return;
    };
    let text = String::from_utf8_lossy(rest);
    // Line 1: the path; then header lines `N:value` (N a digit picking the header); a blank
    // line; the body. Bit 7 of the first byte adds the right token, bit 6 the right Host.
    let mut parts = text.splitn(2, "\n\n");
    let head = parts.next().unwrap_or_default();
    let body = parts.next().unwrap_or_default().to_string();
    let mut lines = head.lines();
    let path = lines.next().unwrap_or("/");
    let method = METHODS[usize::from(first & 7) % METHODS.len()];
    let mut b = Request::builder()
        .method(method)
        .uri(if path.starts_with('/') {
            path.to_string()
        } else {
            format!("/{path}")
        });
    if first & 0x40 != 0 {
        b = b.header("host", "127.0.0.1:8080");
    }
    if first & 0x80 != 0 {
        b = b.header("authorization", format!("Bearer {TOKEN}"));
    }
    for l in lines {
        if let Some((n, v)) = l.split_once(':')
            && let Some(d) = n.parse::<usize>().ok().filter(|d| *d < HEADERS.len())
        {
            b = b.header(HEADERS[d], v);
        }
    }
    let Ok(req) = b.body(Body::from(body)) else {
        return;
    };
    let (rt, state) = state();
    let resp = rt.block_on(async { router(state.clone()).oneshot(req).await });
    let Ok(resp) = resp;
    let status = resp.status();
    assert_ne!(status.as_u16(), 500, "a request made the HMI fail");
    // A HEAD answer has no body by definition (RFC 9110 §9.3.2): only its status is checked.
    if status.is_client_error() && status.as_u16() != 405 && method != "HEAD" {
        let bytes = rt
            .block_on(axum::body::to_bytes(resp.into_body(), 1 << 20))
            .expect("body");
        if !bytes.starts_with(b"<!doctype") {
            let v: serde_json::Value = serde_json::from_slice(&bytes).unwrap_or_else(|e| {
                panic!(
                    "{status}: not JSON ({e}): {}",
                    String::from_utf8_lossy(&bytes)
                )
            });
            assert!(v["error"].is_string(), "{status}: {v}");
        }
    }
    let budget = std::time::Duration::from_millis(500 + data.len() as u64 / 10);
    assert!(
        started.elapsed() <= budget,
        "{} bytes took {:?}",
        data.len(),
        started.elapsed()
    );
});
