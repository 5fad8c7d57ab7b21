//! An in-process virtual CAN bus: every frame one port sends reaches every other port.
//!
//! Used by the tests (a master and simulated nodes in one process) and by the `virtual` transport.
//! Delivery is in send order per sender and never blocks (unbounded channels).

use std::io;
use std::sync::{Arc, Mutex};

use tokio::sync::mpsc;

use super::CanMsg;
use super::transport::CanBus;

type Ports = Arc<Mutex<Vec<(usize, mpsc::UnboundedSender<CanMsg>)>>>;

/// The bus: hands out ports.
#[derive(Clone, Default)]
pub struct VirtualBus {
    ports: Ports,
    next: Arc<Mutex<usize>>,
}

/// One node's connection to a [`VirtualBus`].
pub struct VirtualPort {
    id: usize,
    ports: Ports,
    rx: mpsc::UnboundedReceiver<CanMsg>,
}

impl VirtualBus {
    /// An empty bus.
    pub fn new() -> VirtualBus {
        VirtualBus::default()
    }

    /// Connects a new port.
    pub fn port(&self) -> VirtualPort {
        let (tx, rx) = mpsc::unbounded_channel();
        let id = {
            let mut n = self
                .next
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            *n += 1;
            *n
        };
        self.ports
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .push((id, tx));
        VirtualPort {
            id,
            ports: self.ports.clone(),
            rx,
        }
    }
}

impl Drop for VirtualPort {
    fn drop(&mut self) {
        if let Ok(mut p) = self.ports.lock() {
            p.retain(|(id, _)| *id != self.id);
        }
    }
}

impl CanBus for VirtualPort {
    async fn send(&mut self, msg: &CanMsg) -> io::Result<()> {
        let ports = self
            .ports
            .lock()
            .map_err(|_| io::Error::other("virtual bus poisoned"))?;
        for (id, tx) in ports.iter() {
            if *id != self.id {
                // A port whose receiver is gone is being dropped; skip it.
                let _ = tx.send(*msg);
            }
        }
        Ok(())
    }

    async fn recv(&mut self) -> io::Result<CanMsg> {
        self.rx
            .recv()
            .await
            .ok_or_else(|| io::Error::new(io::ErrorKind::BrokenPipe, "virtual bus closed"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn a_frame_reaches_every_other_port_but_not_the_sender() {
        let bus = VirtualBus::new();
        let (mut a, mut b, mut c) = (bus.port(), bus.port(), bus.port());
        a.send(&CanMsg::new(0x181, &[1, 2])).await.expect("send");
        assert_eq!(b.recv().await.expect("b").payload(), &[1, 2]);
        assert_eq!(c.recv().await.expect("c").id, 0x181);
        assert!(a.rx.try_recv().is_err());
        drop(c);
        b.send(&CanMsg::new(0x80, &[]))
            .await
            .expect("send after drop");
        assert_eq!(a.recv().await.expect("a").id, 0x80);
    }
}
