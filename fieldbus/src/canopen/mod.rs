//! CANopen: a master for CiA 401 digital I/O modules over any [`transport::CanBus`].
//!
//! [`master`] is the packet-A driver (NMT start, SYNC every tick, RPDO/TPDO mapping, heartbeat
//! consumer, SDO configuration at start). The bus is reached through the [`transport::CanBus`] trait
//! with three implementations: Linux SocketCAN ([`socketcan_bus`]), an in-process virtual bus
//! ([`virtual_bus`]) and CAN over UDP in the cannelloni format ([`cannelloni`]). [`node_sim`] is a
//! simulated CiA 401 node for tests and for the `virtual` transport, [`sim_wiring`] its terminals
//! wired to packet A for a simulated machine. [`drive`] is the CiA 402 side
//! of the master (servo drives in cyclic synchronous position or velocity mode), [`drive_sim`] a
//! simulated CiA 402 drive node.

pub mod cannelloni;
pub mod drive;
pub mod drive_machine;
pub mod drive_sim;
pub mod master;
pub mod node_sim;
pub mod sdo;
pub mod sim_node;
pub mod sim_wiring;
pub mod socketcan_bus;
pub mod transport;
pub mod virtual_bus;

/// Maximum data bytes of a frame (CAN FD); classic CAN frames carry at most 8.
pub const MAX_DATA: usize = 64;

/// One CAN frame, independent of the transport.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CanMsg {
    /// 11-bit (standard) or 29-bit (extended) identifier.
    pub id: u32,
    /// True for a 29-bit identifier.
    pub extended: bool,
    /// True for a remote-transmission request.
    pub rtr: bool,
    /// True for a CAN FD frame.
    pub fd: bool,
    /// Number of data bytes.
    pub len: u8,
    /// The data; bytes past `len` are 0.
    pub data: [u8; MAX_DATA],
}

impl CanMsg {
    /// A classic standard-id data frame with up to 8 bytes of `data` (longer data is cut at 8).
    pub fn new(id: u16, data: &[u8]) -> CanMsg {
        let n = data.len().min(8);
        let mut d = [0u8; MAX_DATA];
        d[..n].copy_from_slice(&data[..n]);
        CanMsg {
            id: u32::from(id & 0x7FF),
            extended: false,
            rtr: false,
            fd: false,
            len: n as u8,
            data: d,
        }
    }

    /// The data bytes.
    pub fn payload(&self) -> &[u8] {
        &self.data[..usize::from(self.len).min(MAX_DATA)]
    }
}

/// CANopen function codes (COB-ID bases) of the predefined connection set.
pub mod cob {
    /// NMT command (master → all).
    pub const NMT: u16 = 0x000;
    /// SYNC.
    pub const SYNC: u16 = 0x080;
    /// TPDO1 (node → master); TPDOn = `TPDO1 + 0x100 (n-1)`.
    pub const TPDO1: u16 = 0x180;
    /// RPDO1 (master → node); RPDOn = `RPDO1 + 0x100 (n-1)`.
    pub const RPDO1: u16 = 0x200;
    /// SDO server → client (response).
    pub const SDO_TX: u16 = 0x580;
    /// SDO client → server (request).
    pub const SDO_RX: u16 = 0x600;
    /// NMT error control (heartbeat, boot-up).
    pub const HEARTBEAT: u16 = 0x700;

    /// COB-ID of TPDO `n` (1..4) of `node`.
    pub fn tpdo(n: u8, node: u8) -> u16 {
        TPDO1 + 0x100 * u16::from(n.clamp(1, 4) - 1) + u16::from(node)
    }

    /// COB-ID of RPDO `n` (1..4) of `node`.
    pub fn rpdo(n: u8, node: u8) -> u16 {
        RPDO1 + 0x100 * u16::from(n.clamp(1, 4) - 1) + u16::from(node)
    }
}

/// NMT states as a heartbeat reports them.
pub mod nmt {
    /// Boot-up message.
    pub const BOOTUP: u8 = 0x00;
    /// Stopped.
    pub const STOPPED: u8 = 0x04;
    /// Operational.
    pub const OPERATIONAL: u8 = 0x05;
    /// Pre-operational.
    pub const PRE_OPERATIONAL: u8 = 0x7F;
    /// Command: start remote node.
    pub const CMD_START: u8 = 0x01;
    /// Command: stop remote node.
    pub const CMD_STOP: u8 = 0x02;
    /// Command: enter pre-operational.
    pub const CMD_PRE_OPERATIONAL: u8 = 0x80;
    /// Command: reset node.
    pub const CMD_RESET_NODE: u8 = 0x81;
    /// Command: reset communication.
    pub const CMD_RESET_COMM: u8 = 0x82;
}
