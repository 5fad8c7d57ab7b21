//! The run loop every simulated CANopen node shares (the CiA 401 I/O module of `node_sim`, the
//! CiA 402 drive of `drive_sim`): the boot-up frame, then frames from the bus handed to the node's
//! own `handle` and its heartbeat sent every `heartbeat_ms` (none while 0).
//!
//! Invariant: the node's state is locked only inside `handle` and the heartbeat step, never across
//! an await, so a test may lock it at any time.

use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use super::transport::CanBus;
use super::{CanMsg, cob, nmt};

/// What the shared loop needs of a simulated node's state.
pub trait SimNode: Send + 'static {
    /// The heartbeat producer time (ms; 0 = no heartbeat).
    fn heartbeat_ms(&self) -> u16;
    /// The NMT state byte the heartbeat carries, or `None` while the node sends no heartbeat
    /// (silent, or a test hook stopped it).
    fn heartbeat_state(&self) -> Option<u8>;
    /// The frames the node answers `m` with.
    fn handle(&mut self, id: u8, m: &CanMsg) -> Vec<CanMsg>;
}

/// Runs node `id` on `bus` until the bus fails.
pub async fn run<B: CanBus, S: SimNode>(mut bus: B, id: u8, state: Arc<Mutex<S>>) {
    let lock = || state.lock().unwrap_or_else(PoisonError::into_inner);
    let heartbeat = cob::HEARTBEAT + u16::from(id);
    if bus
        .send(&CanMsg::new(heartbeat, &[nmt::BOOTUP]))
        .await
        .is_err()
    {
        return;
    }
    let mut next_hb = tokio::time::Instant::now();
    loop {
        let hb_ms = lock().heartbeat_ms();
        let wait = if hb_ms == 0 {
            Duration::from_secs(3600)
        } else {
            next_hb.saturating_duration_since(tokio::time::Instant::now())
        };
        let replies = tokio::select! {
            m = bus.recv() => match m {
                Ok(m) => lock().handle(id, &m),
                Err(_) => return,
            },
            () = tokio::time::sleep(wait) => {
                let s = lock();
                next_hb = tokio::time::Instant::now()
                    + Duration::from_millis(u64::from(s.heartbeat_ms().max(1)));
                match (s.heartbeat_ms(), s.heartbeat_state()) {
                    (0, _) | (_, None) => Vec::new(),
                    (_, Some(state)) => vec![CanMsg::new(heartbeat, &[state])],
                }
            }
        };
        for r in replies {
            if bus.send(&r).await.is_err() {
                return;
            }
        }
    }
}
