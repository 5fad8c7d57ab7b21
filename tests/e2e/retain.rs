//! Retain writes survive `kill -9`: a helper saves records in a loop; we SIGKILL it at random
//! moments many times, and every restore must be a complete record, never older than the last one.

use std::process::{Command, Stdio};
use std::time::Duration;

use runtime::retain::{self, RetainRecord};

/// Must match the helper's record for `seq`.
fn pattern(seq: u64) -> RetainRecord {
    RetainRecord {
        seq,
        muspe: seq.is_multiple_of(2),
        t_bytes: (0..64u64)
            .map(|i| (seq.wrapping_mul(7) + i) as u8)
            .collect(),
        layout: seq ^ 0x5a5a,
        retain: (0..16_384u64)
            .map(|i| (seq.wrapping_mul(31) + i) as u8)
            .collect(),
    }
}

#[test]
fn sigkill_during_retain_writes_never_leaves_a_partial_record() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("retain.bin");
    let mut rng: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut last_seq = 0u64;
    let mut advanced = 0;
    for round in 0..40 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_ncplc-retain-torture"))
            .arg(&path)
            .stderr(Stdio::piped())
            .spawn()
            .expect("helper starts");
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        std::thread::sleep(Duration::from_micros(5_000 + rng % 40_000));
        child.kill().expect("SIGKILL");
        let out = child.wait_with_output().expect("wait");
        assert!(
            out.status.code().is_none(),
            "round {round}: helper exited by itself: {:?} {}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
        match retain::load(&path).expect("a complete record after every kill") {
            Some(rec) => {
                assert_eq!(
                    rec,
                    pattern(rec.seq),
                    "round {round}: record {} is not what was written",
                    rec.seq
                );
                assert!(
                    rec.seq >= last_seq,
                    "round {round}: went back from {last_seq} to {}",
                    rec.seq
                );
                if rec.seq > last_seq {
                    advanced += 1;
                }
                last_seq = rec.seq;
            }
            None => assert_eq!(last_seq, 0, "round {round}: the record disappeared"),
        }
    }
    assert!(
        advanced >= 10,
        "the helper made progress in only {advanced} of 40 rounds"
    );
}
