//! [`CanBus`] over a Linux SocketCAN interface (`can0`, `vcan0`) with the `socketcan` crate.
//!
//! Classic CAN frames only; error frames are skipped. Kernels without CAN (`AF_CAN` missing) fail
//! cleanly at [`SocketCanBus::open`] with the operating system's error.

use std::io;

use socketcan::{EmbeddedFrame, ExtendedId, Id, StandardId};

use super::transport::CanBus;
use super::{CanMsg, MAX_DATA};

/// A SocketCAN interface opened for the tokio runtime.
pub struct SocketCanBus {
    socket: socketcan::tokio::CanSocket,
}

impl SocketCanBus {
    /// Opens interface `ifname`; must be called inside a tokio runtime.
    pub fn open(ifname: &str) -> io::Result<SocketCanBus> {
        Ok(SocketCanBus {
            socket: socketcan::tokio::CanSocket::open(ifname)?,
        })
    }
}

fn to_frame(m: &CanMsg) -> io::Result<socketcan::CanFrame> {
    let id: Id = if m.extended {
        ExtendedId::new(m.id).map(Id::Extended).ok_or_else(|| {
            io::Error::new(io::ErrorKind::InvalidInput, "extended id out of range")
        })?
    } else {
        StandardId::new(m.id as u16)
            .map(Id::Standard)
            .ok_or_else(|| {
                io::Error::new(io::ErrorKind::InvalidInput, "standard id out of range")
            })?
    };
    let frame = if m.rtr {
        socketcan::CanFrame::new_remote(id, usize::from(m.len))
    } else {
        socketcan::CanFrame::new(id, m.payload())
    };
    frame.ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            "frame does not fit classic CAN",
        )
    })
}

fn from_frame(f: &socketcan::CanFrame) -> CanMsg {
    let (id, extended) = match f.id() {
        Id::Standard(s) => (u32::from(s.as_raw()), false),
        Id::Extended(e) => (e.as_raw(), true),
    };
    let mut data = [0u8; MAX_DATA];
    let bytes = f.data();
    let n = bytes.len().min(8);
    data[..n].copy_from_slice(&bytes[..n]);
    CanMsg {
        id,
        extended,
        rtr: f.is_remote_frame(),
        fd: false,
        len: if f.is_remote_frame() {
            f.dlc() as u8
        } else {
            n as u8
        },
        data,
    }
}

impl CanBus for SocketCanBus {
    async fn send(&mut self, msg: &CanMsg) -> io::Result<()> {
        self.socket.write_frame(to_frame(msg)?).await
    }

    async fn recv(&mut self) -> io::Result<CanMsg> {
        loop {
            let f = self.socket.read_frame().await?;
            if !matches!(f, socketcan::CanFrame::Error(_)) {
                return Ok(from_frame(&f));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_convert_both_ways() {
        let m = CanMsg::new(0x201, &[1, 2, 3]);
        let back = from_frame(&to_frame(&m).expect("fits"));
        assert_eq!(back, m);
        let ext = CanMsg {
            id: 0x1234567,
            extended: true,
            ..CanMsg::new(0, &[9])
        };
        assert_eq!(from_frame(&to_frame(&ext).expect("fits")), ext);
    }

    #[test]
    fn opening_a_missing_interface_is_an_error_not_a_panic() {
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .expect("runtime");
        let _guard = rt.enter();
        assert!(SocketCanBus::open("ncplc-no-such-can").is_err());
    }
}
