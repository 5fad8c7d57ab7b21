//! `GET /ws`: the live image. Each new snapshot is sent as one JSON text frame; the channel keeps
//! only the latest, so a slow client skips snapshots and never holds up the scan.

use axum::extract::State;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::response::Response;

use crate::server::AppState;

/// Upgrades the connection and streams snapshots until the client goes away.
pub async fn upgrade(ws: WebSocketUpgrade, State(state): State<AppState>) -> Response {
    ws.on_upgrade(move |socket| stream(socket, state))
}

async fn stream(mut socket: WebSocket, state: AppState) {
    // The render thread renders while a client is connected.
    let _client = state.demand.connect();
    let mut rx = state.snapshots.clone();
    // The current value first, then every change.
    rx.mark_changed();
    while rx.changed().await.is_ok() {
        let snap = rx.borrow_and_update().clone();
        let Ok(text) = serde_json::to_string(&*snap) else {
            break;
        };
        if socket.send(Message::Text(text.into())).await.is_err() {
            break;
        }
    }
}
