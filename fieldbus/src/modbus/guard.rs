//! The Modbus HMI server's limits on what one client may cost: a cap on open connections
//! ([`Places`]), requests per second per connection ([`Rate`]) and an idle timeout on each
//! connection ([`Guarded`]: no request byte for that long closes it, so a half-open connection
//! or a client that stops in the middle of a frame gives its place back). [`Guarded`] also hands
//! the request bytes on through a [`Screen`] (whole frames with counts in the protocol's ranges).
//!
//! Invariant: nothing here blocks or waits on the scan; a refused connection is closed at once,
//! a request over the rate is answered with exception 06 (server device busy) and not served.

use std::future::Future;
use std::io;
use std::pin::Pin;
use std::sync::Arc;
use std::task::{Context, Poll};
use std::time::Duration;

use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::net::TcpStream;
use tokio::sync::{OwnedSemaphorePermit, Semaphore};
use tokio::time::{Instant, Sleep};

use super::screen::Screen;

/// The open connections a server allows.
#[derive(Debug, Clone)]
pub struct Places(Arc<Semaphore>);

impl Places {
    /// Room for `n` connections.
    pub fn new(n: usize) -> Places {
        Places(Arc::new(Semaphore::new(n)))
    }

    /// A place for one more connection, if there is one.
    pub fn take(&self) -> Option<OwnedSemaphorePermit> {
        self.0.clone().try_acquire_owned().ok()
    }
}

/// A client connection that holds its place until it closes and fails a read after `idle`
/// without a byte from the client.
pub struct Guarded {
    stream: TcpStream,
    idle: Duration,
    deadline: Pin<Box<Sleep>>,
    screen: Screen,
    _place: OwnedSemaphorePermit,
}

impl Guarded {
    /// Wraps `stream` (inside a tokio runtime).
    pub fn new(stream: TcpStream, idle: Duration, place: OwnedSemaphorePermit) -> Guarded {
        Guarded {
            stream,
            idle,
            deadline: Box::pin(tokio::time::sleep(idle)),
            screen: Screen::new(),
            _place: place,
        }
    }
}

impl AsyncRead for Guarded {
    fn poll_read(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        let this = &mut *self;
        loop {
            if this.screen.has_ready() {
                let n = this.screen.take(buf.initialize_unfilled());
                buf.advance(n);
                return Poll::Ready(Ok(()));
            }
            let mut chunk = [0u8; 512];
            let mut read = ReadBuf::new(&mut chunk);
            match Pin::new(&mut this.stream).poll_read(cx, &mut read) {
                Poll::Ready(Ok(())) => {
                    let idle = this.idle;
                    this.deadline.as_mut().reset(Instant::now() + idle);
                    if read.filled().is_empty() {
                        // End of stream: a partial frame held back is dropped with it.
                        return Poll::Ready(Ok(()));
                    }
                    if let Err(e) = this.screen.push(read.filled()) {
                        return Poll::Ready(Err(io::Error::new(io::ErrorKind::InvalidData, e)));
                    }
                }
                Poll::Ready(Err(e)) => return Poll::Ready(Err(e)),
                Poll::Pending if this.deadline.as_mut().poll(cx).is_ready() => {
                    return Poll::Ready(Err(io::Error::new(
                        io::ErrorKind::TimedOut,
                        "idle Modbus connection closed",
                    )));
                }
                Poll::Pending => return Poll::Pending,
            }
        }
    }
}

impl AsyncWrite for Guarded {
    fn poll_write(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.stream).poll_write(cx, buf)
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.stream).poll_flush(cx)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.stream).poll_shutdown(cx)
    }
}

/// Counts one connection's requests in one-second windows.
#[derive(Debug)]
pub struct Rate {
    limit: u32,
    window: std::time::Instant,
    count: u32,
}

impl Rate {
    /// A counter allowing `limit` requests per second.
    pub fn new(limit: u32, now: std::time::Instant) -> Rate {
        Rate {
            limit,
            window: now,
            count: 0,
        }
    }

    /// Counts one request at `now`; false when it is over the limit of its window.
    pub fn hit(&mut self, now: std::time::Instant) -> bool {
        if now.duration_since(self.window) >= Duration::from_secs(1) {
            self.window = now;
            self.count = 0;
        }
        self.count = self.count.saturating_add(1);
        self.count <= self.limit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rate_allows_its_limit_per_second_window() {
        let t0 = std::time::Instant::now();
        let mut r = Rate::new(2, t0);
        assert!(r.hit(t0));
        assert!(r.hit(t0 + Duration::from_millis(500)));
        assert!(!r.hit(t0 + Duration::from_millis(999)));
        assert!(r.hit(t0 + Duration::from_secs(1)));
    }

    #[test]
    fn places_run_out_and_come_back() {
        let p = Places::new(2);
        let a = p.take().expect("first");
        let _b = p.take().expect("second");
        assert!(p.take().is_none());
        drop(a);
        assert!(p.take().is_some());
    }
}
