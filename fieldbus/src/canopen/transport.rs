//! The transport trait every CAN bus implementation provides.

use std::future::Future;
use std::io;

use super::CanMsg;

/// A CAN bus endpoint: sends frames and receives the frames of the other nodes.
///
/// `recv` must be cancel-safe (a frame is never lost when its future is dropped before it
/// completes), because the master waits for frames and for the scan's tick at the same time.
pub trait CanBus: Send + 'static {
    /// Sends one frame.
    fn send(&mut self, msg: &CanMsg) -> impl Future<Output = io::Result<()>> + Send;

    /// Waits for the next frame from another node.
    fn recv(&mut self) -> impl Future<Output = io::Result<CanMsg>> + Send;
}
