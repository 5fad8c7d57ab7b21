//! End-to-end tests of the web HMI's security checks against `ncplc run --hmi` (issue 23): the
//! four browser-side attacks of the issue refused, the start URL's cookie, every role boundary,
//! read-only, the token file, the limits (body, WebSocket size and rate, clients) and TLS.

use crate::hmi_common;

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use hmi_common::{Hmi, Ws, raw, root};
use serde_json::Value;

const VIEWER: &str = "viewer-0123456789abcdef";
const OPERATOR: &str = "operator-0123456789abcdef";
const INTEGRATOR: &str = "integrator-0123456789abcdef";

fn bearer(token: &str) -> String {
    format!("Authorization: Bearer {token}\r\n")
}

fn lathe() -> std::path::PathBuf {
    root().join("plc-programs/lathe")
}

/// A token file with one token of each role.
fn token_file(dir: &Path) -> String {
    let path = dir.join("tokens");
    std::fs::write(
        &path,
        format!(
            "# the shop's HMI tokens\nviewer {VIEWER}\noperator {OPERATOR}\nintegrator {INTEGRATOR}\n"
        ),
    )
    .expect("write tokens");
    path.to_str().expect("utf8").to_string()
}

fn forced(hmi: &Hmi, signal: &str) -> Value {
    let r = raw(
        &hmi.addr,
        "GET",
        &format!("/api/signal/{signal}"),
        &bearer(hmi.token.as_deref().unwrap_or(INTEGRATOR)),
        None,
    );
    assert_eq!(r.status, 200, "{}", r.body);
    r.json()["forced"].clone()
}

#[test]
fn the_four_attacks_of_the_issue_are_refused_before_any_handler_runs() {
    let hmi = Hmi::start(&lathe(), &["--ticks", "100000"]);
    let token = hmi.token.clone().expect("the start URL's token");
    let auth = bearer(&token);
    let force = Some(r#"{"signal":"I0A3","value":1}"#);

    // 1. DNS rebinding: a foreign Host reads nothing and forces nothing, token or not.
    let evil_host = "Host: attacker.example:80\r\n";
    for (method, path, body) in [("GET", "/api/status", None), ("POST", "/api/force", force)] {
        for headers in [evil_host.to_string(), format!("{evil_host}{auth}")] {
            let r = raw(&hmi.addr, method, path, &headers, body);
            assert_eq!(r.status, 403, "{method} {path}: {}", r.body);
            assert_eq!(
                r.json()["error"],
                "Host `attacker.example:80` is not a name of this HMI (a page of another site may be trying to reach it); a name of the machine on your network is added with --hmi-allow-host"
            );
        }
    }
    // A Host on the right name but another port is foreign too.
    let other_port = format!("Host: 127.0.0.1:1\r\n{auth}");
    assert_eq!(
        raw(&hmi.addr, "GET", "/api/status", &other_port, None).status,
        403
    );
    assert_eq!(forced(&hmi, "I0A3"), false);

    // 2. Cross-site request forgery: a POST from a foreign origin is not executed.
    let evil_origin = format!("Origin: http://attacker.example\r\n{auth}");
    let r = raw(&hmi.addr, "POST", "/api/force", &evil_origin, force);
    assert_eq!(r.status, 403, "{}", r.body);
    assert_eq!(
        r.json()["error"],
        format!(
            "Origin `http://attacker.example` is not this HMI's origin (http://{}): requests that change the machine and WebSocket connections are taken only from the HMI's own page (or an origin given with --hmi-allow-origin)",
            hmi.addr
        )
    );
    // `null` (a sandboxed or privacy-stripped page) and malformed origins are foreign as well.
    for o in [
        "null",
        "attacker",
        "http://127.0.0.1:1",
        "https://attacker.example/x",
    ] {
        let h = format!("Origin: {o}\r\n{auth}");
        assert_eq!(
            raw(&hmi.addr, "POST", "/api/force", &h, force).status,
            403,
            "{o}"
        );
    }
    assert_eq!(forced(&hmi, "I0A3"), false);

    // 3. Cross-site WebSocket hijacking: an upgrade from a foreign origin is refused.
    let Err(answer) = Ws::try_connect_with(&hmi.addr, "/ws", &evil_origin) else {
        panic!("a foreign origin's WebSocket was upgraded");
    };
    assert!(answer.starts_with("HTTP/1.1 403"), "{answer}");
    // The page's own origin is upgraded.
    let own = format!("Origin: http://{}\r\n{auth}", hmi.addr);
    let mut ws = Ws::try_connect_with(&hmi.addr, "/ws", &own).expect("own origin upgrades");
    assert!(ws.next_tick(Duration::from_secs(10)).is_some());

    // 4. No token, even on loopback: 401 for the API and the WebSocket, 401 for a wrong one.
    let r = raw(&hmi.addr, "GET", "/api/status", "", None);
    assert_eq!(r.status, 401);
    assert_eq!(
        r.json()["error"],
        "this HMI needs its access token: open the address printed at start (http://…/?token=…), or send an Authorization: Bearer header"
    );
    let r = raw(
        &hmi.addr,
        "POST",
        "/api/force",
        &bearer("wrong-token-0123456789"),
        force,
    );
    assert_eq!(
        (r.status, r.json()["error"].clone()),
        (401, "the token is not valid for this HMI".into())
    );
    let Err(answer) = Ws::try_connect(&hmi.addr, "/ws") else {
        panic!("a WebSocket without token was upgraded");
    };
    assert!(answer.starts_with("HTTP/1.1 401"), "{answer}");
    assert_eq!(forced(&hmi, "I0A3"), false);
    // The scripts and styles stay public; the page itself needs the token.
    assert_eq!(
        raw(&hmi.addr, "GET", "/static/app.js", "", None).status,
        200
    );
    assert_eq!(raw(&hmi.addr, "GET", "/", "", None).status, 401);

    // The same force from the page's own origin with the token is executed.
    let r = raw(&hmi.addr, "POST", "/api/force", &own, force);
    assert_eq!(r.status, 200, "{}", r.body);
    // The reply names the tick that applied it; the snapshot the API reads shows it from then on.
    let applied = r.json()["tick"].as_u64().expect("tick");
    hmi.wait_tick(applied + 3);
    assert_eq!(forced(&hmi, "I0A3"), true);
    hmi.stop();
}

#[test]
fn the_start_url_becomes_an_http_only_strict_cookie_that_authenticates_the_page() {
    let hmi = Hmi::start(&lathe(), &["--ticks", "100000"]);
    let token = hmi.token.clone().expect("token");
    let port = hmi.addr.rsplit(':').next().expect("port").to_string();
    let r = raw(&hmi.addr, "GET", &format!("/?token={token}"), "", None);
    assert_eq!(r.status, 303, "{}", r.head);
    assert_eq!(r.header("location"), Some("/"));
    let cookie = format!("ncplc_hmi_{port}={token}");
    assert_eq!(
        r.header("set-cookie"),
        Some(format!("{cookie}; Path=/; HttpOnly; SameSite=Strict").as_str())
    );
    // With the cookie alone: the page, the API, a same-origin POST and the WebSocket.
    let with_cookie = format!("Cookie: theme=dark; {cookie}\r\n");
    assert_eq!(raw(&hmi.addr, "GET", "/", &with_cookie, None).status, 200);
    let r = raw(&hmi.addr, "GET", "/api/status", &with_cookie, None);
    assert_eq!(
        (r.status, r.json()["role"].clone()),
        (200, "integrator".into())
    );
    let post = format!("{with_cookie}Origin: http://{}\r\n", hmi.addr);
    let r = raw(
        &hmi.addr,
        "POST",
        "/api/write",
        &post,
        Some(r#"{"signal":"W0K0","value":7}"#),
    );
    assert_eq!(r.status, 200, "{}", r.body);
    let mut ws = Ws::try_connect_with(&hmi.addr, "/ws", &post).expect("upgrade with the cookie");
    assert!(ws.next_tick(Duration::from_secs(10)).is_some());
    // Another port's cookie is not this server's.
    let foreign = format!("Cookie: ncplc_hmi_1={token}\r\n");
    assert_eq!(
        raw(&hmi.addr, "GET", "/api/status", &foreign, None).status,
        401
    );
    hmi.stop();
}

/// Every role against every kind of request: allowed ones pass the check (the handler's own
/// answer), the others are 403 naming the role needed.
#[test]
fn each_role_reaches_exactly_its_routes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = token_file(dir.path());
    let hmi = Hmi::start(&lathe(), &["--ticks", "100000", "--hmi-token-file", &file]);
    assert_eq!(hmi.token, None, "a token file's tokens are not printed");
    let write = Some(r#"{"signal":"W0K1","value":5}"#);
    let force = Some(r#"{"signal":"U5A2","value":1}"#);
    let ack = Some(r#"{"command":"ack"}"#);
    let flow = Some(r#"{"enabled":false}"#);
    type Case = (
        &'static str,
        &'static str,
        Option<&'static str>,
        &'static str,
    );
    let cases: [Case; 7] = [
        ("GET", "/api/status", None, "viewer"),
        ("POST", "/api/command", ack, "operator"),
        ("POST", "/api/write", write, "integrator"),
        ("POST", "/api/force", force, "integrator"),
        ("DELETE", "/api/force/U5A2", None, "integrator"),
        ("DELETE", "/api/force", None, "integrator"),
        ("POST", "/api/flow", flow, "integrator"),
    ];
    let rank = |r: &str| {
        ["viewer", "operator", "integrator"]
            .iter()
            .position(|x| *x == r)
    };
    for (token, role) in [
        (VIEWER, "viewer"),
        (OPERATOR, "operator"),
        (INTEGRATOR, "integrator"),
    ] {
        let r = raw(&hmi.addr, "GET", "/api/status", &bearer(token), None);
        assert_eq!(r.json()["role"], role);
        for (method, path, body, needs) in cases {
            let r = raw(&hmi.addr, method, path, &bearer(token), body);
            if rank(role) >= rank(needs) {
                assert_eq!(r.status, 200, "{role} {method} {path}: {}", r.body);
            } else {
                assert_eq!(r.status, 403, "{role} {method} {path}: {}", r.body);
                let v = r.json();
                assert_eq!(
                    (v["role"].as_str(), v["needs"].as_str()),
                    (Some(role), Some(needs))
                );
                assert!(
                    v["error"].as_str().unwrap_or_default().ends_with(&format!(
                        " need the role {needs}; this session's role is {role}"
                    )),
                    "{v}"
                );
            }
        }
        // Every role watches the WebSocket.
        let mut ws = Ws::try_connect_with(&hmi.addr, "/ws", &bearer(token)).expect("upgrade");
        assert!(ws.next_tick(Duration::from_secs(10)).is_some(), "{role}");
    }
    let r = raw(&hmi.addr, "POST", "/api/force", &bearer(OPERATOR), force);
    assert_eq!(
        r.json()["error"],
        "forces need the role integrator; this session's role is operator"
    );
    hmi.stop();
}

#[test]
fn readonly_makes_every_token_a_viewer_and_a_bad_token_file_stops_the_start() {
    let dir = tempfile::tempdir().expect("tempdir");
    let file = token_file(dir.path());
    let hmi = Hmi::start(
        &lathe(),
        &[
            "--ticks",
            "100000",
            "--hmi-token-file",
            &file,
            "--hmi-readonly",
        ],
    );
    let r = raw(
        &hmi.addr,
        "POST",
        "/api/command",
        &bearer(INTEGRATOR),
        Some(r#"{"command":"ack"}"#),
    );
    assert_eq!(r.status, 403, "{}", r.body);
    assert_eq!(
        r.json()["error"],
        "operator commands (START, HOLD, RESET, mode, MDI, acknowledge) need the role operator; the HMI is read-only (--hmi-readonly): writes, forces and commands are disabled"
    );
    let r = raw(&hmi.addr, "GET", "/api/status", &bearer(INTEGRATOR), None);
    assert_eq!(
        (r.json()["role"].clone(), r.json()["readonly"].clone()),
        ("viewer".into(), true.into())
    );
    hmi.stop();

    // A located error for a bad token file, and no server.
    let bad = dir.path().join("bad");
    std::fs::write(&bad, format!("viewer {VIEWER}\nadmin {INTEGRATOR}\n")).expect("write");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(["run".as_ref(), lathe().as_os_str()])
        .args([
            "--hmi",
            "127.0.0.1:0",
            "--no-watch",
            "--ticks",
            "10",
            "--hmi-token-file",
        ])
        .arg(&bad)
        .output()
        .expect("ncplc");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!(
            "error: --hmi-token-file {}:2:1: `admin` is not a role (viewer, operator or integrator)",
            bad.display()
        )),
        "{err}"
    );
}

#[test]
fn over_limit_requests_get_clear_errors() {
    let hmi = Hmi::start(
        &lathe(),
        &[
            "--ticks",
            "100000",
            "--hmi-max-body",
            "64",
            "--hmi-max-clients",
            "4",
            "--hmi-ws-max-message",
            "32",
            "--hmi-ws-rate",
            "5",
        ],
    );
    let auth = bearer(hmi.token.as_deref().expect("token"));
    // A body over 64 bytes: 413, nothing executed.
    let long = format!(
        r#"{{"signal":"I0A3","value":1,"pad":"{}"}}"#,
        "x".repeat(64)
    );
    let r = raw(&hmi.addr, "POST", "/api/force", &auth, Some(&long));
    assert_eq!(r.status, 413, "{}", r.body);
    assert_eq!(
        r.json()["error"],
        "the request body is larger than 64 bytes (--hmi-max-body)"
    );
    assert_eq!(forced(&hmi, "I0A3"), false);

    // A WebSocket message over 32 bytes: closed with 1009 naming the limit.
    let mut ws = Ws::try_connect_with(&hmi.addr, "/ws?ack=1", &auth).expect("upgrade");
    assert!(ws.next_tick(Duration::from_secs(10)).is_some());
    ws.send(&"a".repeat(33));
    assert_eq!(
        ws.close_frame(Duration::from_secs(10)),
        Some((1009, "message over 32 bytes".to_string()))
    );
    // More than 5 messages in a second: closed with 1008 naming the limit.
    let mut ws = Ws::try_connect_with(&hmi.addr, "/ws", &auth).expect("upgrade");
    for _ in 0..6 {
        ws.send("ack");
    }
    assert_eq!(
        ws.close_frame(Duration::from_secs(10)),
        Some((1008, "more than 5 messages per second".to_string()))
    );
    // At most 4 connections: the fifth gets a 503, and once one closes there is room again.
    std::thread::sleep(Duration::from_millis(200));
    let held: Vec<TcpStream> = (0..4)
        .map(|_| TcpStream::connect(&hmi.addr).expect("connect"))
        .collect();
    std::thread::sleep(Duration::from_millis(200));
    let r = raw(&hmi.addr, "GET", "/api/status", &auth, None);
    assert_eq!(r.status, 503, "{}", r.body);
    assert_eq!(
        r.json()["error"],
        "too many clients: this HMI serves at most 4 connections at once (--hmi-max-clients)"
    );
    drop(held);
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(
        raw(&hmi.addr, "GET", "/api/status", &auth, None).status,
        200
    );
    hmi.stop();
}

/// A certificate for `localhost`, generated here, and its key, as PEM files.
fn certificate(dir: &Path) -> (String, String, rcgen::CertifiedKey<rcgen::KeyPair>) {
    let ck = rcgen::generate_simple_self_signed(vec!["localhost".to_string()]).expect("rcgen");
    let cert = dir.join("cert.pem");
    let key = dir.join("key.pem");
    std::fs::write(&cert, ck.cert.pem()).expect("cert");
    std::fs::write(&key, ck.signing_key.serialize_pem()).expect("key");
    let s = |p: &Path| p.to_str().expect("utf8").to_string();
    (s(&cert), s(&key), ck)
}

#[test]
fn tls_serves_the_api_to_a_rustls_client_and_the_cookie_is_secure() {
    use tokio_rustls::rustls;
    let dir = tempfile::tempdir().expect("tempdir");
    let (cert, key, ck) = certificate(dir.path());
    let hmi = Hmi::start(
        &lathe(),
        &[
            "--ticks",
            "100000",
            "--hmi-tls-cert",
            &cert,
            "--hmi-tls-key",
            &key,
        ],
    );
    let token = hmi.token.clone().expect("token");
    let port = hmi.addr.rsplit(':').next().expect("port").to_string();
    let mut roots = rustls::RootCertStore::empty();
    roots.add(ck.cert.der().clone()).expect("root");
    let provider = Arc::new(rustls::crypto::ring::default_provider());
    let config = Arc::new(
        rustls::ClientConfig::builder_with_provider(provider)
            .with_safe_default_protocol_versions()
            .expect("versions")
            .with_root_certificates(roots)
            .with_no_client_auth(),
    );
    let https = |path: &str, headers: &str| -> String {
        let name = rustls::pki_types::ServerName::try_from("localhost").expect("name");
        let conn = rustls::ClientConnection::new(config.clone(), name).expect("client");
        let tcp = TcpStream::connect(&hmi.addr).expect("connect");
        tcp.set_read_timeout(Some(Duration::from_secs(10)))
            .expect("timeout");
        let mut tls = rustls::StreamOwned::new(conn, tcp);
        write!(
            tls,
            "GET {path} HTTP/1.1\r\nHost: localhost:{port}\r\nConnection: close\r\n{headers}\r\n"
        )
        .expect("send");
        let mut out = Vec::new();
        let _ = tls.read_to_end(&mut out);
        String::from_utf8_lossy(&out).into_owned()
    };
    let answer = https("/api/status", &bearer(&token));
    assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
    assert!(answer.contains("\"role\":\"integrator\""), "{answer}");
    let answer = https("/api/status", "");
    assert!(answer.starts_with("HTTP/1.1 401"), "{answer}");
    let answer = https(&format!("/?token={token}"), "");
    assert!(answer.starts_with("HTTP/1.1 303"), "{answer}");
    assert!(
        answer.contains(&format!(
            "ncplc_hmi_{port}={token}; Path=/; HttpOnly; SameSite=Strict; Secure"
        )),
        "{answer}"
    );
    // Plain HTTP to the TLS port gets no answer.
    let mut plain = TcpStream::connect(&hmi.addr).expect("connect");
    plain
        .set_read_timeout(Some(Duration::from_secs(5)))
        .expect("timeout");
    write!(
        plain,
        "GET /api/status HTTP/1.1\r\nHost: localhost:{port}\r\n\r\n"
    )
    .expect("send");
    let mut got = Vec::new();
    let _ = plain.read_to_end(&mut got);
    assert!(!String::from_utf8_lossy(&got).contains("HTTP/1.1 200"));
    hmi.stop();
}

#[test]
fn a_key_that_is_no_key_stops_the_start_with_its_file_named() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (cert, _, _) = certificate(dir.path());
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .args(["run".as_ref(), lathe().as_os_str()])
        .args(["--hmi", "127.0.0.1:0", "--no-watch", "--ticks", "10"])
        .args(["--hmi-tls-cert", &cert, "--hmi-tls-key", &cert])
        .output()
        .expect("ncplc");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!("error: --hmi-tls-key {cert}: ")),
        "{err}"
    );
}
