//! The boundary between the scan loop and whatever provides packet A (simulation, Modbus, CANopen).
//!
//! The scan loop calls [`PacketIo::latch_inputs`] at the start of every tick and
//! [`PacketIo::publish_outputs`] after the scan. Both work on the packets part of the flat image
//! (the first [`crate::PACKETS_LEN`] bytes) and must never block: a driver that talks to the network
//! exchanges images with its own tasks through lock-free buffers and hands over the latest complete
//! input image it has.

use serde::{Deserialize, Serialize};

/// A source and sink of packet-A signals (and of anything else a driver maps into the packets, such
/// as per-device healthy bits or an HMI's holding-register window in K/N).
pub trait PacketIo: Send {
    /// Short name for status lines and alarms (`sim`, `modbus`, `canopen`).
    fn name(&self) -> &str;

    /// Writes the latest consistent input image into `packets` (inputs only; never blocks).
    fn latch_inputs(&mut self, tick: u64, packets: &mut [u8]);

    /// Takes the outputs the scan produced (never blocks; the driver sends what changed).
    fn publish_outputs(&mut self, tick: u64, packets: &[u8]);

    /// Alarms raised since the last call (a device stopped answering, a node was lost, …).
    fn take_alarms(&mut self) -> Vec<IoAlarm> {
        Vec::new()
    }

    /// Puts every output in its safe state (called when the runtime stops or trips on overruns).
    fn safe_state(&mut self) {}
}

/// An I/O alarm: which device and what happened.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct IoAlarm {
    /// The device's name from the I/O map.
    pub device: String,
    /// What happened, in English.
    pub message: String,
    /// True when the device is working again (the alarm clears).
    pub cleared: bool,
}
