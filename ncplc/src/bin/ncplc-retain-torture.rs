//! Test helper: saves retain records as fast as it can until killed, so that a test can SIGKILL it
//! at random moments and check that every restore is a complete earlier record.
//!
//! Usage: `ncplc-retain-torture FILE`. At start it loads FILE (exit 3 if damaged) and continues
//! the sequence from the record found. Record `seq` holds [`runtime::retain`]-encoded bytes that
//! are a pure function of `seq` ([`pattern`]), so the test can verify any record it finds.

use std::path::PathBuf;
use std::process::ExitCode;

use runtime::retain::{self, RetainRecord};

/// The record number `seq` (16 KiB of retain data, all derived from `seq`).
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

fn main() -> ExitCode {
    let Some(path) = std::env::args_os().nth(1).map(PathBuf::from) else {
        eprintln!("usage: ncplc-retain-torture FILE");
        return ExitCode::from(2);
    };
    let mut seq = match retain::load(&path) {
        Ok(Some(r)) if r == pattern(r.seq) => r.seq,
        Ok(Some(r)) => {
            eprintln!("record {} is not the record that was written", r.seq);
            return ExitCode::from(3);
        }
        Ok(None) => 0,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(3);
        }
    };
    loop {
        seq += 1;
        if let Err(e) = retain::save(&path, &pattern(seq)) {
            eprintln!("{e}");
            return ExitCode::from(4);
        }
    }
}
