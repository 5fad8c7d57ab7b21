//! Starting the HMI: bind (refusing a non-loopback bind without a token), build the router, serve
//! on a thread of its own with a small tokio runtime.

use std::net::SocketAddr;
use std::sync::{Arc, mpsc};

use axum::Router;
use axum::routing::{delete, get, post};
use tokio::sync::watch;

use crate::demand::Demand;
use crate::model::{Catalog, Envelope, SharedSnapshot};
use crate::{api, assets, auth, ws};

/// How the HMI is served.
#[derive(Debug, Clone)]
pub struct ServerConfig {
    /// Where to listen.
    pub addr: SocketAddr,
    /// The access token; required (`Some`) for a non-loopback address.
    pub token: Option<String>,
    /// Refuse writes, forces and commands.
    pub readonly: bool,
}

/// Why the HMI could not start.
#[derive(Debug, thiserror::Error)]
pub enum StartError {
    /// A non-loopback bind without a token.
    #[error(
        "--hmi {0}: not a loopback address, so the HMI needs an access token (--hmi-token-file FILE, or let ncplc generate one with --hmi-token)"
    )]
    NeedsToken(SocketAddr),
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
            auth::require_token,
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
    if !auth::is_loopback(&config.addr) && config.token.is_none() {
        return Err(StartError::NeedsToken(config.addr));
    }
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
    let state = AppState {
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
                if let Err(e) = axum::serve(listener, router(state)).await {
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
