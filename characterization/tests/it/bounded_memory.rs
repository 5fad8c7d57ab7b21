//! Bounded memory on error-dense input (issue 23, item 4), asserted on what is kept, not timed:
//! a capped load keeps exactly `max` diagnostics of a file and counts the rest exactly; the reader
//! keeps at most `MAX_RECORDS` records (error 973) and reads at most `MAX_BYTES` of a file (974).
//! The inputs are those of `tests/gen/error_dense.py`: the lathe's AXCFIL followed by pairs
//! `NAS=X` / `QZQ<n>=1` in section 3, each pair three errors (173 no PAS and 175 no values on the
//! `NAS` line, 6 the unknown instruction on the next).

use std::fs;
use std::path::{Path, PathBuf};

use characterization::reader::{self, Grammar, MAX_BYTES, MAX_RECORDS};
use characterization::{load_machine, load_machine_capped};
use diag::{Hidden, Sink};

fn lathe() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe")
}

/// A copy of the lathe's characterization files whose AXCFIL ends with `pairs` error-dense pairs;
/// returns the directory and the line of the first `NAS=X`.
fn dense_lathe(pairs: usize) -> (tempfile::TempDir, u32) {
    dense_copy("AXCFIL", pairs, |i| format!("NAS=X\nQZQ{}=1\n", i % 10))
}

/// A copy of the lathe's characterization files whose MP0 file `name` ends with `pairs` pairs of
/// lines `pair(k)`; returns the directory and the line of the first pair.
fn dense_copy(
    name: &str,
    pairs: usize,
    pair: impl Fn(usize) -> String,
) -> (tempfile::TempDir, u32) {
    let dir = tempfile::tempdir().expect("temp dir");
    fs::create_dir_all(dir.path().join("MP0")).expect("mkdir");
    fs::copy(lathe().join("FCRSYS"), dir.path().join("FCRSYS")).expect("FCRSYS");
    for f in ["AXCFIL", "PGCFIL", "IOCFIL", "PLCPRG", "MESSAG"] {
        fs::copy(lathe().join("MP0").join(f), dir.path().join("MP0").join(f)).expect("copy");
    }
    // Bytes: the lathe's comments are CP866.
    let mut text = fs::read(lathe().join("MP0").join(name)).expect("lathe file");
    while text.last() == Some(&b'\n') {
        text.pop();
    }
    text.push(b'\n');
    let first = text.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
    for i in 0..pairs {
        text.extend_from_slice(pair(i).as_bytes());
    }
    fs::write(dir.path().join("MP0").join(name), text).expect("write");
    (dir, first)
}

/// The PGCFIL and IOCFIL validators push into the file's capped sink as AXCFIL's do: pairs of a
/// duplicated instruction (101) and one the section does not allow (6), two errors per pair.
#[test]
fn capped_pgcfil_and_iocfil_loads_keep_exactly_max_diagnostics_and_count_the_rest() {
    let pairs = 20_000;
    for (name, pair) in [
        (
            "PGCFIL",
            (|i| format!("MAS=XZ\nQZQ{}=1\n", i % 10)) as fn(usize) -> String,
        ),
        ("IOCFIL", |i| format!("T01=10\nQZQ{}=1\n", i % 10)),
    ] {
        let (dir, first) = dense_copy(name, pairs, pair);
        let file = format!("MP0/{name}");
        let load = load_machine_capped(dir.path(), 100);
        assert_eq!(load.diagnostics.len(), 100, "{name}");
        assert!(load.diagnostics.iter().all(|d| d.file == file), "{name}");
        assert_eq!(
            load.hidden,
            [Hidden {
                file: file.clone(),
                errors: 2 * pairs - 100,
                warnings: 0
            }]
        );
        // Pair k (from 0) is lines first+2k (101) and first+2k+1 (6): the 100th kept is the 6
        // of pair 49.
        let at = |i: usize| {
            let d = &load.diagnostics[i];
            (d.code, d.line, d.column)
        };
        assert_eq!(
            [at(0), at(1), at(2), at(99)],
            [
                (101, first, 1),
                (6, first + 1, 1),
                (101, first + 2, 1),
                (6, first + 99, 1)
            ],
            "{name}"
        );
        let all = load_machine(dir.path());
        assert_eq!(all.diagnostics.len(), 2 * pairs, "{name}");
        assert_eq!(all.diagnostics[..100], load.diagnostics[..], "{name}");
    }
}

#[test]
fn a_capped_load_keeps_exactly_max_diagnostics_and_counts_the_rest() {
    let pairs = 20_000;
    let (dir, first) = dense_lathe(pairs);
    let load = load_machine_capped(dir.path(), 100);
    assert_eq!(load.diagnostics.len(), 100);
    assert!(load.diagnostics.iter().all(|d| d.file == "MP0/AXCFIL"));
    assert_eq!(
        load.hidden,
        [Hidden {
            file: "MP0/AXCFIL".into(),
            errors: 3 * pairs - 100,
            warnings: 0
        }]
    );
    assert!(load.has_errors());
    // In source order: pair k (from 0) is lines first+2k (173, 175) and first+2k+1 (6); the
    // 100th kept is the 173 of pair 33.
    let at = |i: usize| {
        let d = &load.diagnostics[i];
        (d.code, d.line)
    };
    assert_eq!(
        [at(0), at(1), at(2)],
        [(173, first), (175, first), (6, first + 1)]
    );
    assert_eq!(at(99), (173, first + 66));
    // What an uncapped load prints first is what the capped one kept.
    let all = load_machine(dir.path());
    assert_eq!(all.diagnostics.len(), 3 * pairs);
    assert!(all.hidden.is_empty());
    assert_eq!(all.diagnostics[..100], load.diagnostics[..]);
}

#[test]
fn the_reader_keeps_at_most_max_records_and_stops_with_973() {
    let mut text = String::from("*1\n");
    for _ in 0..=MAX_RECORDS {
        text.push_str("QZQ=1\n");
    }
    let mut sink = Sink::new(10);
    let f = reader::read_into("AXCFIL", text.into_bytes(), Grammar::FUNCTIONAL, &mut sink);
    assert!(f.abandoned);
    let records: usize = f.sections.iter().map(|s| s.records.len()).sum();
    assert_eq!(records, MAX_RECORDS);
    let (d, hidden) = sink.finish();
    assert!(hidden.is_empty());
    let got: Vec<(u32, u32, u32)> = d.iter().map(|d| (d.code, d.line, d.column)).collect();
    assert_eq!(got, [(973, MAX_RECORDS as u32 + 2, 1)]);
    // The text is kept up to the line reading stopped at, not beyond.
    assert_eq!(f.text.len(), 3 + (MAX_RECORDS + 1) * 6);
}

#[test]
fn the_reader_reads_at_most_max_bytes_and_stops_with_974() {
    // "*1" then comment lines of 64 bytes, 17 MiB in all: comments never stop the reader.
    let line = format!("; {}\n", "c".repeat(61));
    let mut text = String::from("*1\n");
    while text.len() < 17 << 20 {
        text.push_str(&line);
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("AXCFIL");
    fs::write(&path, &text).expect("write");
    let mut sink = Sink::unbounded();
    let f = reader::read_path(&path, "AXCFIL", Grammar::FUNCTIONAL, &mut sink).expect("read");
    assert!(f.abandoned);
    // Whole lines up to the last line end within MAX_BYTES: (16 MiB - 3) / 64 = 262,143 of them.
    let kept = (MAX_BYTES - 3) / 64;
    assert_eq!(kept, 262_143);
    assert_eq!(f.text.len(), 3 + kept * 64);
    let got: Vec<(u32, u32, u32)> = sink
        .into_vec()
        .iter()
        .map(|d| (d.code, d.line, d.column))
        .collect();
    assert_eq!(got, [(974, kept as u32 + 2, 1)]);
}
