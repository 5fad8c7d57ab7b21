//! Resource limits of the web HMI: request body size, WebSocket message size and rate, the
//! number of concurrent connections and how long a silent connection stays open.
//!
//! Each limit refuses with a clear error: a body over the limit is `413` with a JSON error; a
//! WebSocket message over the size is closed with code 1009, one over the rate with 1008, each
//! with the limit in the close reason; a connection over the client limit gets `503` with a JSON
//! error (plain HTTP) or is closed (TLS).

use std::time::{Duration, Instant};

use axum::body::{Body, Bytes};
use axum::extract::Request;
use axum::http::{StatusCode, header};

use http_body_util::LengthLimitError;

use crate::error::ApiError;

/// The limits, with the defaults documented in `API.md`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Largest request body in bytes (`--hmi-max-body`).
    pub max_body: usize,
    /// Most open connections at once (`--hmi-max-clients`).
    pub max_clients: usize,
    /// Largest WebSocket message from a client in bytes (`--hmi-ws-max-message`).
    pub ws_max_message: usize,
    /// Most WebSocket messages per second from one client (`--hmi-ws-rate`).
    pub ws_rate: u32,
    /// A connection with no byte in either direction for this long is closed.
    pub idle: Duration,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_body: 16 * 1024,
            max_clients: 32,
            ws_max_message: 1024,
            ws_rate: 100,
            idle: Duration::from_secs(60),
        }
    }
}

/// Reads a request's body whole when it is within `max` bytes; a larger one is a `413`.
pub async fn buffered(req: Request, max: usize) -> Result<Request, ApiError> {
    let too_large = || ApiError {
        status: StatusCode::PAYLOAD_TOO_LARGE,
        message: format!("the request body is larger than {max} bytes (--hmi-max-body)"),
    };
    if let Some(n) = req
        .headers()
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.parse::<u64>().ok())
        && n > max as u64
    {
        return Err(too_large());
    }
    let (parts, body) = req.into_parts();
    let bytes: Bytes = axum::body::to_bytes(body, max).await.map_err(|e| {
        if std::error::Error::source(&e).is_some_and(|s| s.is::<LengthLimitError>()) {
            too_large()
        } else {
            ApiError::bad_request(format!("request body: {e}"))
        }
    })?;
    Ok(Request::from_parts(parts, Body::from(bytes)))
}

/// Counts a client's messages in one-second windows.
#[derive(Debug)]
pub struct Rate {
    limit: u32,
    window: Instant,
    count: u32,
}

impl Rate {
    /// A counter allowing `limit` messages per second.
    pub fn new(limit: u32, now: Instant) -> Rate {
        Rate {
            limit,
            window: now,
            count: 0,
        }
    }

    /// Counts one message at `now`; false when it is over the limit of its window.
    pub fn hit(&mut self, now: Instant) -> bool {
        if now.duration_since(self.window) >= Duration::from_secs(1) {
            self.window = now;
            self.count = 0;
        }
        self.count += 1;
        self.count <= self.limit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rate_counts_per_second_window() {
        let t0 = Instant::now();
        let mut r = Rate::new(3, t0);
        assert!(r.hit(t0));
        assert!(r.hit(t0 + Duration::from_millis(10)));
        assert!(r.hit(t0 + Duration::from_millis(20)));
        assert!(!r.hit(t0 + Duration::from_millis(999)));
        assert!(r.hit(t0 + Duration::from_millis(1000)));
    }

    #[tokio::test]
    async fn a_body_over_the_limit_is_413_and_one_within_passes_whole() {
        let req = |body: &'static str, len: bool| {
            let mut b = Request::builder().method("POST").uri("/api/write");
            if len {
                b = b.header(header::CONTENT_LENGTH, body.len());
            }
            b.body(Body::from(body)).expect("request")
        };
        let e = buffered(req("0123456789", true), 8)
            .await
            .expect_err("too large");
        assert_eq!(e.status, StatusCode::PAYLOAD_TOO_LARGE);
        assert_eq!(
            e.message,
            "the request body is larger than 8 bytes (--hmi-max-body)"
        );
        // Without a length (chunked), the limit still holds while reading.
        let e = buffered(req("0123456789", false), 8)
            .await
            .expect_err("too large");
        assert_eq!(e.status, StatusCode::PAYLOAD_TOO_LARGE);
        let ok = buffered(req("01234567", false), 8).await.expect("within");
        let bytes = axum::body::to_bytes(ok.into_body(), 100)
            .await
            .expect("body");
        assert_eq!(&bytes[..], b"01234567");
    }
}
