//! Whether anybody is looking: the connected WebSocket clients and the last API read. The
//! runtime's render thread builds snapshots only while there is demand and otherwise sleeps
//! until there is (no wake-ups without clients); an API read that finds it asleep wakes it and
//! waits briefly for a fresh snapshot.

use std::sync::{Condvar, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// How long the render thread keeps rendering after the last API read (a page polling the API
/// is served from fresh snapshots without waiting on each read).
pub const LINGER: Duration = Duration::from_secs(2);

/// The demand for snapshots, shared by the server and the render thread.
#[derive(Debug)]
pub struct Demand {
    state: Mutex<State>,
    wake: Condvar,
    linger: Duration,
}

#[derive(Debug, Default)]
struct State {
    clients: usize,
    last_read: Option<Instant>,
    requested: bool,
    stopped: bool,
}

impl Default for Demand {
    fn default() -> Self {
        Demand::new(LINGER)
    }
}

impl Demand {
    /// Demand that lasts `linger` after each API read.
    pub fn new(linger: Duration) -> Demand {
        Demand {
            state: Mutex::new(State::default()),
            wake: Condvar::new(),
            linger,
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn wanted(&self, s: &State) -> bool {
        s.clients > 0 || s.last_read.is_some_and(|t| t.elapsed() < self.linger)
    }

    /// A WebSocket client connected; the returned guard disconnects it when dropped.
    pub fn connect(&self) -> ClientGuard<'_> {
        self.lock().clients += 1;
        self.wake.notify_all();
        ClientGuard(self)
    }

    /// An API read: wakes the render thread. True when it was asleep (the current snapshot may
    /// be old; the caller waits for the next one).
    pub fn read(&self) -> bool {
        let mut s = self.lock();
        let asleep = !self.wanted(&s);
        s.last_read = Some(Instant::now());
        s.requested |= asleep;
        drop(s);
        if asleep {
            self.wake.notify_all();
        }
        asleep
    }

    /// Connected WebSocket clients.
    pub fn clients(&self) -> usize {
        self.lock().clients
    }

    /// For the render thread: at once while there is demand, else after sleeping until there is:
    /// `Some(requested)`, true when a read found the thread asleep since the last call (render
    /// the newest frame even if it was rendered before: the reader waits for a new snapshot);
    /// None once [`Demand::stop`] was called.
    pub fn wait(&self) -> Option<bool> {
        let mut s = self.lock();
        loop {
            if s.stopped {
                return None;
            }
            if s.requested || self.wanted(&s) {
                return Some(std::mem::take(&mut s.requested));
            }
            s = self.wake.wait(s).unwrap_or_else(PoisonError::into_inner);
        }
    }

    /// Ends every [`Demand::wait`] (the render thread stops).
    pub fn stop(&self) {
        self.lock().stopped = true;
        self.wake.notify_all();
    }
}

/// A connected WebSocket client; dropping it disconnects it.
#[derive(Debug)]
pub struct ClientGuard<'a>(&'a Demand);

impl Drop for ClientGuard<'_> {
    fn drop(&mut self) {
        let mut s = self.0.lock();
        s.clients = s.clients.saturating_sub(1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demand_follows_clients_and_reads_and_stop_ends_the_wait() {
        let d = Demand::new(Duration::ZERO);
        {
            let _c = d.connect();
            assert_eq!(d.clients(), 1);
            assert_eq!(d.wait(), Some(false), "a client is demand");
        }
        assert_eq!(d.clients(), 0);
        // With no linger a read wakes the thread once and is gone: the first read finds it
        // asleep, and so does the next.
        assert!(d.read());
        assert!(d.read());
        let d = Demand::new(Duration::from_secs(3600));
        assert!(d.read(), "asleep before the first read");
        assert!(!d.read(), "awake within the linger");
        assert_eq!(d.wait(), Some(true), "the first read asks for a render");
        assert_eq!(d.wait(), Some(false), "once");
        let d = Demand::new(Duration::ZERO);
        d.stop();
        assert_eq!(d.wait(), None, "stopped: no demand, no sleep");
    }
}
