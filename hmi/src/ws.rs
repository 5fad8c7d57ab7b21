//! `GET /ws`: the live image. Each snapshot is sent as one JSON text frame, always the latest:
//! the channel keeps only the newest, so the scan is never held up.
//!
//! A browser reads every frame into its own queue however slowly it handles them, so pushing each
//! new snapshot would let a slow page fall behind by seconds. With `?ack=1` (what the page uses)
//! the server sends the next frame only after the client's message acknowledging the last one (any
//! text): a slow client skips snapshots and is never more than one frame behind. Without it each
//! new snapshot is pushed as it comes (at most the publish rate), for clients that cannot answer.
//!
//! A client message over `--hmi-ws-max-message` bytes closes the connection with code 1009, more
//! than `--hmi-ws-rate` messages in a second with code 1008 (the reason names the limit).

use axum::extract::rejection::QueryRejection;
use std::time::Instant;

use axum::extract::ws::{CloseFrame, Message, WebSocket, WebSocketUpgrade, close_code};
use axum::extract::{Query, State};
use axum::response::{IntoResponse, Response};

use crate::error::ApiError;
use crate::security::limits::{Limits, Rate};
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
    let max = state.config.limits.ws_max_message;
    ws.max_message_size(max)
        .max_frame_size(max)
        .on_upgrade(move |socket| stream(socket, state, q.ack == 1))
}

/// What the client sent: an acknowledgement, nothing that matters, or the end.
enum Incoming {
    Ack,
    Other,
    Gone,
}

/// A client's messages: counted against the rate, an error (a message over the size limit) or a
/// message over the rate closes the connection with a close frame saying which limit.
struct Client {
    rate: Rate,
    limits: Limits,
}

impl Client {
    async fn incoming(
        &mut self,
        socket: &mut WebSocket,
        m: Option<Result<Message, axum::Error>>,
    ) -> Incoming {
        let m = match m {
            Some(Ok(Message::Close(_))) | None => return Incoming::Gone,
            Some(Err(_)) => {
                // tungstenite refuses a message or frame over the size limit with an error.
                close(
                    socket,
                    close_code::SIZE,
                    format!("message over {} bytes", self.limits.ws_max_message),
                )
                .await;
                return Incoming::Gone;
            }
            Some(Ok(m)) => m,
        };
        if !self.rate.hit(Instant::now()) {
            close(
                socket,
                close_code::POLICY,
                format!("more than {} messages per second", self.limits.ws_rate),
            )
            .await;
            return Incoming::Gone;
        }
        match m {
            Message::Text(_) | Message::Binary(_) => Incoming::Ack,
            _ => Incoming::Other,
        }
    }

    /// Waits for the client's acknowledgement; false when the client went away instead.
    async fn acknowledged(&mut self, socket: &mut WebSocket) -> bool {
        loop {
            let m = socket.recv().await;
            match self.incoming(socket, m).await {
                Incoming::Ack => return true,
                Incoming::Other => {}
                Incoming::Gone => return false,
            }
        }
    }
}

/// Sends a close frame (best effort: the client may be gone already).
async fn close(socket: &mut WebSocket, code: u16, reason: String) {
    let frame = CloseFrame {
        code,
        reason: reason.into(),
    };
    let _ = socket.send(Message::Close(Some(frame))).await;
}

async fn stream(mut socket: WebSocket, state: AppState, paced: bool) {
    // The render thread renders while a client is connected.
    let _client = state.demand.connect();
    let mut rx = state.snapshots.clone();
    let limits = state.config.limits;
    let mut client = Client {
        rate: Rate::new(limits.ws_rate, Instant::now()),
        limits,
    };
    // The current value first, then every change.
    rx.mark_changed();
    loop {
        tokio::select! {
            changed = rx.changed() => if changed.is_err() { return },
            m = socket.recv() => match client.incoming(&mut socket, m).await {
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
        if paced && !client.acknowledged(&mut socket).await {
            return;
        }
    }
}
