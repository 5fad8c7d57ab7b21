//! Builds the `Signals` part of the address space: a folder per packet and per connector under
//! `Objects/Signals`, one variable per [`SignalNode`] (Boolean for a bit, Byte for a byte) with
//! its meaning as description and its address as the `Address` property, and the run's `Tick`
//! and `TickMs` variables.
//!
//! **Invariant:** only nodes inside the write window carry `CurrentWrite` in their access level
//! (their writes go through [`crate::node_manager`] to the scan); every other node is read-only,
//! so a write answers `BadNotWritable` before anything moves.

use opcua::nodes::{AccessLevel, ObjectBuilder, VariableBuilder};
use opcua::server::address_space::AddressSpace;
use opcua::types::{DataTypeId, NodeId, ObjectId, QualifiedName, VariableTypeId, Variant};

use packets::Packet;

use crate::signals::{SignalNode, connector_folder, packet_folder};

/// The node id of the `Signals` folder.
pub const SIGNALS: &str = "Signals";
/// The node id of the tick counter.
pub const TICK: &str = "Signals/Tick";
/// The node id of the logic tick (ms).
pub const TICK_MS: &str = "Signals/TickMs";

/// Adds the signals folder and its nodes to `space` in namespace `ns`.
pub fn add_signals(space: &mut AddressSpace, ns: u16, table: &[SignalNode], tick_ms: u32) {
    let root = NodeId::new(ns, SIGNALS);
    ObjectBuilder::new(&root, QualifiedName::new(ns, "Signals"), "Signals")
        .description("The packet signals A, K, N and T, by packet and connector")
        .is_folder()
        .organized_by(NodeId::from(ObjectId::ObjectsFolder))
        .insert(space);
    VariableBuilder::new(&NodeId::new(ns, TICK), QualifiedName::new(ns, "Tick"), "Tick")
        .description("The tick whose image the signals show (the trace's t); a value's source timestamp is origin + t x TickMs")
        .data_type(DataTypeId::UInt64)
        .value_rank(-1)
        .value(0u64)
        .organized_by(root.clone())
        .has_type_definition(VariableTypeId::BaseDataVariableType)
        .insert(space);
    VariableBuilder::new(
        &NodeId::new(ns, TICK_MS),
        QualifiedName::new(ns, "TickMs"),
        "TickMs",
    )
    .description("The logic tick in ms")
    .data_type(DataTypeId::UInt32)
    .value_rank(-1)
    .value(tick_ms)
    .organized_by(root.clone())
    .has_type_definition(VariableTypeId::BaseDataVariableType)
    .insert(space);
    for packet in Packet::ALL {
        let pid = NodeId::new(ns, packet_folder(packet));
        let letter = packet.letter().to_string();
        ObjectBuilder::new(
            &pid,
            QualifiedName::new(ns, letter.as_str()),
            letter.as_str(),
        )
        .description(format!("Packet {letter}"))
        .is_folder()
        .organized_by(root.clone())
        .insert(space);
        for c in 0..packet.connectors() {
            let name = c.to_string();
            ObjectBuilder::new(
                &NodeId::new(ns, connector_folder(packet, c)),
                QualifiedName::new(ns, name.as_str()),
                format!("{letter} connector {c}"),
            )
            .is_folder()
            .organized_by(pid.clone())
            .insert(space);
        }
    }
    for n in table {
        add_signal(space, ns, n);
    }
}

fn add_signal(space: &mut AddressSpace, ns: u16, n: &SignalNode) {
    let id = NodeId::new(ns, n.id.as_str());
    let parent = NodeId::new(
        ns,
        connector_folder(n.signal.packet(), crate::signals::connector_of(&n.signal)),
    );
    let access = if n.writable {
        AccessLevel::CURRENT_READ | AccessLevel::CURRENT_WRITE
    } else {
        AccessLevel::CURRENT_READ
    };
    let (data_type, value) = match n.signal.bit() {
        Some(_) => (DataTypeId::Boolean, Variant::Boolean(false)),
        None => (DataTypeId::Byte, Variant::Byte(0)),
    };
    VariableBuilder::new(
        &id,
        QualifiedName::new(ns, n.name.as_str()),
        n.name.as_str(),
    )
    .description(n.meaning.as_str())
    .data_type(data_type)
    .value_rank(-1)
    .value(value)
    .access_level(access)
    .user_access_level(access)
    .organized_by(parent)
    .has_type_definition(VariableTypeId::BaseDataVariableType)
    .insert(space);
    let address = format!("{}/Address", n.id);
    VariableBuilder::new(
        &NodeId::new(ns, address.as_str()),
        QualifiedName::new(ns, "Address"),
        "Address",
    )
    .description("The signal's address in the packets")
    .data_type(DataTypeId::String)
    .value_rank(-1)
    .value(n.signal.to_string())
    .property_of(id)
    .has_type_definition(VariableTypeId::PropertyType)
    .insert(space);
}
