//! The operator HMI of ncplc: a web server with a JSON API (`API.md`), a WebSocket `/ws` carrying
//! the live image, and the pages (Signals, Program, Trace, Machine) embedded in the binary.
//!
//! The scan never waits for the HMI: it publishes [`Snapshot`]s into a `tokio::sync::watch`
//! channel (only the latest value is kept, so a slow browser skips frames) and drains
//! [`Envelope`]s (writes, forces, commands) from a `std::sync::mpsc` channel at tick boundaries,
//! answering each with the tick that applied it. The server runs on its own thread with its own
//! tokio runtime.

pub mod api;
pub mod assets;
pub mod demand;
pub mod error;
pub mod model;
pub mod security;
pub mod server;
pub mod ws;

pub use demand::Demand;
pub use model::{
    AlarmEntry, AxisStatus, Catalog, Command, Envelope, HandshakeCounts, MachineStatus,
    MdiCompiles, MessageEntry, NamedSignal, PathPiece, ProcessStatus, Reply, Request, ScanStats,
    SharedSnapshot, Snapshot, SourceLine, Toolpath,
};
pub use security::{Role, Tokens};
pub use server::{Running, ServerConfig, StartError, is_loopback, start};
