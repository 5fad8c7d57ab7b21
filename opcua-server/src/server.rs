//! Starts async-opcua beside the scan: binds the listener (so a busy port is a clear error at
//! start, and port 0 gets a real port), builds the address space, and runs the server and the
//! publisher on a thread of their own with a small tokio runtime. Dropping [`Running`] stops both.
//!
//! **Invariants:** the minimum publishing and sampling intervals are the logic tick (async-opcua's
//! defaults are 100 ms), the subscription poll a tenth of it ([`crate::limits::poll_ms`]); the scan never calls into this module
//! after [`start`] returned.

use std::net::SocketAddr;
use std::path::Path;
use std::sync::Arc;
use std::thread::JoinHandle;

use opcua::server::node_manager::memory::simple_node_manager_imports;
use opcua::server::{ServerBuilder, ServerHandle};
use opcua::types::{DateTime, NodeId};

use crate::handoff::ServerSide;
use crate::limits::Limits;
use crate::node_manager::{self, OwnManager};
use crate::publisher::{self, Nodes};
use crate::signals::SignalNode;
use crate::users::Users;
use crate::{auth, machine_tool, nodesets, space, values};

/// The server's own namespace: the signals and the machine tool instance.
pub const NCPLC_NS: &str = "urn:ncplc";
/// The name of the node manager of [`NCPLC_NS`].
const OWN: &str = "ncplc";

/// Why the server did not start.
#[derive(Debug, thiserror::Error)]
pub enum StartError {
    /// The address could not be bound.
    #[error("--opcua {addr}: cannot listen: {source}")]
    Bind {
        /// The address asked for.
        addr: SocketAddr,
        /// The OS's reason.
        source: std::io::Error,
    },
    /// async-opcua refused the configuration, or the server thread failed.
    #[error("opcua: {0}")]
    Server(String),
}

/// A running server.
pub struct Running {
    /// The address it listens on.
    pub addr: SocketAddr,
    handle: ServerHandle,
    thread: Option<JoinHandle<()>>,
}

impl Drop for Running {
    fn drop(&mut self) {
        self.handle.cancel();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// What [`start`] needs besides the hand-over.
pub struct Plan<'a> {
    /// Where to listen.
    pub addr: SocketAddr,
    /// The machine directory (its `opcua-pki/` holds the stack's certificates and trust lists).
    pub machine_dir: &'a Path,
    /// The signal table.
    pub table: Vec<SignalNode>,
    /// The logic tick.
    pub tick_ms: u32,
    /// Sessions, items and message sizes.
    pub limits: Limits,
    /// What the Machine Tools instance shows.
    pub model: machine_tool::Inputs,
    /// The users (empty: anonymous only, on loopback).
    pub users: Users,
    /// The PLC variables.
    pub vars: crate::variables::Layout,
}

/// Sets TCP_NODELAY on the listener; Linux gives it to every connection accepted from it (the
/// stack accepts them and sets no option). Without it Nagle's algorithm held a PublishResponse
/// back until the client's delayed ACK of the previous segment (`bench/nagle.py`; with asyncua
/// the tick-to-client p99 was 40–48 ms instead of 15).
fn no_delay(listener: &std::net::TcpListener) -> std::io::Result<()> {
    socket2::SockRef::from(listener).set_tcp_nodelay(true)
}

/// Binds, builds and starts the server on its own thread.
pub fn start(plan: Plan<'_>, side: ServerSide) -> Result<Running, StartError> {
    let listener = std::net::TcpListener::bind(plan.addr)
        .and_then(|l| l.set_nonblocking(true).map(|()| l))
        .and_then(|l| no_delay(&l).map(|()| l))
        .map_err(|source| StartError::Bind {
            addr: plan.addr,
            source,
        })?;
    let addr = listener.local_addr().map_err(|source| StartError::Bind {
        addr: plan.addr,
        source,
    })?;
    let tick_ms = plan.tick_ms.max(1);
    let loopback = crate::settings::is_loopback(addr.ip());
    let builder = auth::endpoints(ServerBuilder::new(), &plan.users.credentials(), loopback);
    let authenticator = Arc::new(auth::Auth::new(plan.users.clone(), loopback));
    let mut builder = builder
        .application_name("ncplc")
        .application_uri("urn:ncplc:server")
        .with_authenticator(authenticator.clone())
        .product_uri("urn:ncplc")
        .host(addr.ip().to_string())
        .port(addr.port())
        .pki_dir(plan.machine_dir.join("opcua-pki"))
        .subscription_poll_interval_ms(crate::limits::poll_ms(tick_ms))
        .with_node_manager(simple_node_manager_imports(
            nodesets::imports().map_err(StartError::Server)?,
            "machine-tool-types",
        ))
        .with_node_manager(node_manager::builder(
            NCPLC_NS,
            OWN,
            authenticator,
            side.writes.clone(),
            side.commands.clone(),
        ));
    plan.limits.apply(&mut builder, tick_ms);
    // The stack spawns its tasks while it is built: inside the runtime that will run it.
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .thread_name("opcua-worker")
        .enable_all()
        .build()
        .map_err(|e| StartError::Server(e.to_string()))?;
    let guard = rt.enter();
    let listener =
        tokio::net::TcpListener::from_std(listener).map_err(|source| StartError::Bind {
            addr: plan.addr,
            source,
        })?;
    let (server, handle) = builder.build().map_err(StartError::Server)?;
    let nm = handle
        .node_managers()
        .get_by_name::<OwnManager>(OWN)
        .ok_or_else(|| StartError::Server("the ncplc node manager is missing".into()))?;
    let index = |uri: &str| {
        handle
            .get_namespace_index(uri)
            .ok_or_else(|| StartError::Server(format!("namespace {uri} is missing")))
    };
    let ns = machine_tool::Ns {
        own: index(NCPLC_NS)?,
        mt: index(nodesets::MACHINE_TOOL)?,
        machinery: index(nodesets::MACHINERY)?,
        di: index(nodesets::DI)?,
        ia: index(nodesets::IA)?,
    };
    let added = {
        let mut space = nm.address_space().write();
        space::add_signals(&mut space, ns.own, &plan.table, tick_ms);
        crate::variables::add(&mut space, ns.own, &plan.vars);
        machine_tool::add(&mut space, ns, &plan.model)
    };
    for n in plan.table.iter().filter(|n| n.writable) {
        nm.inner()
            .add_writable(NodeId::new(ns.own, n.id.as_str()), n.signal);
    }
    for (id, process, command) in added.methods {
        nm.inner().add_method(id, process, command);
    }
    let publisher = publisher::Publisher {
        nm,
        subs: Arc::clone(handle.subscriptions()),
        nodes: Nodes::new(ns.own, &plan.table, &plan.vars),
        model: values::Evaluator::new(added.values, ns.mt),
        messages: (
            NodeId::new(ns.own, machine_tool::MESSAGES),
            NodeId::new(ns.mt, 35u32),
        ),
        side,
        tick_ms,
        origin: DateTime::now().checked_ticks(),
    };
    drop(guard);
    let thread = std::thread::Builder::new()
        .name("opcua".into())
        .spawn(move || {
            rt.block_on(async move {
                let publish = tokio::spawn(publisher::run(publisher));
                if let Err(e) = server.run_with(listener).await {
                    eprintln!("opcua: the server stopped: {e}");
                }
                publish.abort();
            });
        })
        .map_err(|e| StartError::Server(e.to_string()))?;
    Ok(Running {
        addr,
        handle,
        thread: Some(thread),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_connection_accepted_from_the_listener_has_no_delay() {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
        no_delay(&listener).expect("nodelay");
        let addr = listener.local_addr().expect("addr");
        let _client = std::net::TcpStream::connect(addr).expect("connect");
        let (accepted, _) = listener.accept().expect("accept");
        assert!(accepted.nodelay().expect("read TCP_NODELAY"));
        // Without it the accepted connection has Nagle's algorithm on.
        let plain = std::net::TcpListener::bind("127.0.0.1:0").expect("bind");
        let _other = std::net::TcpStream::connect(plain.local_addr().expect("addr"));
        let (accepted, _) = plain.accept().expect("accept");
        assert!(!accepted.nodelay().expect("read TCP_NODELAY"));
    }
}
