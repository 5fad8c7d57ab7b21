//! What every driver does with packet A at a tick boundary: latch a device's inputs (with its
//! health, fail values and healthy bit) and find the outputs the logic changed. The Modbus client and
//! the CANopen master share these so that every bus treats inputs, lost devices and outputs alike.

use packets::IoAlarm;

use crate::exchange::MAX_PENDING_ALARMS;
use crate::health::{Fault, Health};
use crate::map::ByteRange;

/// Bytes in packet A, the part of the image the drivers exchange.
pub const A_LEN: usize = packets::Packet::A.len();

/// Latches one device's inputs into the packets at the start of a tick: advances its health with
/// the newest frame (`seq`, `fault`), copies each mapped input range from `data` while the device is
/// healthy or fills it with its fail value otherwise, and writes the device's healthy bit. Returns
/// the alarm to raise or clear, if the device's state changed. Shared by every driver so that all
/// buses treat a lost device the same way.
pub fn latch_device(
    health: &mut Health,
    seq: u64,
    fault: Fault,
    data: &[u8],
    inputs: impl Iterator<Item = (ByteRange, u8)>,
    healthy_bit: Option<packets::Signal>,
    packets: &mut [u8],
) -> Option<IoAlarm> {
    let alarm = health.tick(seq, fault);
    let healthy = health.healthy();
    for (range, fail) in inputs {
        let (s, e) = (range.start, range.end());
        if let Some(dst) = packets.get_mut(s..e) {
            match data.get(s..e) {
                Some(src) if healthy => dst.copy_from_slice(src),
                _ => dst.fill(fail),
            }
        }
    }
    if let Some(bit) = healthy_bit {
        bit.write(packets, u8::from(healthy));
    }
    alarm
}

/// Queues `alarm` for the runtime's next `take_alarms`, dropping it when
/// [`MAX_PENDING_ALARMS`] are already pending (a runtime that never takes them must not grow memory).
pub fn queue_alarm(pending: &mut Vec<IoAlarm>, alarm: Option<IoAlarm>) {
    if let Some(a) = alarm
        && pending.len() < MAX_PENDING_ALARMS
    {
        pending.push(a);
    }
}

/// The packet-A image that commands each output range's safe value (zero elsewhere).
pub fn safe_image(outputs: impl Iterator<Item = (ByteRange, u8)>) -> [u8; A_LEN] {
    let mut image = [0u8; A_LEN];
    for (range, safe) in outputs {
        if let Some(dst) = image.get_mut(range.start..range.end()) {
            dst.fill(safe);
        }
    }
    image
}

/// Copies the output ranges of `packets` that differ from `last` into `last`; true when any did.
pub fn take_changed_outputs(
    ranges: impl Iterator<Item = ByteRange>,
    packets: &[u8],
    last: &mut [u8],
) -> bool {
    let mut changed = false;
    for range in ranges {
        let (s, e) = (range.start, range.end());
        if let (Some(src), Some(dst)) = (packets.get(s..e), last.get_mut(s..e))
            && src != dst
        {
            dst.copy_from_slice(src);
            changed = true;
        }
    }
    changed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_changed_ranges_are_taken() {
        let mut last = [0u8; 8];
        let mut packets = [0u8; 8];
        let ranges = [
            ByteRange { start: 0, len: 2 },
            ByteRange { start: 4, len: 2 },
        ];
        assert!(!take_changed_outputs(
            ranges.iter().copied(),
            &packets,
            &mut last
        ));
        packets[5] = 7;
        packets[3] = 9; // outside every range: never taken
        assert!(take_changed_outputs(
            ranges.iter().copied(),
            &packets,
            &mut last
        ));
        assert_eq!(last, [0, 0, 0, 0, 0, 7, 0, 0]);
        assert!(!take_changed_outputs(
            ranges.iter().copied(),
            &packets,
            &mut last
        ));
    }

    #[test]
    fn the_safe_image_fills_only_the_output_ranges() {
        let outputs = [
            (ByteRange { start: 16, len: 2 }, 0xAA),
            (ByteRange { start: 20, len: 1 }, 1),
        ];
        let image = safe_image(outputs.into_iter());
        assert_eq!(&image[15..22], &[0, 0xAA, 0xAA, 0, 0, 1, 0]);
        assert_eq!(image.iter().filter(|&&b| b != 0).count(), 3);
    }
}
