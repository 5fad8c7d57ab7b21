//! The JSON API (documented in `hmi/API.md`): status, signals, writes, forces and commands.

use std::time::Duration;

use axum::body::Bytes;
use axum::extract::rejection::PathRejection;
use axum::extract::{Path, State};
use axum::response::{IntoResponse, Response};
use axum::{Extension, Json};
use packets::{Packet, Signal};
use serde::Deserialize;
use serde_json::{Value, json};

use crate::error::{ApiError, path_param};
use crate::model::{Command, Envelope, Request, SharedSnapshot};
use crate::security::Role;
use crate::server::AppState;

/// How long a handler waits for the scan to apply a request.
const REPLY_TIMEOUT: Duration = Duration::from_secs(3);

/// How long a read waits for a fresh snapshot when it found the render thread asleep.
const WAKE_TIMEOUT: Duration = Duration::from_millis(250);

/// The latest snapshot for a read. The render thread sleeps while nobody looks; a read that
/// finds it asleep wakes it and waits (at most [`WAKE_TIMEOUT`]) for the snapshot it renders.
pub async fn snapshot(state: &AppState) -> SharedSnapshot {
    let mut rx = state.snapshots.clone();
    let _ = rx.borrow_and_update();
    if state.demand.read() {
        let _ = tokio::time::timeout(WAKE_TIMEOUT, rx.changed()).await;
    }
    rx.borrow().clone()
}

/// `GET /api/status`: the latest snapshot without the raw image.
pub async fn status(State(state): State<AppState>, role: Option<Extension<Role>>) -> Response {
    let snap = snapshot(&state).await;
    let mut v = serde_json::to_value(&*snap).unwrap_or(Value::Null);
    if let Some(o) = v.as_object_mut() {
        o.remove("image");
        o.insert("readonly".into(), Value::Bool(state.config.readonly));
        if let Some(Extension(role)) = role {
            o.insert("role".into(), Value::String(role.name().into()));
        }
        o.insert(
            "machine_name".into(),
            Value::String(state.catalog.machine.clone()),
        );
    }
    Json(v).into_response()
}

/// `GET /api/signals`: interface-map names and program aliases.
pub async fn signals(State(state): State<AppState>) -> Response {
    Json(json!({ "names": state.catalog.names })).into_response()
}

/// `GET /api/program`: the PLC source with the signals each line reads and writes.
pub async fn program(State(state): State<AppState>) -> Response {
    let online = snapshot(&state).await.online.clone();
    Json(json!({
        "file": state.catalog.source_name,
        "lines": state.catalog.source,
        "online": online,
    }))
    .into_response()
}

/// `GET /api/flow`: the power flow of the last published scan, `[line, value]` per statement.
pub async fn flow(State(state): State<AppState>) -> Response {
    let snap = snapshot(&state).await;
    Json(json!({ "tick": snap.tick, "flow": snap.flow })).into_response()
}

/// The body of `POST /api/flow`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FlowBody {
    enabled: bool,
}

/// `POST /api/flow`: switch the scan's power flow on or off (role `integrator`: it changes the
/// scan's code). The scan switches once the variant is compiled, at a tick boundary.
pub async fn set_flow(
    State(state): State<AppState>,
    Extension(role): Extension<Role>,
    body: Bytes,
) -> Result<Response, ApiError> {
    let b: FlowBody = parse_json(&body)?;
    let tick = ask(&state, role, Request::Flow(b.enabled)).await?;
    Ok(Json(json!({"enabled": b.enabled, "tick": tick})).into_response())
}

/// `GET /api/signal/<ADDR>`: one signal's value and whether it is forced.
pub async fn signal(
    State(state): State<AppState>,
    addr: Result<Path<String>, PathRejection>,
) -> Result<Response, ApiError> {
    let addr = path_param(addr)?;
    let sig = resolve(&state, &addr)?;
    let snap = snapshot(&state).await;
    let forced = snap.forced.iter().any(|(s, _)| same_storage(s, &sig));
    Ok(Json(json!({
        "signal": sig.to_string(),
        "value": sig.read(&snap.image),
        "forced": forced,
        "tick": snap.tick,
    }))
    .into_response())
}

/// `GET /api/force`: the force table.
pub async fn forces(State(state): State<AppState>) -> Response {
    let snap = snapshot(&state).await;
    let list: Vec<Value> = snap
        .forced
        .iter()
        .map(|(s, v)| json!({"signal": s.to_string(), "value": v}))
        .collect();
    Json(json!({ "forced": list })).into_response()
}

/// The body of `POST /api/write` and `POST /api/force`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SetBody {
    signal: String,
    value: u64,
}

/// `POST /api/write`: write a value once, before the next scan.
pub async fn write(
    State(state): State<AppState>,
    Extension(role): Extension<Role>,
    body: Bytes,
) -> Result<Response, ApiError> {
    let (sig, value) = set_body(&state, &body)?;
    let tick = ask(&state, role, Request::Write(sig, value)).await?;
    Ok(Json(json!({"signal": sig.to_string(), "value": value, "tick": tick})).into_response())
}

/// `POST /api/force`: force a value before and after every scan until unforced.
pub async fn force(
    State(state): State<AppState>,
    Extension(role): Extension<Role>,
    body: Bytes,
) -> Result<Response, ApiError> {
    let (sig, value) = set_body(&state, &body)?;
    let tick = ask(&state, role, Request::Force(sig, value)).await?;
    Ok(
        Json(json!({"signal": sig.to_string(), "value": value, "forced": true, "tick": tick}))
            .into_response(),
    )
}

/// `DELETE /api/force/<ADDR>`: remove one force.
pub async fn unforce(
    State(state): State<AppState>,
    Extension(role): Extension<Role>,
    addr: Result<Path<String>, PathRejection>,
) -> Result<Response, ApiError> {
    let addr = path_param(addr)?;
    writable(&state)?;
    let sig = resolve(&state, &addr)?;
    let tick = ask(&state, role, Request::Unforce(sig)).await?;
    Ok(Json(json!({"signal": sig.to_string(), "forced": false, "tick": tick})).into_response())
}

/// `DELETE /api/force`: remove every force.
pub async fn unforce_all(
    State(state): State<AppState>,
    Extension(role): Extension<Role>,
) -> Result<Response, ApiError> {
    writable(&state)?;
    let tick = ask(&state, role, Request::UnforceAll).await?;
    Ok(Json(json!({"forced": [], "tick": tick})).into_response())
}

/// The body of `POST /api/command`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CommandBody {
    process: Option<u8>,
    command: String,
    mode: Option<String>,
    line: Option<String>,
}

/// `POST /api/command`: an operator command for a process.
pub async fn command(
    State(state): State<AppState>,
    Extension(role): Extension<Role>,
    body: Bytes,
) -> Result<Response, ApiError> {
    writable(&state)?;
    let b: CommandBody = parse_json(&body)?;
    let process = match b.process {
        Some(p) if !(1..=5).contains(&p) => {
            return Err(ApiError::bad_request(format!(
                "process {p} does not exist (processes are 1..5)"
            )));
        }
        Some(p) => p,
        // `ack` without a process acknowledges every alarm.
        None if b.command == "ack" => 0,
        None => {
            return Err(ApiError::bad_request(format!(
                "command \"{}\" needs \"process\"",
                b.command
            )));
        }
    };
    let extra = |field: &str, v: &Option<String>| -> Result<(), ApiError> {
        match v {
            Some(_) => Err(ApiError::bad_request(format!(
                "\"{field}\" does not belong to command \"{}\"",
                b.command
            ))),
            None => Ok(()),
        }
    };
    let command = match b.command.as_str() {
        "start" | "hold" | "reset" | "ack" => {
            extra("mode", &b.mode)?;
            extra("line", &b.line)?;
            match b.command.as_str() {
                "start" => Command::Start,
                "hold" => Command::Hold,
                "ack" => Command::Ack,
                _ => Command::Reset,
            }
        }
        "mode" => {
            extra("line", &b.line)?;
            let mode = b
                .mode
                .clone()
                .ok_or_else(|| ApiError::bad_request("command \"mode\" needs \"mode\""))?;
            Command::Mode { mode }
        }
        "mdi" => {
            extra("mode", &b.mode)?;
            let line = b
                .line
                .clone()
                .ok_or_else(|| ApiError::bad_request("command \"mdi\" needs \"line\""))?;
            Command::Mdi { line }
        }
        other => {
            return Err(ApiError::bad_request(format!(
                "unknown command \"{other}\" (expected start, hold, reset, mode, mdi, ack)"
            )));
        }
    };
    let tick = ask(
        &state,
        role,
        Request::Command {
            process,
            command: command.clone(),
        },
    )
    .await?;
    let process = (process > 0).then_some(process);
    Ok(Json(json!({"process": process, "command": command, "tick": tick})).into_response())
}

/// `GET /api/toolpath/<P>`: process P's programmed path and the set points sampled so far.
pub async fn toolpath(
    State(state): State<AppState>,
    process: Result<Path<String>, PathRejection>,
) -> Result<Response, ApiError> {
    let process = path_param(process)?;
    let snap = snapshot(&state).await;
    let found = process
        .parse::<u8>()
        .ok()
        .and_then(|n| snap.toolpaths.iter().find(|t| t.process == n));
    match found {
        Some(t) => Ok(Json(t).into_response()),
        None => Err(ApiError::not_found(format!(
            "process {process} has no tool path (no CNC kernel runs, or the process has no interpolated axes)"
        ))),
    }
}

/// Anything else: a JSON 404.
pub async fn not_found(uri: axum::http::Uri) -> ApiError {
    ApiError::not_found(format!("no such page or API route: {}", uri.path()))
}

fn writable(state: &AppState) -> Result<(), ApiError> {
    if state.config.readonly {
        Err(ApiError::readonly())
    } else {
        Ok(())
    }
}

fn parse_json<T: serde::de::DeserializeOwned>(body: &[u8]) -> Result<T, ApiError> {
    serde_json::from_slice(body).map_err(|e| ApiError::bad_request(format!("request body: {e}")))
}

fn set_body(state: &AppState, body: &[u8]) -> Result<(Signal, u8), ApiError> {
    writable(state)?;
    let b: SetBody = parse_json(body)?;
    let sig = resolve(state, &b.signal)?;
    if sig.packet() == Packet::T {
        return Err(ApiError::bad_request(format!(
            "{}: packet T holds the machine's constants (IOCFIL section 4); it is not written from the HMI",
            b.signal
        )));
    }
    let max = if sig.bit().is_some() { 1 } else { 255 };
    if b.value > max {
        return Err(ApiError::bad_request(format!(
            "{}: value {} is out of range (0..{max})",
            b.signal, b.value
        )));
    }
    Ok((sig, b.value as u8))
}

fn resolve(state: &AppState, text: &str) -> Result<Signal, ApiError> {
    state.catalog.resolve(text).ok_or_else(|| {
        ApiError::not_found(format!(
            "`{text}` is neither a signal address (I0A3, U4A0, W3K0) nor a name of this machine"
        ))
    })
}

/// Two addresses of the same storage (`I4A0` and `U4A0`).
pub fn same_storage(a: &Signal, b: &Signal) -> bool {
    a.image_byte() == b.image_byte() && a.bit() == b.bit()
}

async fn ask(state: &AppState, role: Role, request: Request) -> Result<u64, ApiError> {
    let (tx, rx) = tokio::sync::oneshot::channel();
    state
        .requests
        .send(Envelope {
            request,
            role,
            reply: tx,
        })
        .map_err(|_| ApiError::unavailable("the scan has stopped"))?;
    match tokio::time::timeout(REPLY_TIMEOUT, rx).await {
        Ok(Ok(Ok(tick))) => Ok(tick),
        Ok(Ok(Err(refusal))) => Err(ApiError::refused(refusal)),
        Ok(Err(_)) => Err(ApiError::unavailable("the scan has stopped")),
        Err(_) => Err(ApiError::unavailable(
            "the scan did not take the request within 3 s",
        )),
    }
}
