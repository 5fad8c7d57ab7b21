//! The protocol loop: lsp-server over stdio (or any [`Connection`], e.g. `Connection::memory()`
//! in tests), the open documents, debounced diagnostics, and the requests.
//!
//! Diagnostics of an edit are published when no further edit of that document arrived for the
//! debounce time (`initializationOptions.debounceMs`, default [`DEBOUNCE_MS`]); a request on an
//! edited document analyses its current text at once. Inlay hints show a running controller's
//! power flow when `initializationOptions.hmi` names its HMI ([`crate::flow`]), and the client is
//! asked every [`FLOW_REFRESH`] to fetch them again when it can be. A request the server cannot
//! decode gets an `InvalidParams` error and the server goes on; nothing a client sends ends the
//! loop but `exit`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crossbeam_channel::RecvTimeoutError;
use lsp_server::{Connection, ErrorCode, Message, Notification, Request, Response};
use lsp_types::notification::{self as n, Notification as _};
use lsp_types::request::{self as r, Request as _};
use lsp_types::{
    CompletionOptions, DocumentHighlight, DocumentHighlightKind, DocumentSymbol, Hover,
    HoverContents, HoverProviderCapability, InitializeParams, Location, MarkupContent, MarkupKind,
    MessageType, OneOf, PrepareRenameResponse, PublishDiagnosticsParams, RenameOptions,
    SemanticTokens, SemanticTokensFullOptions, SemanticTokensOptions, SemanticTokensResult,
    SemanticTokensServerCapabilities, ServerCapabilities, ShowMessageParams, SymbolInformation,
    SymbolKind, TextDocumentSyncCapability, TextDocumentSyncKind, TextEdit, Uri, WorkspaceEdit,
};

use crate::analysis::Document;
use crate::index::Index;
use crate::machine::Machine;
use crate::navigate::{self, Target};
use crate::text::Text;
use crate::{complete, flow, format, hover, tokens, uri};

/// Default debounce of diagnostics after an edit, in milliseconds.
pub const DEBOUNCE_MS: u64 = 150;

/// How often the client is asked to fetch the inlay hints again while a power flow is read.
pub const FLOW_REFRESH: Duration = Duration::from_secs(1);

/// Why the server stopped abnormally.
#[derive(Debug, thiserror::Error)]
pub enum ServerError {
    /// The client broke the protocol (e.g. no `initialize` first).
    #[error("protocol: {0}")]
    Protocol(#[from] lsp_server::ProtocolError),
    /// A message could not be encoded.
    #[error("json: {0}")]
    Json(#[from] serde_json::Error),
    /// The connection is gone.
    #[error("the client connection closed")]
    Closed,
    /// The I/O threads failed.
    #[error("i/o: {0}")]
    Io(#[from] std::io::Error),
}

/// `ncplc lsp`: serves one client over stdin/stdout until `exit`.
pub fn serve_stdio() -> Result<(), ServerError> {
    let (conn, io) = Connection::stdio();
    let r = serve(&conn);
    // The writer thread ends only when every sender is gone.
    drop(conn);
    io.join()?;
    r
}

/// The capabilities the server announces.
pub fn capabilities() -> ServerCapabilities {
    ServerCapabilities {
        text_document_sync: Some(TextDocumentSyncCapability::Kind(
            TextDocumentSyncKind::INCREMENTAL,
        )),
        hover_provider: Some(HoverProviderCapability::Simple(true)),
        definition_provider: Some(OneOf::Left(true)),
        references_provider: Some(OneOf::Left(true)),
        document_highlight_provider: Some(OneOf::Left(true)),
        document_symbol_provider: Some(OneOf::Left(true)),
        workspace_symbol_provider: Some(OneOf::Left(true)),
        completion_provider: Some(CompletionOptions::default()),
        rename_provider: Some(OneOf::Right(RenameOptions {
            prepare_provider: Some(true),
            work_done_progress_options: Default::default(),
        })),
        document_formatting_provider: Some(OneOf::Left(true)),
        inlay_hint_provider: Some(OneOf::Left(true)),
        semantic_tokens_provider: Some(SemanticTokensServerCapabilities::SemanticTokensOptions(
            SemanticTokensOptions {
                legend: tokens::legend(),
                full: Some(SemanticTokensFullOptions::Bool(true)),
                range: None,
                work_done_progress_options: Default::default(),
            },
        )),
        ..ServerCapabilities::default()
    }
}

/// Runs the handshake and the loop on `conn` until `shutdown`/`exit` or a closed connection.
pub fn serve(conn: &Connection) -> Result<(), ServerError> {
    let params = conn.initialize(serde_json::to_value(capabilities())?)?;
    let init: InitializeParams = serde_json::from_value(params).unwrap_or_default();
    let debounce = init
        .initialization_options
        .as_ref()
        .and_then(|o| o.get("debounceMs")?.as_u64())
        .unwrap_or(DEBOUNCE_MS);
    // The power flow's source: a running `ncplc run --hmi … --hmi-flow` (its start URL).
    let hmi = init
        .initialization_options
        .as_ref()
        .and_then(|o| o.get("hmi"))
        .map(|v| match v.as_str() {
            Some(url) => flow::Hmi::from_url(url),
            None => Err(flow::FlowError::Url(v.to_string())),
        });
    // Live power flow: the client re-asks for inlay hints when told to, if it can be told.
    let refresh = matches!(hmi, Some(Ok(_)))
        && init
            .capabilities
            .workspace
            .as_ref()
            .and_then(|w| w.inlay_hint.as_ref()?.refresh_support)
            .unwrap_or(false);
    let mut s = Server {
        conn,
        docs: HashMap::new(),
        pending: HashMap::new(),
        machines: HashMap::new(),
        debounce: Duration::from_millis(debounce),
        told: false,
        hmi,
        refresh: refresh.then(Instant::now),
        refreshes: 0,
    };
    s.run()
}

struct Server<'c> {
    conn: &'c Connection,
    docs: HashMap<Uri, Document>,
    /// Documents whose diagnostics are due at the instant.
    pending: HashMap<Uri, Instant>,
    /// Machines of the documents opened, by directory (for workspace symbols).
    machines: HashMap<PathBuf, Arc<Machine>>,
    debounce: Duration,
    /// The "no machine context" note was shown.
    told: bool,
    /// Where inlay hints read the power flow (`initializationOptions.hmi`), if anywhere.
    hmi: Option<Result<flow::Hmi, flow::FlowError>>,
    /// When the client is next asked to refresh its inlay hints (power flow read, client able).
    refresh: Option<Instant>,
    /// Refresh requests sent (their ids).
    refreshes: u64,
}

/// A request's failure: code and message.
type Failure = (ErrorCode, String);

impl Server<'_> {
    fn run(&mut self) -> Result<(), ServerError> {
        loop {
            self.refresh_due()?;
            let refresh = self.refresh.filter(|_| !self.docs.is_empty());
            let next = self
                .pending
                .values()
                .min()
                .copied()
                .into_iter()
                .chain(refresh)
                .min();
            let msg = match next {
                Some(when) => {
                    let wait = when.saturating_duration_since(Instant::now());
                    match self.conn.receiver.recv_timeout(wait) {
                        Ok(m) => m,
                        Err(RecvTimeoutError::Timeout) => {
                            self.publish_due()?;
                            continue;
                        }
                        Err(RecvTimeoutError::Disconnected) => return Ok(()),
                    }
                }
                None => match self.conn.receiver.recv() {
                    Ok(m) => m,
                    Err(_) => return Ok(()),
                },
            };
            match msg {
                Message::Request(req) => {
                    if self.conn.handle_shutdown(&req)? {
                        return Ok(());
                    }
                    let id = req.id.clone();
                    let resp = match self.request(req) {
                        Ok(v) => Response::new_ok(id, v),
                        Err((code, m)) => Response::new_err(id, code as i32, m),
                    };
                    self.send(Message::Response(resp))?;
                }
                Message::Notification(note) => self.notification(note)?,
                Message::Response(_) => {}
            }
        }
    }

    fn send(&self, m: Message) -> Result<(), ServerError> {
        self.conn.sender.send(m).map_err(|_| ServerError::Closed)
    }

    fn notify<N: n::Notification>(&self, params: N::Params) -> Result<(), ServerError> {
        self.send(Message::Notification(Notification::new(
            N::METHOD.to_string(),
            params,
        )))
    }

    /// Asks the client to fetch the inlay hints (the power flow) again when it is time.
    fn refresh_due(&mut self) -> Result<(), ServerError> {
        let now = Instant::now();
        if self.docs.is_empty() || self.refresh.is_none_or(|at| at > now) {
            return Ok(());
        }
        self.refresh = Some(now + FLOW_REFRESH);
        self.refreshes += 1;
        self.send(Message::Request(Request::new(
            format!("flow-refresh-{}", self.refreshes).into(),
            r::InlayHintRefreshRequest::METHOD.to_string(),
            serde_json::Value::Null,
        )))
    }

    fn publish_due(&mut self) -> Result<(), ServerError> {
        let now = Instant::now();
        let due: Vec<Uri> = self
            .pending
            .iter()
            .filter(|(_, w)| **w <= now)
            .map(|(u, _)| u.clone())
            .collect();
        for u in due {
            self.pending.remove(&u);
            self.publish(&u)?;
        }
        Ok(())
    }

    fn publish(&mut self, u: &Uri) -> Result<(), ServerError> {
        let Some(doc) = self.docs.get_mut(u) else {
            return Ok(());
        };
        let diagnostics = doc.lsp_diagnostics();
        let version = Some(doc.version);
        self.notify::<n::PublishDiagnostics>(PublishDiagnosticsParams {
            uri: u.clone(),
            diagnostics,
            version,
        })
    }

    fn machine_for(&mut self, path: Option<&Path>) -> Arc<Machine> {
        let m = Arc::new(match path {
            Some(p) => Machine::for_file(p),
            None => Machine {
                note: Some(
                    "this document is not a file: checking the language rules only".to_string(),
                ),
                ..Machine::for_file(Path::new("/"))
            },
        });
        if let Some(d) = &m.dir {
            self.machines.insert(d.clone(), m.clone());
        }
        m
    }

    fn notification(&mut self, note: Notification) -> Result<(), ServerError> {
        match note.method.as_str() {
            n::DidOpenTextDocument::METHOD => {
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidOpenTextDocumentParams>(note.params)
                else {
                    return Ok(());
                };
                let u = p.text_document.uri;
                let path = uri::to_path(&u);
                let machine = self.machine_for(path.as_deref());
                if let Some(why) = machine.note.clone().filter(|_| !self.told) {
                    self.told = true;
                    self.notify::<n::ShowMessage>(ShowMessageParams {
                        typ: MessageType::INFO,
                        message: format!("ncplc: {why}"),
                    })?;
                }
                let name = path.map_or_else(|| u.as_str().to_string(), |p| p.display().to_string());
                let doc =
                    Document::new(name, p.text_document.text, p.text_document.version, machine);
                self.docs.insert(u.clone(), doc);
                self.pending.remove(&u);
                self.publish(&u)?;
            }
            n::DidChangeTextDocument::METHOD => {
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidChangeTextDocumentParams>(note.params)
                else {
                    return Ok(());
                };
                let u = p.text_document.uri;
                if let Some(doc) = self.docs.get_mut(&u) {
                    doc.edit(p.text_document.version, &p.content_changes);
                    if self.debounce.is_zero() {
                        self.publish(&u)?;
                    } else {
                        self.pending.insert(u, Instant::now() + self.debounce);
                    }
                }
            }
            n::DidCloseTextDocument::METHOD => {
                let Ok(p) =
                    serde_json::from_value::<lsp_types::DidCloseTextDocumentParams>(note.params)
                else {
                    return Ok(());
                };
                let u = p.text_document.uri;
                self.docs.remove(&u);
                self.pending.remove(&u);
                self.notify::<n::PublishDiagnostics>(PublishDiagnosticsParams {
                    uri: u,
                    diagnostics: Vec::new(),
                    version: None,
                })?;
            }
            _ => {}
        }
        Ok(())
    }

    fn doc(&mut self, u: &Uri) -> Result<&mut Document, Failure> {
        self.docs.get_mut(u).ok_or_else(|| {
            (
                ErrorCode::InvalidParams,
                format!("{} is not open", u.as_str()),
            )
        })
    }

    fn request(&mut self, req: Request) -> Result<serde_json::Value, Failure> {
        fn params<P: serde::de::DeserializeOwned>(v: serde_json::Value) -> Result<P, Failure> {
            serde_json::from_value(v).map_err(|e| (ErrorCode::InvalidParams, e.to_string()))
        }
        fn json(v: impl serde::Serialize) -> Result<serde_json::Value, Failure> {
            serde_json::to_value(v).map_err(|e| (ErrorCode::InternalError, e.to_string()))
        }
        match req.method.as_str() {
            r::HoverRequest::METHOD => {
                let p: lsp_types::HoverParams = params(req.params)?;
                let pp = p.text_document_position_params;
                let doc = self.doc(&pp.text_document.uri)?;
                let offset = doc.text.offset(pp.position);
                let (a, text, machine) = doc.parts();
                json(
                    hover::hover(a, machine, text, offset).map(|(md, span)| Hover {
                        contents: HoverContents::Markup(MarkupContent {
                            kind: MarkupKind::Markdown,
                            value: md,
                        }),
                        range: Some(text.range(span)),
                    }),
                )
            }
            r::GotoDefinition::METHOD => {
                let p: lsp_types::GotoDefinitionParams = params(req.params)?;
                let pp = p.text_document_position_params;
                let u = pp.text_document.uri;
                let doc = self.doc(&u)?;
                let offset = doc.text.offset(pp.position);
                let machine = doc.machine.clone();
                let target = navigate::definition(doc.analysis(), &machine, offset);
                let loc = match target {
                    Some(Target::Here(span)) => {
                        Some(Location::new(u.clone(), doc.text.range(span)))
                    }
                    Some(Target::File(f, span)) => std::fs::read_to_string(&f).ok().and_then(|t| {
                        let t = Text::new(t);
                        Some(Location::new(uri::from_path(Path::new(&f))?, t.range(span)))
                    }),
                    None => None,
                };
                json(loc)
            }
            r::References::METHOD => {
                let p: lsp_types::ReferenceParams = params(req.params)?;
                let pp = p.text_document_position;
                let u = pp.text_document.uri;
                let doc = self.doc(&u)?;
                let offset = doc.text.offset(pp.position);
                let refs =
                    navigate::references(doc.analysis(), offset, p.context.include_declaration);
                let locs: Vec<Location> = refs
                    .into_iter()
                    .map(|(s, _)| Location::new(u.clone(), doc.text.range(s)))
                    .collect();
                json(locs)
            }
            r::DocumentHighlightRequest::METHOD => {
                let p: lsp_types::DocumentHighlightParams = params(req.params)?;
                let pp = p.text_document_position_params;
                let doc = self.doc(&pp.text_document.uri)?;
                let offset = doc.text.offset(pp.position);
                let refs = navigate::references(doc.analysis(), offset, true);
                let hl: Vec<DocumentHighlight> = refs
                    .into_iter()
                    .map(|(s, usage)| DocumentHighlight {
                        range: doc.text.range(s),
                        kind: Some(match usage {
                            crate::index::Use::Write | crate::index::Use::Decl => {
                                DocumentHighlightKind::WRITE
                            }
                            crate::index::Use::Read => DocumentHighlightKind::READ,
                        }),
                    })
                    .collect();
                json(hl)
            }
            r::Completion::METHOD => {
                let p: lsp_types::CompletionParams = params(req.params)?;
                let pp = p.text_document_position;
                let doc = self.doc(&pp.text_document.uri)?;
                let offset = doc.text.offset(pp.position);
                let (a, text, machine) = doc.parts();
                json(lsp_types::CompletionResponse::Array(complete::complete(
                    a, machine, text, offset,
                )))
            }
            r::PrepareRenameRequest::METHOD => {
                let p: lsp_types::TextDocumentPositionParams = params(req.params)?;
                let doc = self.doc(&p.text_document.uri)?;
                let offset = doc.text.offset(p.position);
                let (a, text, machine) = doc.parts();
                let (_, r) = navigate::prepare_rename(a, machine, offset)
                    .map_err(|e| (ErrorCode::RequestFailed, e.to_string()))?;
                json(PrepareRenameResponse::Range(text.range(a.to_doc(&r.span))))
            }
            r::Rename::METHOD => {
                let p: lsp_types::RenameParams = params(req.params)?;
                let pp = p.text_document_position;
                let u = pp.text_document.uri;
                let doc = self.doc(&u)?;
                let offset = doc.text.offset(pp.position);
                let machine = doc.machine.clone();
                let spans = navigate::rename(doc.analysis(), &machine, offset, &p.new_name)
                    .map_err(|e| (ErrorCode::RequestFailed, e.to_string()))?;
                let edits: Vec<TextEdit> = spans
                    .into_iter()
                    .map(|s| TextEdit::new(doc.text.range(s), p.new_name.clone()))
                    .collect();
                json(WorkspaceEdit {
                    changes: Some(HashMap::from([(u, edits)])),
                    ..WorkspaceEdit::default()
                })
            }
            r::InlayHintRequest::METHOD => {
                let p: lsp_types::InlayHintParams = params(req.params)?;
                let Some(hmi) = &self.hmi else {
                    return json(Vec::<lsp_types::InlayHint>::new());
                };
                let failed = |e: &flow::FlowError| (ErrorCode::RequestFailed, e.to_string());
                let running = hmi
                    .as_ref()
                    .map_err(failed)?
                    .read()
                    .map_err(|e| failed(&e))?;
                let doc = self.doc(&p.text_document.uri)?;
                json(flow::hints(
                    &doc.text,
                    &running.source,
                    &running.flow,
                    p.range.start.line,
                    p.range.end.line,
                ))
            }
            r::Formatting::METHOD => {
                let p: lsp_types::DocumentFormattingParams = params(req.params)?;
                let doc = self.doc(&p.text_document.uri)?;
                let src = doc.text.as_str();
                let f = format::format(src);
                let edits = if f == src {
                    Vec::new()
                } else {
                    vec![TextEdit::new(doc.text.range(0..src.len()), f)]
                };
                json(edits)
            }
            r::DocumentSymbolRequest::METHOD => {
                let p: lsp_types::DocumentSymbolParams = params(req.params)?;
                let doc = self.doc(&p.text_document.uri)?;
                let len = doc.text.as_str().len();
                let syms = navigate::document_symbols(doc.analysis(), len);
                let text = &doc.text;
                #[allow(deprecated)]
                fn conv(s: navigate::Symbol, text: &Text) -> DocumentSymbol {
                    DocumentSymbol {
                        name: s.name,
                        detail: Some(s.detail),
                        kind: if s.section {
                            SymbolKind::NAMESPACE
                        } else if s.block {
                            SymbolKind::EVENT
                        } else {
                            SymbolKind::VARIABLE
                        },
                        tags: None,
                        deprecated: None,
                        range: text.range(s.span.clone()),
                        selection_range: text.range(s.name_span.clone()),
                        children: Some(s.children.into_iter().map(|c| conv(c, text)).collect()),
                    }
                }
                let out: Vec<DocumentSymbol> = syms.into_iter().map(|s| conv(s, text)).collect();
                json(lsp_types::DocumentSymbolResponse::Nested(out))
            }
            r::WorkspaceSymbolRequest::METHOD => {
                let p: lsp_types::WorkspaceSymbolParams = params(req.params)?;
                json(self.workspace_symbols(&p.query))
            }
            r::SemanticTokensFullRequest::METHOD => {
                let p: lsp_types::SemanticTokensParams = params(req.params)?;
                let doc = self.doc(&p.text_document.uri)?;
                json(SemanticTokensResult::Tokens(SemanticTokens {
                    result_id: None,
                    data: tokens::semantic_tokens(&doc.text),
                }))
            }
            other => Err((
                ErrorCode::MethodNotFound,
                format!("{other} is not supported"),
            )),
        }
    }

    /// The `DEF`s matching `query` (case-insensitive substring) in the open documents and in the
    /// PLC source of every machine seen (read from disk when it is not open).
    #[allow(deprecated)]
    fn workspace_symbols(&mut self, query: &str) -> Vec<SymbolInformation> {
        let q = query.to_ascii_uppercase();
        let mut out = Vec::new();
        let mut seen: Vec<PathBuf> = Vec::new();
        let mut add = |u: &Uri, text: &Text, index: &Index, base: usize| {
            for d in index.defs.iter().filter(|d| d.name.contains(&q)) {
                out.push(SymbolInformation {
                    name: d.name.clone(),
                    kind: SymbolKind::VARIABLE,
                    tags: None,
                    deprecated: None,
                    location: Location::new(
                        u.clone(),
                        text.range(d.name_span.start + base..d.name_span.end + base),
                    ),
                    container_name: Some(navigate::def_detail(d)),
                });
            }
        };
        for (u, doc) in &mut self.docs {
            if let Some(p) = uri::to_path(u) {
                seen.push(p);
            }
            let (a, text, _) = doc.parts();
            add(u, text, &a.index, a.base);
        }
        for m in self.machines.values() {
            let Some(src) = &m.plc_source else { continue };
            if seen.iter().any(|s| s == src) {
                continue;
            }
            let (Ok(bytes), Some(u)) = (compiler::read_source(src), uri::from_path(src)) else {
                continue;
            };
            if bytes.len() > compiler::MAX_SOURCE_BYTES {
                // Refused by the compiler (1012): nothing to index.
                continue;
            }
            let t = compiler::lexer::decode_source(&bytes);
            let (ast, _) = compiler::parser::parse(&src.display().to_string(), &t);
            let index = Index::new(&ast, &m.ctx);
            add(&u, &Text::new(t), &index, 0);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lsp_server::RequestId;
    use serde_json::{Value, json};

    fn request(c: &Connection, id: i32, method: &str, params: Value) -> Response {
        c.sender
            .send(Message::Request(Request::new(
                RequestId::from(id),
                method.into(),
                params,
            )))
            .expect("send");
        loop {
            match c
                .receiver
                .recv_timeout(Duration::from_secs(30))
                .expect("a reply")
            {
                Message::Response(r) if r.id == RequestId::from(id) => return r,
                _ => {}
            }
        }
    }

    fn note(c: &Connection, method: &str, params: Value) {
        c.sender
            .send(Message::Notification(Notification::new(
                method.into(),
                params,
            )))
            .expect("send");
    }

    fn next_note(c: &Connection) -> Notification {
        loop {
            if let Message::Notification(n) = c
                .receiver
                .recv_timeout(Duration::from_secs(30))
                .expect("a notification")
            {
                return n;
            }
        }
    }

    #[test]
    fn in_memory_session_debounces_and_survives_bad_requests() {
        let (server, client) = Connection::memory();
        let t = std::thread::spawn(move || serve(&server));
        let r = request(
            &client,
            1,
            "initialize",
            json!({"capabilities": {}, "initializationOptions": {"debounceMs": 40}}),
        );
        assert_eq!(
            r.response_result.expect("capabilities")["capabilities"]["renameProvider"]["prepareProvider"],
            json!(true)
        );
        note(&client, "initialized", json!({}));
        let u = "file:///nonexistent-machine/x.plc";
        note(
            &client,
            "textDocument/didOpen",
            json!({"textDocument": {"uri": u, "languageId": "ncplc-plc", "version": 1, "text": "U4A0 = I4A0\n"}}),
        );
        let told = next_note(&client);
        assert_eq!(told.method, "window/showMessage");
        let d = next_note(&client);
        assert_eq!(d.method, "textDocument/publishDiagnostics");
        assert_eq!(d.params["diagnostics"][0]["code"], 1105);
        assert_eq!(d.params["version"], 1);
        // Two edits in a row: one publication, of the last version, after the debounce.
        for (v, text) in [(2, "I0A0"), (3, "I0A1")] {
            note(
                &client,
                "textDocument/didChange",
                json!({"textDocument": {"uri": u, "version": v}, "contentChanges": [
                    {"range": {"start": {"line": 0, "character": 7}, "end": {"line": 0, "character": 11}}, "text": text}]}),
            );
        }
        let d = next_note(&client);
        assert_eq!(d.params["version"], 3);
        assert_eq!(d.params["diagnostics"], json!([]));
        // Bad params and an unknown method are errors; the server goes on.
        let r = request(&client, 2, "textDocument/hover", json!({"nonsense": 1}));
        assert_eq!(
            r.response_result.err().map(|e| e.code),
            Some(ErrorCode::InvalidParams as i32)
        );
        let r = request(&client, 3, "textDocument/nothing", json!({}));
        assert_eq!(
            r.response_result.err().map(|e| e.code),
            Some(ErrorCode::MethodNotFound as i32)
        );
        let r = request(
            &client,
            4,
            "textDocument/hover",
            json!({"textDocument": {"uri": u}, "position": {"line": 0, "character": 9}}),
        );
        let v = r.response_result.expect("a hover");
        assert_eq!(
            v["contents"]["value"],
            "**I0A1**\n\nPacket A, connector 0, bit 1; width bit\n\nWho writes it: written by the I/O (a physical input), read by the PLC. This program does not write it."
        );
        let r = request(&client, 5, "shutdown", Value::Null);
        assert!(r.response_result.is_ok());
        note(&client, "exit", Value::Null);
        assert!(t.join().expect("the server thread").is_ok());
    }
}
