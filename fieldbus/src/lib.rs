//! Packet-A I/O over Modbus TCP (client and HMI server) and CANopen (SocketCAN, virtual bus, cannelloni UDP).
//!
//! The runtime's scan loop talks to every driver through [`packets::PacketIo`]. This crate reads the
//! machine's I/O map (`<machine>/io.toml`, [`map`] and [`validate`]), and [`open`] starts the driver the
//! command line chose: the Modbus TCP remote-I/O client ([`modbus::client`]) or the CANopen master
//! ([`canopen::master`]). [`start_hmi`] wraps any driver (the simulated one too) with the Modbus TCP
//! server for an HMI or SCADA ([`modbus::server`]). Drivers never block the scan: their network tasks
//! run on a private tokio runtime and exchange images through lock-free buffers ([`exchange`]).

pub mod canopen;
pub mod exchange;
pub mod health;
pub mod map;
pub mod modbus;
pub mod validate;

pub use map::{DeclaredConnectors, IoMap};
pub use validate::{load_map, parse_map};
