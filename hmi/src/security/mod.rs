//! What every request passes before a handler runs, in this order: the `Host` allow-list
//! ([`host`]), the `Origin` of a state-changing request or WebSocket upgrade ([`origin`]), the
//! session token ([`session`], [`tokens`]), the role the route needs ([`roles`]) and the body
//! limit ([`limits`]). The listener ([`listener`]) caps connections and speaks TLS ([`tls`]).
//!
//! Invariant: no handler runs for a request that fails a check; static assets (`/static/…`)
//! need no token but still a valid `Host`.

pub mod host;
pub mod limits;
pub mod listener;
pub mod origin;
pub mod roles;
pub mod session;
pub mod tls;
pub mod tokens;

use axum::extract::{Request, State};
use axum::http::{Method, StatusCode, header};
use axum::middleware::Next;
use axum::response::{Html, IntoResponse, Response};

use crate::error::ApiError;
use crate::server::AppState;
pub use roles::Role;
pub use tokens::Tokens;

/// The checks of one server, built once it is bound.
#[derive(Debug, Clone)]
pub struct Guard {
    /// The `Host` allow-list.
    pub hosts: host::HostList,
    /// The extra allowed origins.
    pub origins: origin::OriginList,
    /// The tokens and their roles.
    pub tokens: Tokens,
    /// Everyone is a viewer (`--hmi-readonly`).
    pub readonly: bool,
    /// The server speaks TLS.
    pub tls: bool,
    /// The bound port (names the cookie).
    pub port: u16,
    /// The largest request body.
    pub max_body: usize,
}

fn forbidden(message: String) -> Response {
    ApiError {
        status: StatusCode::FORBIDDEN,
        message,
    }
    .into_response()
}

/// Middleware: the checks of this module, then the handler.
pub async fn check(State(state): State<AppState>, mut req: Request, next: Next) -> Response {
    let g = &state.guard;
    let host = match req.headers().get(header::HOST).map(|v| v.to_str()) {
        Some(Ok(h)) => h.to_string(),
        _ => String::new(),
    };
    if !g.hosts.allows(&host) {
        return forbidden(format!(
            "Host `{host}` is not a name of this HMI (a page of another site may be trying to reach it); a name of the machine on your network is added with --hmi-allow-host"
        ));
    }
    let method = req.method().clone();
    let path = req.uri().path().to_string();
    if path.starts_with("/static/") {
        return next.run(req).await;
    }
    let safe = matches!(method, Method::GET | Method::HEAD | Method::OPTIONS);
    if !safe || req.headers().contains_key(header::UPGRADE) {
        match req.headers().get(header::ORIGIN).map(|v| v.to_str()) {
            None => {}
            Some(Ok(o)) if g.origins.allows(o, &host, g.tls) => {}
            Some(o) => {
                let o = o.unwrap_or("(not text)");
                let scheme = if g.tls { "https" } else { "http" };
                return forbidden(format!(
                    "Origin `{o}` is not this HMI's origin ({scheme}://{host}): requests that change the machine and WebSocket connections are taken only from the HMI's own page (or an origin given with --hmi-allow-origin)"
                ));
            }
        }
    }
    let presented = session::presented(req.headers(), req.uri(), g.port);
    let Some((via, role)) = presented
        .iter()
        .find_map(|p| g.tokens.role(p.token()).map(|r| (p, r)))
    else {
        return unauthorized(&method, &path, !presented.is_empty());
    };
    if let session::Presented::Query(t) = via
        && method == Method::GET
        && path == "/"
    {
        return session::start_redirect(t, g.port, g.tls);
    }
    let role = if g.readonly { Role::Viewer } else { role };
    let need = roles::required(&method, &path);
    if role < need {
        let what = roles::what(&method, &path);
        let why = if g.readonly {
            "the HMI is read-only (--hmi-readonly): writes, forces and commands are disabled"
                .to_string()
        } else {
            format!("this session's role is {role}")
        };
        return (
            StatusCode::FORBIDDEN,
            axum::Json(serde_json::json!({
                "error": format!("{what} need the role {need}; {why}"),
                "role": role,
                "needs": need,
            })),
        )
            .into_response();
    }
    req.extensions_mut().insert(role);
    if !safe {
        req = match limits::buffered(req, g.max_body).await {
            Ok(r) => r,
            Err(e) => return e.into_response(),
        };
    }
    next.run(req).await
}

/// `401`: JSON for the API, a short page for the HMI's own address.
fn unauthorized(method: &Method, path: &str, wrong: bool) -> Response {
    let msg = if wrong {
        "the token is not valid for this HMI"
    } else {
        "this HMI needs its access token: open the address printed at start (http://…/?token=…), or send an Authorization: Bearer header"
    };
    if method == Method::GET && path == "/" {
        let page =
            format!("<!doctype html><meta charset=utf-8><title>ncplc HMI</title><p>{msg}.</p>");
        return (StatusCode::UNAUTHORIZED, Html(page)).into_response();
    }
    ApiError {
        status: StatusCode::UNAUTHORIZED,
        message: msg.to_string(),
    }
    .into_response()
}
