//! The signal table the server publishes: every byte of the packets A, K, N and T (`W<c><P><b>`)
//! and every name of the interface map and of the PLC program's `DEF` aliases, each placed under
//! its packet and connector, with its meaning and whether the io.toml write window lets a client
//! write it.
//!
//! **Invariants:** node ids are unique (a name that repeats a byte address or an earlier name of
//! the same connector is listed once); the table is in image order, so equal inputs give equal
//! address spaces.

use std::collections::BTreeSet;

use packets::{Packet, Signal};

use crate::window::Window;

/// Where a signal node's name comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// A byte of a packet, named by its address.
    Byte,
    /// A name of the interface map.
    Interface,
    /// A `DEF` alias of the PLC program.
    Program,
}

/// One variable node of the `Signals` folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SignalNode {
    /// The string node id (`Signals/K/200/W200K0`).
    pub id: String,
    /// The browse name: the address of a byte, else the interface-map or program name.
    pub name: String,
    /// The address.
    pub signal: Signal,
    /// What it means (the interface map's text; for a byte or an alias: what it is).
    pub meaning: String,
    /// Where the name comes from.
    pub origin: Origin,
    /// Inside the io.toml write window.
    pub writable: bool,
}

/// The id of the folder of `packet` (`Signals/K`).
pub fn packet_folder(packet: Packet) -> String {
    format!("Signals/{}", packet.letter())
}

/// The id of the folder of a connector (`Signals/K/200`).
pub fn connector_folder(packet: Packet, connector: u16) -> String {
    format!("Signals/{}/{connector}", packet.letter())
}

/// The connector a signal belongs to.
pub fn connector_of(signal: &Signal) -> u16 {
    match *signal {
        Signal::Bit { connector, .. } | Signal::Byte { connector, .. } => connector,
    }
}

/// Builds the table from the named signals (interface map and aliases: name, address, meaning,
/// from the program) and the write window.
pub fn table(names: &[(String, Signal, String, bool)], window: &Window) -> Vec<SignalNode> {
    let mut nodes = Vec::new();
    let mut ids = BTreeSet::new();
    for packet in Packet::ALL {
        for connector in 0..packet.connectors() {
            for index in 0..4u8 {
                let signal = Signal::Byte {
                    packet,
                    connector,
                    index,
                };
                let name = signal.to_string();
                let id = format!("{}/{name}", connector_folder(packet, connector));
                ids.insert(id.clone());
                nodes.push(SignalNode {
                    id,
                    meaning: format!("byte {index} of {} connector {connector}", packet.letter()),
                    name,
                    signal,
                    origin: Origin::Byte,
                    writable: window.contains(&signal),
                });
            }
        }
    }
    let mut named: Vec<SignalNode> = Vec::new();
    for (name, signal, meaning, program) in names {
        let id = format!(
            "{}/{name}",
            connector_folder(signal.packet(), connector_of(signal))
        );
        if !ids.insert(id.clone()) {
            continue;
        }
        named.push(SignalNode {
            id,
            name: name.clone(),
            signal: *signal,
            meaning: if meaning.is_empty() && *program {
                format!("PLC program alias of {signal}")
            } else {
                meaning.clone()
            },
            origin: if *program {
                Origin::Program
            } else {
                Origin::Interface
            },
            writable: window.contains(signal),
        });
    }
    nodes.extend(named);
    nodes.sort_by_key(|n| (n.signal.image_byte(), n.origin != Origin::Byte));
    nodes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_packet_byte_and_every_name_once_in_image_order() {
        let window = Window::from_ranges(vec![(Packet::K.offset() + 800, 4)]);
        let start: Signal = "I200K0".parse().expect("signal");
        let fov: Signal = "W3K0".parse().expect("signal");
        let names = vec![
            ("START".to_string(), start, "cycle start".to_string(), false),
            ("START".to_string(), start, String::new(), true),
            ("FOV".to_string(), fov, "feed override".to_string(), false),
            ("W3K0".to_string(), fov, String::new(), true),
        ];
        let t = table(&names, &window);
        assert_eq!(t.len(), packets::PACKETS_LEN + 2);
        let start_node = t.iter().find(|n| n.name == "START").expect("START");
        assert_eq!(start_node.id, "Signals/K/200/START");
        assert_eq!(start_node.origin, Origin::Interface);
        assert!(start_node.writable);
        let fov_node = t.iter().find(|n| n.name == "FOV").expect("FOV");
        assert!(!fov_node.writable);
        assert_eq!(fov_node.meaning, "feed override");
        let w = t
            .iter()
            .position(|n| n.id == "Signals/K/200/W200K0")
            .expect("byte");
        assert_eq!(t[w + 1].name, "START", "a name follows its byte");
        assert_eq!(t[0].id, "Signals/A/0/W0A0");
        assert_eq!(t.last().map(|n| n.id.as_str()), Some("Signals/T/15/W15T3"));
    }
}
