//! `GET /ws`: the live image. Each snapshot is sent as one JSON text frame, always the latest:
//! the channel keeps only the newest, so the scan is never held up.
//!
//! A browser reads every frame into its own queue however slowly it handles them, so pushing each
//! new snapshot would let a slow page fall behind by seconds. With `?ack=1` (what the page uses)
//! the server sends the next frame only after the client's message acknowledging the last one (any
//! text): a slow client skips snapshots and is never more than one frame behind. Without it each
//! new snapshot is pushed as it comes (at most the publish rate), for clients that cannot answer.

use axum::extract::rejection::QueryRejection;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{Query, State};
use axum::response::{IntoResponse, Response};

use crate::error::ApiError;

use crate::server::AppState;

/// The query of `/ws` (the token, if any, is checked before).
#[derive(Debug, Default, serde::Deserialize)]
pub struct WsQuery {
    /// `1`: paced by the client's acknowledgements.
    #[serde(default)]
    pub ack: u8,
}

/// Upgrades the connection and streams snapshots until the client goes away; an `ack` other
/// than 0 or 1 is a `400`, not silently a pushed stream.
pub async fn upgrade(
    query: Result<Query<WsQuery>, QueryRejection>,
    ws: WebSocketUpgrade,
    State(state): State<AppState>,
) -> Response {
    let q = match query {
        Ok(Query(q)) => q,
        Err(e) => return ApiError::bad_request(format!("/ws: {e}")).into_response(),
    };
    if q.ack > 1 {
        return ApiError::bad_request(format!("ack={}: 1 paces frames, 0 pushes them", q.ack))
            .into_response();
    }
    ws.on_upgrade(move |socket| stream(socket, state, q.ack == 1))
}

/// What the client sent: an acknowledgement, nothing that matters, or the end.
enum Incoming {
    Ack,
    Other,
    Gone,
}

fn incoming(m: Option<Result<Message, axum::Error>>) -> Incoming {
    match m {
        Some(Ok(Message::Text(_) | Message::Binary(_))) => Incoming::Ack,
        Some(Ok(Message::Ping(_) | Message::Pong(_))) => Incoming::Other,
        Some(Ok(Message::Close(_)) | Err(_)) | None => Incoming::Gone,
    }
}

/// Waits for the client's acknowledgement; false when the client went away instead.
async fn acknowledged(socket: &mut WebSocket) -> bool {
    loop {
        match incoming(socket.recv().await) {
            Incoming::Ack => return true,
            Incoming::Other => {}
            Incoming::Gone => return false,
        }
    }
}

async fn stream(mut socket: WebSocket, state: AppState, paced: bool) {
    // The render thread renders while a client is connected.
    let _client = state.demand.connect();
    let mut rx = state.snapshots.clone();
    // The current value first, then every change.
    rx.mark_changed();
    loop {
        tokio::select! {
            changed = rx.changed() => if changed.is_err() { return },
            m = socket.recv() => match incoming(m) {
                Incoming::Gone => return,
                // An acknowledgement with no frame outstanding, or a ping: wait on.
                Incoming::Ack | Incoming::Other => continue,
            },
        }
        let snap = rx.borrow_and_update().clone();
        let Ok(text) = serde_json::to_string(&*snap) else {
            return;
        };
        if socket.send(Message::Text(text.into())).await.is_err() {
            return;
        }
        // Paced: no next frame before the client has taken this one.
        if paced && !acknowledged(&mut socket).await {
            return;
        }
    }
}
