//! Starting the HMI: bind, build the router behind the security checks (`security`), serve on a
//! thread of its own with a small tokio runtime, over TLS when given a certificate.

use std::net::SocketAddr;
use std::sync::{Arc, mpsc};

use axum::Router;
use axum::routing::{delete, get, post};
use tokio::sync::watch;

use crate::demand::Demand;
use crate::model::{Catalog, Envelope, SharedSnapshot};
use crate::security::limits::Limits;
use crate::security::listener::Gate;
use crate::security::tls::{self, TlsError, TlsFiles};
use crate::security::{Guard, Tokens, host, origin};
use crate::{api, assets, security, ws};

/// How the HMI is served.
#[derive(Debug, Clone)]
pub struct ServerConfig {
    /// Where to listen.
    pub addr: SocketAddr,
    /// The session tokens and their roles (at least one).
    pub tokens: Tokens,
    /// Everyone is a viewer: writes, forces, commands and the power-flow switch are refused.
    pub readonly: bool,
    /// More names the `Host` header may give (`--hmi-allow-host`).
    pub allow_hosts: Vec<String>,
    /// More origins a state-changing request or WebSocket may come from (`--hmi-allow-origin`).
    pub allow_origins: Vec<String>,
    /// Serve HTTPS with these PEM files.
    pub tls: Option<TlsFiles>,
    /// Resource limits.
    pub limits: Limits,
}

/// True when `addr` only accepts connections from this host.
pub fn is_loopback(addr: &SocketAddr) -> bool {
    addr.ip().is_loopback()
}

/// Why the HMI could not start.
#[derive(Debug, thiserror::Error)]
pub enum StartError {
    /// No token to check requests against.
    #[error("--hmi {0}: the HMI needs at least one access token")]
    NeedsToken(SocketAddr),
    /// An `--hmi-allow-origin` value that is not an origin.
    #[error("--hmi-allow-origin: {0}")]
    BadOrigin(String),
    /// The certificate or key could not be used.
    #[error(transparent)]
    Tls(#[from] TlsError),
    /// The address could not be bound.
    #[error("--hmi {addr}: {source}")]
    Bind {
        /// The address.
        addr: SocketAddr,
        /// The OS error.
        source: std::io::Error,
    },
    /// The server's runtime could not start.
    #[error("HMI runtime: {0}")]
    Runtime(std::io::Error),
}

/// The state every handler shares.
#[derive(Clone)]
pub struct AppState {
    /// Settings.
    pub config: Arc<ServerConfig>,
    /// Names and source.
    pub catalog: Arc<Catalog>,
    /// The latest snapshot.
    pub snapshots: watch::Receiver<SharedSnapshot>,
    /// Requests to the scan.
    pub requests: mpsc::Sender<Envelope>,
    /// Who is looking (wakes the render thread).
    pub demand: Arc<Demand>,
    /// The checks every request passes.
    pub guard: Arc<Guard>,
}

/// A running HMI server.
#[derive(Debug)]
pub struct Running {
    /// The bound address (the real port when 0 was asked for).
    pub addr: SocketAddr,
    _thread: std::thread::JoinHandle<()>,
}

/// The router with every page, API route and the WebSocket.
pub fn router(state: AppState) -> Router {
    Router::new()
        .route("/", get(assets::index))
        .route("/static/{*path}", get(assets::file))
        .route("/api/status", get(api::status))
        .route("/api/signals", get(api::signals))
        .route("/api/program", get(api::program))
        .route("/api/signal/{addr}", get(api::signal))
        .route("/api/write", post(api::write))
        .route(
            "/api/force",
            post(api::force).delete(api::unforce_all).get(api::forces),
        )
        .route("/api/force/{addr}", delete(api::unforce))
        .route("/api/command", post(api::command))
        .route("/api/toolpath/{process}", get(api::toolpath))
        .route("/api/flow", get(api::flow).post(api::set_flow))
        .route("/ws", get(ws::upgrade))
        .fallback(api::not_found)
        .layer(axum::middleware::from_fn_with_state(
            state.clone(),
            security::check,
        ))
        .with_state(state)
}

/// Binds `config.addr` and serves the HMI on a new thread.
pub fn start(
    config: ServerConfig,
    catalog: Catalog,
    snapshots: watch::Receiver<SharedSnapshot>,
    requests: mpsc::Sender<Envelope>,
    demand: Arc<Demand>,
) -> Result<Running, StartError> {
    if config.tokens.first().is_none() {
        return Err(StartError::NeedsToken(config.addr));
    }
    if let Some(bad) = config
        .allow_origins
        .iter()
        .find_map(|o| origin::OriginList::invalid(o))
    {
        return Err(StartError::BadOrigin(bad));
    }
    let acceptor = match &config.tls {
        Some(files) => Some(tls::acceptor(files)?),
        None => None,
    };
    let listener = std::net::TcpListener::bind(config.addr).map_err(|source| StartError::Bind {
        addr: config.addr,
        source,
    })?;
    let addr = listener.local_addr().map_err(StartError::Runtime)?;
    listener
        .set_nonblocking(true)
        .map_err(StartError::Runtime)?;
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .thread_name("hmi")
        .enable_all()
        .build()
        .map_err(StartError::Runtime)?;
    let guard = Guard {
        hosts: host::HostList::new(addr, acceptor.is_some(), &config.allow_hosts),
        origins: origin::OriginList::new(&config.allow_origins),
        tokens: config.tokens.clone(),
        readonly: config.readonly,
        tls: acceptor.is_some(),
        port: addr.port(),
        max_body: config.limits.max_body,
    };
    let limits = config.limits;
    let state = AppState {
        guard: Arc::new(guard),
        config: Arc::new(config),
        catalog: Arc::new(catalog),
        snapshots,
        requests,
        demand,
    };
    let thread = std::thread::Builder::new()
        .name("hmi".into())
        .spawn(move || {
            rt.block_on(async move {
                let listener = match tokio::net::TcpListener::from_std(listener) {
                    Ok(l) => l,
                    Err(e) => {
                        eprintln!("hmi: {e}");
                        return;
                    }
                };
                let gate = match Gate::start(listener, limits.max_clients, limits.idle, acceptor) {
                    Ok(g) => g,
                    Err(e) => {
                        eprintln!("hmi: {e}");
                        return;
                    }
                };
                if let Err(e) = axum::serve(gate, router(state)).await {
                    eprintln!("hmi: {e}");
                }
            });
        })
        .map_err(StartError::Runtime)?;
    Ok(Running {
        addr,
        _thread: thread,
    })
}
