//! Drive start-up as CANopen masters do it: NMT *enter pre-operational*, the device type check,
//! the SDO configuration (mode of operation, interpolation period, PDO mappings, heartbeat, the
//! entry's extra writes), the statusword read, and NMT *start* — for every drive, or for none.
//!
//! A `csp` drive also gets the homing PDOs: RPDO2 carries the touch probe function `60B8h`,
//! TPDO2 the touch probe status `60B9h` and the latched position `60BAh` (together, so that a
//! "stored" bit always comes with its value), TPDO3 the digital inputs `60FDh` (bit 2: the home
//! switch). `60FDh` does not fit TPDO2 as well: 16 + 32 + 32 bits exceed a classic CAN frame.
//!
//! [`configuration`] lists the SDO writes of one drive (pure, tested byte for byte);
//! [`start`] performs them on a bus. One failed transfer (a timeout or an abort) stops the start-up
//! with a [`DriveStartError`] naming the axis, the node, the object and the abort code: no drive is
//! started, so nothing can be enabled.

use std::time::Duration;

use super::super::transport::CanBus;
use super::super::{CanMsg, cob, nmt, sdo};
use crate::map::{CanDrive, DriveMode, SdoWrite};

/// Device profile number of CiA 402 (low 16 bits of object `1000h`).
pub const CIA_402: u32 = 402;

/// Why a drive did not start.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DriveStartError {
    /// An SDO transfer timed out or was aborted.
    #[error("drive of axis {axis} (node {node}): SDO {what} {index:04X}h/{subindex} {}", outcome(*.code))]
    Sdo {
        /// The axis.
        axis: char,
        /// The node id.
        node: u8,
        /// `write` or `read`.
        what: &'static str,
        /// Object index.
        index: u16,
        /// Sub-index.
        subindex: u8,
        /// The abort code; `None` when the drive did not answer.
        code: Option<u32>,
    },
    /// The node is not a CiA 402 device.
    #[error("drive of axis {axis} (node {node}): device type {device_type:08X}h is not a CiA 402 drive (profile {})", device_type & 0xFFFF)]
    NotCia402 {
        /// The axis.
        axis: char,
        /// The node id.
        node: u8,
        /// Object `1000h` as read.
        device_type: u32,
    },
    /// The bus failed.
    #[error("drive start-up: bus error: {0}")]
    Bus(String),
}

impl DriveStartError {
    /// The node the error is about (none for a bus error).
    pub fn node(&self) -> Option<u8> {
        match self {
            DriveStartError::Sdo { node, .. } | DriveStartError::NotCia402 { node, .. } => {
                Some(*node)
            }
            DriveStartError::Bus(_) => None,
        }
    }

    /// The error as a diagnostic on io.toml (code 3077) at `span` (the drive's entry): no drive
    /// was started.
    pub fn diagnostic(&self, span: std::ops::Range<usize>) -> diag::Diagnostic {
        diag::Diagnostic::error(crate::codes::DRIVE_START, "io.toml", span, self.to_string())
            .with_hint("no drive was started or enabled; check the node id and wiring, and the object in the drive's manual")
    }
}

fn outcome(code: Option<u32>) -> String {
    match code {
        None => "got no answer (timeout)".into(),
        Some(c) => format!("was aborted with code {c:08X}h ({})", abort_text(c)),
    }
}

/// The CiA 301 meaning of an SDO abort code.
pub fn abort_text(code: u32) -> &'static str {
    match code {
        0x0504_0001 => "command specifier not valid",
        0x0601_0000 => "unsupported access to an object",
        0x0601_0002 => "attempt to write a read-only object",
        0x0602_0000 => "object does not exist",
        0x0604_0041 => "object cannot be mapped to the PDO",
        0x0604_0042 => "mapped objects exceed the PDO length",
        0x0607_0010 => "data type does not match, length of service parameter does not match",
        0x0609_0011 => "sub-index does not exist",
        0x0609_0030 => "value range of parameter exceeded",
        0x0800_0000 => "general error",
        0x0800_0022 => "data cannot be transferred because of the present device state",
        _ => "see the drive's manual",
    }
}

fn w(index: u16, subindex: u8, value: u32, size: u8) -> SdoWrite {
    SdoWrite {
        index,
        subindex,
        value,
        size,
    }
}

/// Object `60C2h` for a tick: (value, exponent) with value · 10^exponent s = `tick`, the value
/// fitting a byte (sub 1 unsigned, sub 2 signed).
pub fn interpolation_period(tick: Duration) -> (u8, i8) {
    let us = tick.as_micros();
    for (exp, div) in [
        (-6i8, 1u128),
        (-5, 10),
        (-4, 100),
        (-3, 1000),
        (-2, 10_000),
        (-1, 100_000),
    ] {
        if us.is_multiple_of(div) && us / div <= 255 {
            return ((us / div) as u8, exp);
        }
    }
    ((us / 1_000_000).min(255) as u8, 0)
}

/// The SDO writes that configure `d` for an interpolation `tick`, in the order they are sent.
pub fn configuration(d: &CanDrive, tick: Duration) -> Vec<SdoWrite> {
    let id = u32::from(d.node_id);
    let (target, actual) = match d.mode {
        DriveMode::Csp => (0x607A_0020, 0x6064_0020),
        DriveMode::Csv => (0x60FF_0020, 0x606C_0020),
    };
    let (period, exp) = interpolation_period(tick);
    let mut list = vec![
        w(0x6060, 0, u32::from(d.mode.code() as u8), 1),
        w(0x60C2, 1, u32::from(period), 1),
        w(0x60C2, 2, u32::from(exp as u8), 1),
        // RPDO1: disable, every SYNC, map controlword + target, enable.
        w(0x1400, 1, 0x8000_0000 | (u32::from(cob::RPDO1) + id), 4),
        w(0x1400, 2, 1, 1),
        w(0x1600, 0, 0, 1),
        w(0x1600, 1, 0x6040_0010, 4),
        w(0x1600, 2, target, 4),
        w(0x1600, 0, 2, 1),
        w(0x1400, 1, u32::from(cob::RPDO1) + id, 4),
        // TPDO1: disable, every SYNC, map statusword + actual value, enable.
        w(0x1800, 1, 0x8000_0000 | (u32::from(cob::TPDO1) + id), 4),
        w(0x1800, 2, 1, 1),
        w(0x1A00, 0, 0, 1),
        w(0x1A00, 1, 0x6041_0010, 4),
        w(0x1A00, 2, actual, 4),
        w(0x1A00, 0, 2, 1),
        w(0x1800, 1, u32::from(cob::TPDO1) + id, 4),
    ];
    if d.mode == DriveMode::Csp && d.homing {
        list.extend(homing_pdos(id));
    }
    list.extend([
        // Heartbeat producer.
        w(
            0x1017,
            0,
            d.heartbeat.as_millis().min(u128::from(u16::MAX)) as u32,
            2,
        ),
    ]);
    list.extend(d.sdo.iter().copied());
    list
}

/// The homing PDOs of a `csp` drive with node id `id`: RPDO2 = `60B8h` touch probe function;
/// TPDO2 = `60B9h` touch probe status + `60BAh` touch probe 1 positive edge position; TPDO3 =
/// `60FDh` digital inputs; every SYNC, each disabled while mapped and enabled after.
pub fn homing_pdos(id: u32) -> Vec<SdoWrite> {
    let mut list = Vec::new();
    let pdos: [(u16, u16, u32, &[u32]); 3] = [
        (0x1401, 0x1601, u32::from(cob::rpdo(2, 0)), &[0x60B8_0010]),
        (
            0x1801,
            0x1A01,
            u32::from(cob::tpdo(2, 0)),
            &[0x60B9_0010, 0x60BA_0020],
        ),
        (0x1802, 0x1A02, u32::from(cob::tpdo(3, 0)), &[0x60FD_0020]),
    ];
    for (comm, map, base, entries) in pdos {
        list.push(w(comm, 1, 0x8000_0000 | (base + id), 4));
        list.push(w(comm, 2, 1, 1));
        list.push(w(map, 0, 0, 1));
        for (k, e) in entries.iter().enumerate() {
            list.push(w(map, k as u8 + 1, *e, 4));
        }
        list.push(w(map, 0, entries.len() as u32, 1));
        list.push(w(comm, 1, base + id, 4));
    }
    list
}

/// Starts `drives` on `bus`: pre-operational, configuration, statusword read, then NMT start of
/// every drive; returns the statusword of each (in order). Frames of other kinds that arrive
/// meanwhile go to `other`. On the first failure no drive is started.
pub async fn start<B: CanBus>(
    bus: &mut B,
    drives: &[CanDrive],
    tick: Duration,
    timeout: Duration,
    other: &mut impl FnMut(&CanMsg),
) -> Result<Vec<u16>, DriveStartError> {
    let bus_err = |e: std::io::Error| DriveStartError::Bus(e.to_string());
    for d in drives {
        bus.send(&CanMsg::new(
            cob::NMT,
            &[nmt::CMD_PRE_OPERATIONAL, d.node_id],
        ))
        .await
        .map_err(bus_err)?;
    }
    let mut statuswords = Vec::with_capacity(drives.len());
    for d in drives {
        let fail = |what, e: sdo::SdoError| match e {
            sdo::SdoError::Timeout { index, subindex } => DriveStartError::Sdo {
                axis: d.axis,
                node: d.node_id,
                what,
                index,
                subindex,
                code: None,
            },
            sdo::SdoError::Abort {
                index,
                subindex,
                code,
            } => DriveStartError::Sdo {
                axis: d.axis,
                node: d.node_id,
                what,
                index,
                subindex,
                code: Some(code),
            },
            other => DriveStartError::Bus(other.to_string()),
        };
        let (device_type, _) = sdo::upload(bus, d.node_id, 0x1000, 0, timeout, other)
            .await
            .map_err(|e| fail("read", e))?;
        if device_type & 0xFFFF != CIA_402 {
            return Err(DriveStartError::NotCia402 {
                axis: d.axis,
                node: d.node_id,
                device_type,
            });
        }
        for wr in configuration(d, tick) {
            sdo::download(bus, d.node_id, &wr, timeout, other)
                .await
                .map_err(|e| fail("write", e))?;
        }
        let (sw, _) = sdo::upload(bus, d.node_id, 0x6041, 0, timeout, other)
            .await
            .map_err(|e| fail("read", e))?;
        statuswords.push(sw as u16);
    }
    for d in drives {
        bus.send(&CanMsg::new(cob::NMT, &[nmt::CMD_START, d.node_id]))
            .await
            .map_err(bus_err)?;
    }
    Ok(statuswords)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_interpolation_period_is_the_tick_in_the_finest_unit_that_fits_a_byte() {
        assert_eq!(interpolation_period(Duration::from_millis(10)), (100, -4));
        assert_eq!(interpolation_period(Duration::from_millis(1)), (100, -5));
        assert_eq!(interpolation_period(Duration::from_micros(250)), (250, -6));
        assert_eq!(interpolation_period(Duration::from_millis(40)), (40, -3));
        assert_eq!(interpolation_period(Duration::from_millis(2)), (200, -5));
    }

    #[test]
    fn a_csv_drive_maps_the_velocities() {
        let d = CanDrive {
            process: 1,
            axis: 'S',
            node_id: 5,
            counts_per_unit: 4096.0,
            mode: DriveMode::Csv,
            heartbeat: Duration::from_millis(50),
            sdo: vec![w(0x2000, 1, 7, 1)],
            simulate: Default::default(),
            span: 0..0,
            homing: true,
        };
        let c = configuration(&d, Duration::from_millis(4));
        assert_eq!(c[0], w(0x6060, 0, 9, 1));
        assert_eq!((c[1].value, c[2].value), (40, 0xFC));
        assert_eq!(c[3], w(0x1400, 1, 0x8000_0205, 4));
        assert_eq!(c[7], w(0x1600, 2, 0x60FF_0020, 4));
        assert_eq!(c[9], w(0x1400, 1, 0x205, 4));
        assert_eq!(c[14], w(0x1A00, 2, 0x606C_0020, 4));
        assert_eq!(c[16], w(0x1800, 1, 0x185, 4));
        assert_eq!(c[17], w(0x1017, 0, 50, 2));
        assert_eq!(c[18], w(0x2000, 1, 7, 1));
        assert_eq!(c.len(), 19);
    }

    #[test]
    fn a_csp_drive_gets_the_homing_pdos_before_its_heartbeat() {
        let d = CanDrive {
            process: 1,
            axis: 'X',
            node_id: 3,
            counts_per_unit: 10000.0,
            mode: DriveMode::Csp,
            heartbeat: Duration::from_millis(100),
            sdo: Vec::new(),
            simulate: Default::default(),
            span: 0..0,
            homing: true,
        };
        let c = configuration(&d, Duration::from_millis(2));
        let homing = [
            w(0x1401, 1, 0x8000_0303, 4),
            w(0x1401, 2, 1, 1),
            w(0x1601, 0, 0, 1),
            w(0x1601, 1, 0x60B8_0010, 4),
            w(0x1601, 0, 1, 1),
            w(0x1401, 1, 0x303, 4),
            w(0x1801, 1, 0x8000_0283, 4),
            w(0x1801, 2, 1, 1),
            w(0x1A01, 0, 0, 1),
            w(0x1A01, 1, 0x60B9_0010, 4),
            w(0x1A01, 2, 0x60BA_0020, 4),
            w(0x1A01, 0, 2, 1),
            w(0x1801, 1, 0x283, 4),
            w(0x1802, 1, 0x8000_0383, 4),
            w(0x1802, 2, 1, 1),
            w(0x1A02, 0, 0, 1),
            w(0x1A02, 1, 0x60FD_0020, 4),
            w(0x1A02, 0, 1, 1),
            w(0x1802, 1, 0x383, 4),
        ];
        assert_eq!(c[17..36], homing);
        assert_eq!(c[36], w(0x1017, 0, 100, 2));
        assert_eq!(c.len(), 37);
        // The same drive of an axis without MCZ (an absolute encoder): no homing objects are
        // touched, the heartbeat follows PDO1 at once.
        let c = configuration(
            &CanDrive {
                homing: false,
                ..d.clone()
            },
            Duration::from_millis(2),
        );
        assert_eq!(c[17], w(0x1017, 0, 100, 2));
        assert_eq!(c.len(), 18);
        assert!(
            c.iter()
                .all(|x| !matches!(x.index, 0x1401 | 0x1601 | 0x1801 | 0x1A01 | 0x1802 | 0x1A02))
        );
    }
}
