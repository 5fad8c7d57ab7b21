//! The node manager of the server's own namespace (`urn:ncplc`): async-opcua's in-memory node
//! manager with our `Write` and `Call`, which see the session (its role) where the stack's simple
//! node manager does not.
//!
//! - **Write:** a node whose `AccessLevel` lacks `CurrentWrite` (everything outside the io.toml
//!   write window) answers `BadNotWritable`, whoever asks; inside the window a role without the
//!   right answers `BadUserAccessDenied` (the user access level, [`crate::auth`]), a value of the
//!   wrong type `BadTypeMismatch`, an index range `BadIndexRangeInvalid`; an accepted write goes to
//!   the scan as a [`crate::handoff::Write`]. Nothing is written on a refusal.
//! - **Call:** the channel's `Start`, `Hold` and `Reset` ([`crate::machine_tool`]) go to the scan
//!   as a [`CommandRequest`] with the caller's role and wait for the kernel's answer (the stack has
//!   checked that the role may execute methods); the output is the tick it was applied at.
//!
//! **Invariant:** neither path touches the scan: a request is a channel send, and the answer an
//! `await` on the server's task; the address space is only read here.

use std::collections::HashMap;
use std::sync::mpsc::Sender;
use std::sync::{Arc, RwLock as StdRwLock};
use std::time::Duration;

use async_trait::async_trait;
use hmi::Command;
use opcua::nodes::{AccessLevel, NodeType};
use opcua::server::address_space::{AddressSpace, validate_node_write};
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::memory::{
    InMemoryNodeManager, InMemoryNodeManagerBuilder, InMemoryNodeManagerImpl,
};
use opcua::server::node_manager::{
    MethodCall, NodeManagerBuilder, RequestContext, ServerContext, WriteNode,
};
use opcua::sync::RwLock;
use opcua::types::{AttributeId, NodeId, StatusCode, Variant};
use packets::Signal;

use crate::auth::Auth;
use crate::handoff::{CommandRequest, Write};

/// How long a method call waits for the scan's answer (a tick, unless the scan has stopped).
pub const COMMAND_WAIT: Duration = Duration::from_secs(5);

/// The node manager as the stack holds it.
pub type OwnManager = InMemoryNodeManager<Own>;

/// Our half of the node manager.
pub struct Own {
    namespace: NamespaceMetadata,
    name: String,
    auth: Arc<Auth>,
    writes: Sender<Write>,
    commands: Sender<CommandRequest>,
    writable: StdRwLock<HashMap<NodeId, Signal>>,
    methods: StdRwLock<HashMap<NodeId, (u8, Command)>>,
}

/// The builder of the node manager for namespace `uri`, named `name`.
pub fn builder(
    uri: &str,
    name: &str,
    auth: Arc<Auth>,
    writes: Sender<Write>,
    commands: Sender<CommandRequest>,
) -> impl NodeManagerBuilder {
    let (uri, name) = (uri.to_string(), name.to_string());
    InMemoryNodeManagerBuilder::new(move |ctx: ServerContext, space: &mut AddressSpace| {
        let index = ctx.type_tree.write().namespaces_mut().add_namespace(&uri);
        space.add_namespace(&uri, index);
        Own {
            namespace: NamespaceMetadata {
                namespace_uri: uri,
                namespace_index: index,
                ..Default::default()
            },
            name,
            auth,
            writes,
            commands,
            writable: StdRwLock::default(),
            methods: StdRwLock::default(),
        }
    })
}

impl Own {
    /// Lets clients write `signal` through variable `id` (a node inside the write window).
    pub fn add_writable(&self, id: NodeId, signal: Signal) {
        let mut w = self
            .writable
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        w.insert(id, signal);
    }

    /// Makes method `id` give `command` to `process`'s kernel.
    pub fn add_method(&self, id: NodeId, process: u8, command: Command) {
        let mut m = self
            .methods
            .write()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        m.insert(id, (process, command));
    }

    fn write_one(
        &self,
        context: &RequestContext,
        space: &AddressSpace,
        write: &WriteNode,
    ) -> StatusCode {
        let v = write.value();
        let Some(node) = space.find(&v.node_id) else {
            return StatusCode::BadNodeIdUnknown;
        };
        // The node's own access level first: outside the window nobody may write.
        let writable = matches!(node, NodeType::Variable(var)
            if var.access_level().contains(AccessLevel::CURRENT_WRITE));
        if v.attribute_id != AttributeId::Value || !writable {
            return StatusCode::BadNotWritable;
        }
        {
            let tree = context.type_tree.read();
            if let Err(e) = validate_node_write(node, context, v, &*tree) {
                return e;
            }
        }
        if v.index_range.has_range() {
            return StatusCode::BadIndexRangeInvalid;
        }
        let signal = {
            let w = self
                .writable
                .read()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            match w.get(&v.node_id) {
                Some(s) => *s,
                None => return StatusCode::BadNotWritable,
            }
        };
        let value = match (&v.value.value, signal.bit()) {
            (Some(Variant::Boolean(b)), Some(_)) => u8::from(*b),
            (Some(Variant::Byte(x)), None) => *x,
            _ => return StatusCode::BadTypeMismatch,
        };
        match self.writes.send((signal, value)) {
            Ok(()) => StatusCode::Good,
            Err(_) => StatusCode::BadServerHalted,
        }
    }

    async fn call_one(&self, context: &RequestContext, method: &mut MethodCall) {
        let found = {
            let m = self
                .methods
                .read()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            m.get(method.method_id()).cloned()
        };
        let Some((process, command)) = found else {
            method.set_status(StatusCode::BadMethodInvalid);
            return;
        };
        let Some(role) = self.auth.role(&context.token) else {
            method.set_status(StatusCode::BadUserAccessDenied);
            return;
        };
        let (reply, answer) = tokio::sync::oneshot::channel();
        let request = CommandRequest {
            process,
            command,
            role,
            reply,
        };
        if self.commands.send(request).is_err() {
            method.set_status(StatusCode::BadServerHalted);
            return;
        }
        match tokio::time::timeout(COMMAND_WAIT, answer).await {
            Ok(Ok(Ok(tick))) => {
                method.set_outputs(vec![Variant::UInt64(tick)]);
                method.set_status(StatusCode::Good);
            }
            // The kernel refused it (not in AUTO, nothing to hold, …).
            Ok(Ok(Err(_why))) => method.set_status(StatusCode::BadInvalidState),
            Ok(Err(_)) => method.set_status(StatusCode::BadServerHalted),
            Err(_) => method.set_status(StatusCode::BadTimeout),
        }
    }
}

#[async_trait]
impl InMemoryNodeManagerImpl for Own {
    async fn init(&self, _space: &mut AddressSpace, _context: ServerContext) {}

    fn name(&self) -> &str {
        &self.name
    }

    fn namespaces(&self) -> Vec<NamespaceMetadata> {
        vec![self.namespace.clone()]
    }

    async fn write(
        &self,
        context: &RequestContext,
        address_space: &RwLock<AddressSpace>,
        nodes_to_write: &mut [&mut WriteNode],
    ) -> Result<(), StatusCode> {
        let space = address_space.read();
        for w in nodes_to_write {
            let status = self.write_one(context, &space, w);
            w.set_status(status);
        }
        Ok(())
    }

    async fn call(
        &self,
        context: &RequestContext,
        _address_space: &RwLock<AddressSpace>,
        methods_to_call: &mut [&mut &mut MethodCall],
    ) -> Result<(), StatusCode> {
        for m in methods_to_call {
            self.call_one(context, m).await;
        }
        Ok(())
    }
}
