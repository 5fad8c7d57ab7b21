//! What the scan thread hands the HMI: a [`Frame`] of plain data (the packet image, a few scan and
//! kernel numbers) copied into a preallocated slot of a triple buffer. The scan's part of a
//! published snapshot is that copy: no allocation once the slots have grown to size, no JSON, no
//! names. The HMI's render thread ([`super::render`]) turns the newest frame into a
//! [`hmi::Snapshot`].

use std::sync::Arc;

use compiler::ir::flow::FlowMap;
use hmi::{AlarmEntry, MessageEntry};
use packets::Signal;
use partprogram::canon::Canon;

/// Most processes whose alarm acknowledges a frame counts (index 0: every process).
pub const MAX_PROCESSES: usize = 8;

/// One published state of the controller as the scan copied it.
#[derive(Debug, Clone, Default)]
pub struct Frame {
    /// Bumped on every publish (0: nothing published yet).
    pub seq: u64,
    /// Ticks run so far.
    pub tick: u64,
    /// The running engine's name.
    pub engine: String,
    /// The last tick's and the longest scan time in ns, overruns.
    pub scan: (u64, u64, u64),
    /// Packets A, K, N and T.
    pub image: Vec<u8>,
    /// The active forces in image order.
    pub forced: Vec<(Signal, u8)>,
    /// The machine-wide alarm list.
    pub alarms: Vec<AlarmEntry>,
    /// The PLC messages' list.
    pub messages: Vec<MessageEntry>,
    /// The online-change status.
    pub online: String,
    /// The overrun limit tripped the safe state.
    pub tripped: bool,
    /// Power flow is switched on.
    pub flow_enabled: bool,
    /// Acknowledge commands so far, per process (index 0: `ack` for every process).
    pub acks: [u64; MAX_PROCESSES],
    /// The power-flow area of the image and where each statement's slot is in it (none: the
    /// program was not compiled for power flow).
    pub flow: (Vec<u8>, Option<Arc<FlowMap>>),
    /// The CNC kernel's processes (empty without a kernel).
    pub kernel: Vec<RawProcess>,
    /// The last MDI line the kernel accepted and how many it accepted so far.
    pub mdi: (u64, String),
    /// MDI lines compiled on the HMI's request thread and on the scan so far (None: no kernel).
    pub mdi_compiles: Option<(u64, u64)>,
}

/// One kernel process as the scan copied it.
#[derive(Debug, Clone)]
pub struct RawProcess {
    /// The kernel's status (filled in place by [`cnc::Process::status_into`]).
    pub status: cnc::ProcessStatus,
    /// A feed hold keeps the path stopped.
    pub held: bool,
    /// Completed M, S and T handshakes.
    pub handshakes: [u64; 3],
    /// The loaded program: a number that changes with every load, and its blocks (shared, not
    /// copied: the scan copies a program once, when it is loaded).
    pub program: (u64, Arc<[Canon]>),
}

impl Frame {
    /// A frame whose image is `len` bytes long (so that the first publish does not grow it).
    pub fn with_image(len: usize) -> Frame {
        Frame {
            image: vec![0; len],
            ..Frame::default()
        }
    }
}
