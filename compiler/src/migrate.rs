//! Online change: carry the state of a running program over to its new version.

use std::collections::HashMap;

use crate::ir::{HDR_FAULTS, Program, SlotKind, Ty};

/// Copies the packets, the fault flags and every state slot whose name (ASCII case-insensitive, as
/// in the language), kind, type and length are unchanged from `old_image` (laid out for `old`) into `new_image` (laid out for `new`). Slots
/// that are new or changed keep what `new_image` holds (normally the new program's initial
/// values); the SLOW slice index restarts at 0. Out-of-range slots are skipped, never a panic.
pub fn migrate_state(old: &Program, old_image: &[u8], new: &Program, new_image: &mut [u8]) {
    let n = packets::PACKETS_LEN
        .min(old_image.len())
        .min(new_image.len());
    new_image[..n].copy_from_slice(&old_image[..n]);
    if let (Some(src), Some(dst)) = (
        old_image.get(HDR_FAULTS..HDR_FAULTS + 4),
        new_image.get_mut(HDR_FAULTS..HDR_FAULTS + 4),
    ) {
        dst.copy_from_slice(src);
    }
    if let Some(dst) = new_image.get_mut(crate::ir::HDR_NEXT_SLICE..crate::ir::HDR_NEXT_SLICE + 4) {
        dst.fill(0);
    }
    let old_slots: HashMap<(String, SlotKind), (Ty, usize, usize)> = old
        .state_slots()
        .into_iter()
        .map(|s| {
            (
                (s.name.to_ascii_uppercase(), s.kind),
                (s.ty, s.offset, s.len),
            )
        })
        .collect();
    for s in new.state_slots() {
        let Some(&(ty, offset, len)) = old_slots.get(&(s.name.to_ascii_uppercase(), s.kind)) else {
            continue;
        };
        if ty != s.ty || len != s.len {
            continue;
        }
        if let (Some(src), Some(dst)) = (
            old_image.get(offset..offset + len),
            new_image.get_mut(s.offset..s.offset + len),
        ) {
            dst.copy_from_slice(src);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::{ProgramBuilder, TimerKind, Value};

    #[test]
    fn unchanged_slots_move_and_changed_ones_restart() {
        let mut b = ProgramBuilder::new(10, 5);
        b.var("count", Ty::Dint, None, false);
        b.var("mode", Ty::Byte, None, false);
        b.timer("t", TimerKind::Ton, 100);
        let old = b.finish(vec![], vec![]).expect("valid");
        let mut old_image = old.new_image();
        old_image[130] = 0x5A;
        old_image[old.vars[0].offset..old.vars[0].offset + 4].copy_from_slice(&77i32.to_le_bytes());
        old_image[old.vars[1].offset] = 3;
        old_image[old.timers[0].offset] = 40;

        let mut b = ProgramBuilder::new(10, 5);
        b.timer("t", TimerKind::Ton, 200);
        b.var("mode", Ty::Word, Some(Value::Word(9)), false);
        b.var("COUNT", Ty::Dint, None, false);
        let new = b.finish(vec![], vec![]).expect("valid");
        let mut new_image = new.new_image();
        migrate_state(&old, &old_image, &new, &mut new_image);
        assert_eq!(new_image[130], 0x5A);
        let at = new.vars[1].offset;
        assert_eq!(
            i32::from_le_bytes(new_image[at..at + 4].try_into().expect("4")),
            77
        );
        let at = new.vars[0].offset;
        assert_eq!(
            &new_image[at..at + 2],
            &[9, 0],
            "a changed type restarts from the initial value"
        );
        assert_eq!(new_image[new.timers[0].offset], 40);
    }
}
