//! CiA 402 servo drives over CANopen: the master's side.
//!
//! [`startup`] configures and starts the drives (all or none), [`cia402`] is the power state
//! machine, [`set::DriveSet`] the per-tick logic without I/O (what a master task embeds), and
//! [`Drives`] runs a [`DriveSet`] on a bus of its own, one SYNC per [`Drives::sync`] call — the
//! interface the CNC kernel plugs into: per interpolation tick, [`Drives::command`] for every axis,
//! then [`Drives::sync`], then [`Drives::feedback`].
//!
//! Invariant: the target carried by the RPDO that precedes SYNC n is the set point commanded for
//! tick n (commanded before that `sync` call); the feedback after `sync` n is the drive's answer
//! to SYNC n.

pub mod cia402;
pub mod link;
pub mod set;
pub mod startup;

use std::io;

use tokio::time::{Duration, Instant};

pub use cia402::State;
pub use link::{DriveAnswer, DriveAnswers, DriveOrder, DriveOrders, DriveTiming, ScanDrives};
pub use set::{AxisId, DriveCommand, DriveFault, DriveFeedback, DriveSet, FaultCause};
pub use startup::DriveStartError;

use super::transport::CanBus;
use super::{CanMsg, cob};
use crate::map::CanDrive;

/// A bus of CiA 402 drives, driven one SYNC at a time.
pub struct Drives<B> {
    bus: B,
    set: DriveSet,
    answer_timeout: Duration,
}

impl<B: CanBus> Drives<B> {
    /// Configures and starts `drives` on `bus` (see [`startup::start`]), SYNC every `tick`; an SDO
    /// transfer waits at most `sdo_timeout`. On an error no drive is started.
    pub async fn start(
        mut bus: B,
        drives: &[CanDrive],
        tick: Duration,
        sdo_timeout: Duration,
    ) -> Result<Drives<B>, DriveStartError> {
        let mut seen = Vec::new();
        let statuswords = startup::start(&mut bus, drives, tick, sdo_timeout, &mut |m: &CanMsg| {
            seen.push(*m);
        })
        .await?;
        let mut set = DriveSet::new(drives, tick);
        let now = Instant::now();
        for m in &seen {
            set.on_frame(m, now);
        }
        set.started(now, &statuswords);
        Ok(Drives {
            bus,
            set,
            answer_timeout: tick / 2,
        })
    }

    /// How long [`Drives::sync`] waits for the drives' answers (default: half a tick).
    pub fn set_answer_timeout(&mut self, t: Duration) {
        self.answer_timeout = t;
    }

    /// The axes, in drive order.
    pub fn axes(&self) -> Vec<AxisId> {
        self.set.axes().collect()
    }

    /// Commands `axis` for the next SYNC; false when no drive has that axis.
    pub fn command(&mut self, axis: AxisId, cmd: DriveCommand) -> bool {
        self.set.command(axis, cmd)
    }

    /// The feedback of `axis` after the last SYNC.
    pub fn feedback(&self, axis: AxisId) -> Option<DriveFeedback> {
        self.set.feedback(axis)
    }

    /// One interpolation tick: the RPDOs of this tick's commands, the SYNC, then the drives'
    /// answers (until every drive answered and no fault code is being read, or the answer
    /// timeout), then the heartbeat and enable checks.
    pub async fn sync(&mut self) -> io::Result<()> {
        for m in self.set.rpdos(Instant::now()) {
            self.bus.send(&m).await?;
        }
        self.bus.send(&CanMsg::new(cob::SYNC, &[])).await?;
        let deadline = Instant::now() + self.answer_timeout;
        while !self.set.all_answered() || self.set.code_pending() {
            let m = match tokio::time::timeout_at(deadline, self.bus.recv()).await {
                Err(_) => break,
                Ok(m) => m?,
            };
            for reply in self.set.on_frame(&m, Instant::now()) {
                self.bus.send(&reply).await?;
            }
        }
        self.set.after_sync(Instant::now());
        Ok(())
    }

    /// Passes frames that arrive between ticks (heartbeats, EMCY) to the drives, for at most
    /// `wait`; used between two `sync` calls instead of sleeping.
    pub async fn idle(&mut self, wait: Duration) -> io::Result<()> {
        let deadline = Instant::now() + wait;
        loop {
            let m = match tokio::time::timeout_at(deadline, self.bus.recv()).await {
                Err(_) => return Ok(()),
                Ok(m) => m?,
            };
            for reply in self.set.on_frame(&m, Instant::now()) {
                self.bus.send(&reply).await?;
            }
        }
    }
}
