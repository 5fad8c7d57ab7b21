//! End-to-end tests of `ncplc lsp`: a small LSP client (Content-Length framing over the child's
//! stdin/stdout) drives the real binary through initialize, didOpen/didChange, hover, definition,
//! references, highlights, completion, rename, formatting and symbols on the bundled machines,
//! with exact expected results; and every diagnostic `ncplc build` gives on a corpus of broken
//! programs (tests/lsp-corpus) must come from the server at the same place with the same code,
//! message and hint. Also `ncplc fmt` as a CLI, and the power flow of a running `ncplc run --hmi`
//! as inlay hints.

use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .canonicalize()
        .expect("the repository")
}

fn uri(p: &Path) -> String {
    let mut s = String::from("file://");
    for b in p.to_str().expect("utf-8 path").bytes() {
        if b.is_ascii_alphanumeric() || b"/-._~".contains(&b) {
            s.push(char::from(b));
        } else {
            s.push_str(&format!("%{b:02X}"));
        }
    }
    s
}

/// A running `ncplc lsp` and what it sent that was not yet asked for.
struct Client {
    child: Child,
    stdin: ChildStdin,
    rx: Receiver<Value>,
    next_id: i64,
    /// Notifications received while waiting for something else.
    notes: Vec<Value>,
}

impl Client {
    fn start() -> Client {
        Client::start_with(json!({"debounceMs": 0}), json!({}))
    }

    /// A server started with these `initializationOptions` and client capabilities.
    fn start_with(options: Value, capabilities: Value) -> Client {
        let mut child = Command::new(env!("CARGO_BIN_EXE_ncplc"))
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("ncplc lsp starts");
        let stdin = child.stdin.take().expect("stdin");
        let stdout = child.stdout.take().expect("stdout");
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut r = BufReader::new(stdout);
            loop {
                let mut len = None;
                loop {
                    let mut line = String::new();
                    if r.read_line(&mut line).unwrap_or(0) == 0 {
                        return;
                    }
                    let line = line.trim_end();
                    if line.is_empty() {
                        break;
                    }
                    if let Some(v) = line.strip_prefix("Content-Length: ") {
                        len = v.parse::<usize>().ok();
                    }
                }
                let mut body = vec![0; len.expect("Content-Length")];
                if r.read_exact(&mut body).is_err() {
                    return;
                }
                let v: Value = serde_json::from_slice(&body).expect("JSON from the server");
                if tx.send(v).is_err() {
                    return;
                }
            }
        });
        let mut c = Client {
            child,
            stdin,
            rx,
            next_id: 1,
            notes: Vec::new(),
        };
        let r = c.request(
            "initialize",
            json!({"capabilities": capabilities, "initializationOptions": options}),
        );
        assert_eq!(r["result"]["capabilities"]["hoverProvider"], json!(true));
        assert_eq!(r["result"]["capabilities"]["textDocumentSync"], json!(2));
        c.notify("initialized", json!({}));
        c
    }

    fn send(&mut self, v: Value) {
        let body = v.to_string();
        write!(self.stdin, "Content-Length: {}\r\n\r\n{body}", body.len()).expect("write");
        self.stdin.flush().expect("flush");
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    fn recv(&mut self) -> Value {
        match self.rx.recv_timeout(Duration::from_secs(60)) {
            Ok(v) => v,
            Err(RecvTimeoutError::Timeout) => panic!("no message from the server in 60 s"),
            Err(RecvTimeoutError::Disconnected) => panic!("the server closed its output"),
        }
    }

    /// The whole response (`result` or `error`).
    fn request(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        self.send(json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        loop {
            let v = self.recv();
            if v["id"] == json!(id) && v.get("method").is_none() {
                return v;
            }
            self.notes.push(v);
        }
    }

    /// The next `publishDiagnostics` for `uri`.
    fn diagnostics(&mut self, uri: &str) -> Vec<Value> {
        let start = Instant::now();
        loop {
            if let Some(i) = self.notes.iter().position(|n| {
                n["method"] == "textDocument/publishDiagnostics" && n["params"]["uri"] == uri
            }) {
                let n = self.notes.remove(i);
                return n["params"]["diagnostics"]
                    .as_array()
                    .cloned()
                    .unwrap_or_default();
            }
            assert!(start.elapsed() < Duration::from_secs(60), "no diagnostics");
            let v = self.recv();
            self.notes.push(v);
        }
    }

    fn open(&mut self, uri: &str, text: &str) -> Vec<Value> {
        self.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri, "languageId": "ncplc-plc", "version": 1, "text": text}}),
        );
        self.diagnostics(uri)
    }

    fn at(&mut self, method: &str, uri: &str, line: u32, character: u32, extra: Value) -> Value {
        let mut p = json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}});
        if let (Some(p), Some(e)) = (p.as_object_mut(), extra.as_object()) {
            p.extend(e.clone());
        }
        self.request(method, p)
    }

    fn stop(mut self) {
        let r = self.request("shutdown", Value::Null);
        assert_eq!(r["result"], Value::Null);
        self.notify("exit", Value::Null);
        let status = self.child.wait().expect("the server exits");
        assert!(status.success(), "{status}");
    }
}

fn range(l0: u32, c0: u32, l1: u32, c1: u32) -> Value {
    json!({"start": {"line": l0, "character": c0}, "end": {"line": l1, "character": c1}})
}

fn hover_text(v: &Value) -> String {
    v["result"]["contents"]["value"]
        .as_str()
        .unwrap_or("")
        .to_string()
}

#[test]
fn the_lathe_program_through_every_request() {
    let path = root().join("plc-programs/lathe/MP0/PLCPRG");
    let text = std::fs::read_to_string(&path).expect("the lathe program");
    let u = uri(&path);
    let mut c = Client::start();
    assert_eq!(c.open(&u, &text), Vec::<Value>::new());
    assert!(
        c.notes.iter().all(|n| n["method"] != "window/showMessage"),
        "no note for a file inside a machine"
    );

    // Hover: a timer, an interface name, an alias of a packet-A output, a keyword.
    assert_eq!(
        hover_text(&c.at("textDocument/hover", &u, 52, 6, json!({}))),
        "```plc\nDEF SP_READY : TON(200ms)\n```\n`SP_READY`: defined at line 53, type TON\n\n\
         TON on-delay timer, preset 200 ms = 20 ticks of the 10 ms logic tick (IOCFIL `CLO` tick_logic; \
         the preset is rounded up to whole ticks). Reads: `t` / `t.Q`, `t.ET` (ms)."
    );
    let h = c.at("textDocument/hover", &u, 62, 2, json!({}));
    assert_eq!(
        hover_text(&h),
        "Interface map: **ESTOP** (U11K4) — emergency stop, active when 0 (wire-break safe); width bit, \
         direction out (PLC → CNC), process 1\n\nPacket K, connector 11, bit 4; width bit\n\n\
         Who writes it: written by the PLC, read by the CNC. This program writes it at line 63."
    );
    assert_eq!(h["result"]["range"], range(62, 0, 62, 5));
    assert_eq!(
        hover_text(&c.at("textDocument/hover", &u, 63, 3, json!({}))),
        "```plc\nDEF DRIVES_ON = U4A4\n```\n`DRIVES_ON`: defined at line 41, a name for the signal below\n\n\
         Packet A, connector 4, bit 4; width bit\n\nIOCFIL line 7 `OU0=4,5,,,,,,` declares output connector 4\n\n\
         Who writes it: written by the PLC, driven to a physical output by the I/O. This program writes it at line 64."
    );
    assert_eq!(
        hover_text(&c.at("textDocument/hover", &u, 97, 1, json!({}))),
        "**SET**: `SET target = expr`: set coil, target := 1 when expr is 1 (§4)"
    );

    // Definition of a DEF name, from a use.
    let d = c.at("textDocument/definition", &u, 61, 3, json!({}));
    assert_eq!(
        d["result"],
        json!({"uri": u, "range": range(45, 4, 45, 12)})
    );

    // References: the DEF name, the aliased signal and the write, in order.
    let r = c.at(
        "textDocument/references",
        &u,
        63,
        0,
        json!({"context": {"includeDeclaration": true}}),
    );
    assert_eq!(
        r["result"],
        json!([
            {"uri": u, "range": range(40, 4, 40, 13)},
            {"uri": u, "range": range(40, 16, 40, 20)},
            {"uri": u, "range": range(63, 0, 63, 9)},
        ])
    );
    // Highlights mark the write (3) and the reads (2) of CHAIN_OK on the lines 62..64.
    let hl = c.at("textDocument/documentHighlight", &u, 61, 0, json!({}));
    let kinds: Vec<(u64, u64)> = hl["result"]
        .as_array()
        .expect("highlights")
        .iter()
        .filter(|h| (61..=63).contains(&h["range"]["start"]["line"].as_u64().unwrap_or(0)))
        .map(|h| {
            (
                h["range"]["start"]["line"].as_u64().unwrap_or(0),
                h["kind"].as_u64().unwrap_or(0),
            )
        })
        .collect();
    assert_eq!(kinds, vec![(61, 3), (62, 2), (63, 2)]);

    // Completion: DEF names with their type, interface names with address and meaning, the
    // machine's packet-A contacts, snippets.
    let items = c.at("textDocument/completion", &u, 82, 0, json!({}));
    let items = items["result"].as_array().expect("items").clone();
    let detail = |label: &str| {
        items
            .iter()
            .find(|i| i["label"] == label)
            .map(|i| i["detail"].as_str().unwrap_or("").to_string())
    };
    assert_eq!(detail("SP_READY").as_deref(), Some("TON(200 ms)"));
    assert_eq!(detail("DRIVES_ON").as_deref(), Some("= U4A4"));
    assert_eq!(
        detail("FOLD").as_deref(),
        Some("U10K5 · feed hold request (level)")
    );
    assert_eq!(
        detail("I1A31").as_deref(),
        Some("input connector 1 contact 31 (IOCFIL)")
    );
    assert_eq!(detail("I2A0"), None, "connector 2 is not declared");
    let coil = items
        .iter()
        .find(|i| i["label"] == "self-holding coil")
        .expect("the snippet");
    assert_eq!(
        coil["insertText"],
        "${1:U4A0} = (${2:I0A0} + ${1:U4A0}) * /${3:I0A1}"
    );

    // Rename of a DEF name: every use outside comments (15 lines).
    let r = c.at(
        "textDocument/rename",
        &u,
        61,
        0,
        json!({"newName": "CHAIN_CLOSED"}),
    );
    let edits = r["result"]["changes"][&u]
        .as_array()
        .expect("edits")
        .clone();
    let lines: Vec<u64> = edits
        .iter()
        .map(|e| e["range"]["start"]["line"].as_u64().unwrap_or(0))
        .collect();
    assert_eq!(
        lines,
        vec![
            45, 61, 62, 63, 66, 67, 72, 74, 76, 79, 80, 81, 100, 109, 131
        ]
    );
    assert!(edits.iter().all(|e| e["newText"] == "CHAIN_CLOSED"));
    // … refused for an interface-map name and for a bad new name.
    let r = c.at("textDocument/rename", &u, 62, 0, json!({"newName": "X"}));
    assert_eq!(
        r["error"]["message"],
        "`ESTOP` is a name of the interface map (docs/plc-interface-map.md); the CNC knows it by that name, rename it in the machine's interface.toml instead"
    );
    let r = c.at("textDocument/rename", &u, 61, 0, json!({"newName": "U4A0"}));
    assert!(
        r["error"]["message"]
            .as_str()
            .is_some_and(|m| m.starts_with("`U4A0` is not a valid name")),
        "{r}"
    );

    // Document symbols: FAST with its 35 DEFs (20 aliases, 15 variables and blocks), SLOW with the
    // 3 aliases of the PLC messages' request bits.
    let s = c.request(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": u}}),
    );
    let s = s["result"].as_array().expect("symbols").clone();
    assert_eq!(s.len(), 2);
    assert_eq!(
        (s[0]["name"].as_str(), s[1]["name"].as_str()),
        (Some("FAST"), Some("SLOW"))
    );
    assert_eq!(s[0]["children"].as_array().map(Vec::len), Some(35));
    assert_eq!(s[1]["children"].as_array().map(Vec::len), Some(3));

    // An edit that reads an undeclared connector: error 1104 at once (debounce 0), at its place.
    c.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": u, "version": 2},
               "contentChanges": [{"range": range(63, 12, 63, 20), "text": "I2A0"}]}),
    );
    let d = c.diagnostics(&u);
    assert_eq!(d.len(), 1, "{d:?}");
    assert_eq!(d[0]["code"], 1104);
    assert_eq!(d[0]["severity"], 1);
    assert_eq!(d[0]["range"], range(63, 12, 63, 16));
    // Undo: clean again.
    c.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": u, "version": 3},
               "contentChanges": [{"range": range(63, 12, 63, 16), "text": "CHAIN_OK"}]}),
    );
    assert_eq!(c.diagnostics(&u), Vec::<Value>::new());

    // Formatting a document of the same machine (not on disk).
    let fu = uri(&root().join("plc-programs/lathe/MP0/FMT.plc"));
    c.open(&fu, "IF I0A0 THEN\nU4A0 = 1 ; on   \nEND_IF");
    let f = c.request(
        "textDocument/formatting",
        json!({"textDocument": {"uri": fu}, "options": {"tabSize": 2, "insertSpaces": true}}),
    );
    assert_eq!(
        f["result"],
        json!([{"range": range(0, 0, 2, 6), "newText": "IF I0A0 THEN\n  U4A0 = 1 ; on\nEND_IF\n"}])
    );

    // Workspace symbols over the open documents.
    let w = c.request("workspace/symbol", json!({"query": "lube_"}));
    let mut names: Vec<String> = w["result"]
        .as_array()
        .expect("symbols")
        .iter()
        .map(|s| s["name"].as_str().unwrap_or("").to_string())
        .collect();
    names.sort();
    assert_eq!(
        names,
        vec![
            "LUBE_ACKED",
            "LUBE_ACK_LAMP",
            "LUBE_ALARM",
            "LUBE_CLOCK",
            "LUBE_LAMP",
            "LUBE_LEVEL_OK",
            "LUBE_LOW",
            "LUBE_MINUTES",
            "LUBE_PUMP",
            "LUBE_RUN"
        ]
    );
    c.stop();
}

#[test]
fn the_mill_goes_to_its_interface_toml_and_a_file_outside_a_machine_is_told_once() {
    let mill = root().join("plc-programs/mill");
    let path = mill.join("MP0/PLCPRG");
    let text = std::fs::read_to_string(&path).expect("the mill program");
    let u = uri(&path);
    let mut c = Client::start();
    assert_eq!(c.open(&u, &text), Vec::<Value>::new());
    // Line 161: `MFIN_T = MSTB_T * …`: MSTB_T is process 2's M strobe from interface.toml.
    let d = c.at("textDocument/definition", &u, 160, 10, json!({}));
    assert_eq!(d["result"]["uri"], uri(&mill.join("interface.toml")));
    let toml = std::fs::read_to_string(mill.join("interface.toml")).expect("interface.toml");
    let at = toml.find("\"MSTB_T\"").expect("the entry");
    let line = toml[..at].matches('\n').count() as u64;
    assert_eq!(d["result"]["range"]["start"]["line"], line);
    let h = hover_text(&c.at("textDocument/hover", &u, 160, 10, json!({})));
    assert!(
        h.starts_with("Interface map: **MSTB_T** (I6K0) — magazine process: M strobe, a new M code is in MCODE_T; width bit, direction in (CNC → PLC), process 2\n\nPacket K, connector 6, bit 0; width bit\n\nWho writes it: written by the CNC, read by the PLC."),
        "{h}"
    );

    let dir = tempfile::tempdir().expect("temp dir");
    let loose = uri(&dir.path().join("loose.plc"));
    // Connector 6 is an output connector by the language's rule; without a machine it is allowed.
    assert_eq!(
        c.open(&loose, "U6A0 = I2A0\nU4A1 = I9A0\n"),
        Vec::<Value>::new()
    );
    let other = uri(&dir.path().join("other.plc"));
    let d = c.open(&other, "U4A0 = I4A0\n");
    assert_eq!(d.len(), 1);
    assert_eq!(d[0]["code"], 1105);
    let told: Vec<&Value> = c
        .notes
        .iter()
        .filter(|n| n["method"] == "window/showMessage")
        .collect();
    assert_eq!(told.len(), 1, "said once: {told:?}");
    assert!(
        told[0]["params"]["message"].as_str().is_some_and(
            |m| m.contains("loose.plc is not inside a machine directory (no FCRSYS above it)")
        ),
        "{told:?}"
    );
    c.stop();
}

/// `ncplc build --format json` of `file` as the lathe's PLC program: (code, line, column,
/// severity, message, hint) of every diagnostic.
fn build_diagnostics(file: &Path) -> Vec<(u64, u64, u64, String, String, String)> {
    let out = Command::new(env!("CARGO_BIN_EXE_ncplc"))
        .arg("build")
        .arg(root().join("plc-programs/lathe"))
        .arg("--plc")
        .arg(file)
        .args(["--format", "json", "--max-errors", "0"])
        .output()
        .expect("ncplc build runs");
    String::from_utf8_lossy(&out.stderr)
        .lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| {
            let v: Value = serde_json::from_str(l).expect("a JSON line");
            (
                v["code"].as_u64().unwrap_or(0),
                v["line"].as_u64().unwrap_or(0),
                v["column"].as_u64().unwrap_or(0),
                v["severity"].as_str().unwrap_or("").to_string(),
                v["message"].as_str().unwrap_or("").to_string(),
                v["hint"].as_str().unwrap_or("").to_string(),
            )
        })
        .collect()
}

#[test]
fn every_build_diagnostic_of_the_broken_corpus_comes_from_the_server_at_the_same_place() {
    let corpus = root().join("tests/lsp-corpus");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&corpus)
        .expect("the corpus")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    files.sort();
    assert_eq!(files.len(), 6);
    let mut c = Client::start();
    let mut total = 0;
    for f in &files {
        let want = build_diagnostics(f);
        assert!(!want.is_empty(), "{}: build reports nothing", f.display());
        let text = std::fs::read_to_string(f).expect("read");
        // Opened as a file of the lathe, so that the server checks it against the same machine.
        let name = f.file_name().and_then(|n| n.to_str()).expect("name");
        let u = uri(&root().join("plc-programs/lathe/MP0").join(name));
        let got: Vec<_> = c
            .open(&u, &text)
            .iter()
            .map(|d| {
                let full = d["message"].as_str().unwrap_or("");
                let (message, hint) = full.split_once("\nhelp: ").unwrap_or((full, ""));
                (
                    d["code"].as_u64().unwrap_or(0),
                    d["range"]["start"]["line"].as_u64().unwrap_or(0) + 1,
                    d["range"]["start"]["character"].as_u64().unwrap_or(0) + 1,
                    if d["severity"] == 1 {
                        "error"
                    } else {
                        "warning"
                    }
                    .to_string(),
                    message.to_string(),
                    hint.to_string(),
                )
            })
            .collect();
        // Whole-file diagnostics (line 0) are at the start of the document in LSP.
        let want: Vec<_> = want
            .into_iter()
            .map(|(code, l, col, s, m, h)| (code, l.max(1), col.max(1), s, m, h))
            .collect();
        assert_eq!(got, want, "{}", f.display());
        total += want.len();
    }
    assert!(total >= 40, "{total} diagnostics in the corpus");
    c.stop();
}

#[test]
fn ncplc_fmt_rewrites_checks_and_refuses_legacy_encodings() {
    let dir = tempfile::tempdir().expect("temp dir");
    let p = dir.path().join("PLCPRG");
    std::fs::write(&p, "IF I0A0 THEN\nU4A0 = 1\nEND_IF\n\n").expect("write");
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_ncplc"))
            .arg("fmt")
            .arg(&p)
            .args(args)
            .output()
            .expect("ncplc fmt runs")
            .status
            .code()
    };
    assert_eq!(run(&["--check"]), Some(1));
    assert_eq!(
        std::fs::read_to_string(&p).expect("read"),
        "IF I0A0 THEN\nU4A0 = 1\nEND_IF\n\n"
    );
    assert_eq!(run(&[]), Some(0));
    assert_eq!(
        std::fs::read_to_string(&p).expect("read"),
        "IF I0A0 THEN\n  U4A0 = 1\nEND_IF\n"
    );
    assert_eq!(run(&["--check"]), Some(0));
    std::fs::write(&p, b"U4A0 = I0A0 ; \xe0\xa0\n").expect("write");
    assert_eq!(run(&[]), Some(2));
    assert_eq!(
        std::fs::read(&p).expect("read"),
        b"U4A0 = I0A0 ; \xe0\xa0\n".to_vec()
    );
    // Over the PLC source limit: refused, read no further than the limit, left as it is.
    let big = "U4A0 = I0A0\n".repeat(3_000_000 / 12);
    std::fs::write(&p, &big).expect("write");
    assert_eq!(run(&[]), Some(2));
    assert_eq!(std::fs::read_to_string(&p).expect("read"), big);
    // Formatting replaces the file by a rename (a new inode: never half written over the old
    // program) and leaves no temporary file.
    std::fs::write(&p, "IF I0A0 THEN\nU4A0 = 1\nEND_IF\n").expect("write");
    let inode = |p: &std::path::Path| {
        use std::os::unix::fs::MetadataExt;
        std::fs::metadata(p).expect("metadata").ino()
    };
    let before = inode(&p);
    assert_eq!(run(&[]), Some(0));
    assert_ne!(inode(&p), before);
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .expect("dir")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names, [std::ffi::OsString::from("PLCPRG")]);
}

/// The power flow of a running `ncplc run --hmi … --hmi-flow` of the lathe as inlay hints on its
/// program, at the end of each statement's line, refreshed by the client when the server asks; none
/// on a text that is not the running program.
#[test]
fn inlay_hints_show_the_power_flow_of_the_running_lathe() {
    let machine = root().join("plc-programs/lathe");
    let hmi = crate::hmi_common::Hmi::start(&machine, &["--hmi-flow"]);
    hmi.wait_tick(20);
    let url = format!(
        "http://{}/?token={}",
        hmi.addr,
        hmi.token.clone().unwrap_or_default()
    );
    let mut c = Client::start_with(
        json!({"debounceMs": 0, "hmi": url}),
        json!({"workspace": {"inlayHint": {"refreshSupport": true}}}),
    );
    let path = machine.join("MP0/PLCPRG");
    let text = std::fs::read_to_string(&path).expect("the lathe program");
    let u = uri(&path);
    c.open(&u, &text);
    let n = u32::try_from(text.lines().count()).expect("lines");
    let all = json!({"textDocument": {"uri": u}, "range": range(0, 0, n, 0)});
    // CHAIN_OK = ESTOP_PB_OK * OVERTRAVEL_OK (line 62) computes 1 while the sim closes the chain.
    let line62 = text.lines().nth(61).expect("line 62");
    let end = u32::try_from(line62.encode_utf16().count()).expect("short");
    let start = Instant::now();
    loop {
        let hints = c.request("textDocument/inlayHint", all.clone())["result"].clone();
        let h = hints.as_array().and_then(|h| {
            h.iter()
                .find(|h| h["position"]["line"] == json!(61))
                .cloned()
        });
        if let Some(h) = h.filter(|h| h["label"] == json!("= 1")) {
            assert_eq!(h["position"], json!({"line": 61, "character": end}));
            assert_eq!(h["paddingLeft"], json!(true));
            // One hint per line at most.
            let lines: Vec<&Value> = hints
                .as_array()
                .map(|h| h.iter().map(|h| &h["position"]["line"]).collect())
                .unwrap_or_default();
            let mut dedup = lines.clone();
            dedup.dedup();
            assert_eq!(lines, dedup);
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "no `= 1` hint on line 62 in 30 s: {hints}"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    // The client can refresh: the server asks it to, about every second, for live values.
    let start = Instant::now();
    let ask = loop {
        if let Some(i) = c
            .notes
            .iter()
            .position(|m| m["method"] == json!("workspace/inlayHint/refresh"))
        {
            break c.notes.remove(i);
        }
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "no refresh request in 10 s"
        );
        let m = c.recv();
        c.notes.push(m);
    };
    assert_eq!(ask["params"], Value::Null);
    let id = ask["id"].clone();
    c.send(json!({"jsonrpc": "2.0", "id": id, "result": null}));
    // Edited, the text is no longer the program that runs: no hints.
    c.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": u, "version": 2},
               "contentChanges": [{"range": range(0, 0, 0, 0), "text": "; edited\n"}]}),
    );
    let hints = c.request("textDocument/inlayHint", all)["result"].clone();
    assert_eq!(hints, json!([]));
    c.stop();
    hmi.stop();
}
