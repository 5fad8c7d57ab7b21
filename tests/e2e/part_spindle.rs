//! End-to-end tests of the spindle, the alternative feed and the tool-correction request in part
//! runs: G96 on the lathe (FACE96), gear ranges with GEARREQ/GEARACK on a two-range copy of the
//! lathe, the alarm for an S no range reaches, QCKFD with PGCFIL QFD, and `--kor-change` taken at
//! the mill's M06 (m_request 14).

use crate::e2e_common;
use e2e_common::{Ncplc, copy_dir, ncplc, root};

fn s(p: &std::path::Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// Replaces `from` by `to` in the file at `path`, byte for byte (the machine files are CP866).
fn patch(path: &std::path::Path, from: &str, to: &str) {
    let bytes = std::fs::read(path).expect("read");
    let at = bytes
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .unwrap_or_else(|| panic!("{from:?} not in {}", path.display()));
    let mut out = bytes[..at].to_vec();
    out.extend_from_slice(to.as_bytes());
    out.extend_from_slice(&bytes[at + from.len()..]);
    std::fs::write(path, out).expect("write");
}

fn run(machine: &std::path::Path, program: &str, extra: &[&str]) -> (bool, String) {
    let out = Ncplc::run(machine)
        .virtual_time()
        .program(program)
        .until_end()
        .args(extra)
        .output();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    (out.status.success(), text)
}

/// FACE96 faces from diameter 60 to 20 at 120 m/min: the top speed is 120 000 / (2π·10 mm) =
/// 1909.86 rev/min, below GM1's 3000; the run replays identically (kernel recomputes G96).
#[test]
fn the_lathe_faces_at_constant_surface_speed_and_replays() {
    let lathe = root().join("plc-programs/lathe");
    let dir = tempfile::tempdir().expect("tempdir");
    let trace = dir.path().join("face96.jsonl");
    let (ok, text) = run(&lathe, "FACE96", &["--record", s(&trace)]);
    assert!(ok, "{text}");
    assert!(text.contains("cycle time"), "{text}");
    assert!(
        text.contains("; top speed 1909.9 rev/min; gear changes 0\n"),
        "{text}"
    );
    let out = ncplc(&["replay", s(&lathe), s(&trace)]);
    let replay = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{replay}");
    assert!(
        replay.contains("kernel signals and axis positions identical"),
        "{replay}"
    );
}

/// A copy of the lathe with two gear ranges (GM1 1000, GM2 3000 rev/min) and a PLC that engages
/// the range the CNC asks for (GEARACK = GEARREQ).
fn two_range_lathe() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    patch(
        &dir.path().join("MP0/AXCFIL"),
        "GM1=3000,8.5,6,,",
        "GM1=1000,8.5,6,,\nGM2=3000,8.5,6,,",
    );
    patch(
        &dir.path().join("MP0/PLCPRG"),
        "TFIN = TSTB\n",
        "TFIN = TSTB\nGEARACK = GEARREQ\n",
    );
    dir
}

/// PART1's S1200 needs range 2 (GM1 1000 < 1200 ≤ GM2 3000): one gear change, then the part runs
/// to M30 as usual.
#[test]
fn s1200_on_a_two_range_lathe_engages_range_2_and_the_part_ends() {
    let m = two_range_lathe();
    let (ok, text) = run(m.path(), "PART1", &[]);
    assert!(ok, "{text}");
    assert!(text.contains("gear changes 1\n"), "{text}");
    assert!(text.contains("process 1: 17 blocks;"), "{text}");
}

/// S4000 is beyond the lathe's only range (GM1 3000): a stopping alarm naming the block, exit 1.
#[test]
fn an_s_beyond_every_range_stops_the_part_with_a_located_alarm() {
    let dir = tempfile::tempdir().expect("tempdir");
    let prog = dir.path().join("FAST");
    std::fs::write(&prog, "%1\nN10 G54 S4000 M03\nN20 M30\n").expect("write");
    let (ok, text) = run(&root().join("plc-programs/lathe"), s(&prog), &[]);
    assert!(!ok, "{text}");
    assert!(
        text.contains(
            "alarm: process 1: S4000 beyond every gear range (top 3000 rev/min) (block 1 (N10))"
        ),
        "{text}"
    );
}

/// QCKFD = 1 (a lathe copy whose PLC holds it) runs every F move of PART1 (F300, F150 under G94)
/// at the lathe's PGCFIL QFD = 500 mm/min; rapid moves keep their speed.
#[test]
fn qckfd_runs_the_g94_feed_moves_at_qfd() {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    patch(
        &dir.path().join("MP0/PLCPRG"),
        "TFIN = TSTB\n",
        "TFIN = TSTB\nQCKFD = 1\n",
    );
    let traj = dir.path().join("t.jsonl");
    let (ok, text) = run(dir.path(), "PART1", &["--trajectory", s(&traj)]);
    assert!(ok, "{text}");
    let mut top = std::collections::BTreeMap::<u64, f64>::new();
    for line in std::fs::read_to_string(&traj)
        .expect("trajectory")
        .lines()
        .skip(1)
    {
        let r: serde_json::Value = serde_json::from_str(line).expect("json");
        if let (Some(b), Some(f)) = (r["block"].as_u64(), r["feed"].as_f64()) {
            let e = top.entry(b).or_insert(0.0);
            *e = e.max(f);
        }
    }
    // Blocks 3, 4, 7, 8 (F300) and 11, 12 (F150) are the feed moves (0-based block indices).
    for b in [3, 4, 7, 8, 11, 12] {
        assert_eq!(top.get(&b), Some(&500.0), "block {b}: {top:?}");
    }
    assert!(top.get(&2).is_some_and(|f| *f > 10_000.0), "{top:?}");
}

/// The mill's M06 (`M06=02,14,62`: tool-correction request) re-plans the following blocks with
/// the table `--kor-change` gives: entry 2's Z length −120.25 → −119.75 moves the next block's
/// end point from Z−170.25 (−50 − 120.25) to exactly Z−169.75; the header names the table so
/// that the replay re-runs it.
#[test]
fn a_tool_correction_request_takes_the_changed_offset_for_the_following_block() {
    let mill = root().join("plc-programs/mill");
    let dir = tempfile::tempdir().expect("tempdir");
    let prog = dir.path().join("TLEN");
    std::fs::write(
        &prog,
        "%3\nN10 D2 &0010\nN20 T2 M06\nN30 G53 G00 X-100 Y-100 Z-50\nN40 M30\n",
    )
    .expect("write");
    let kor = dir.path().join("NEW.KOR");
    let table = std::fs::read_to_string(mill.join("MP0/TAB0.KOR")).expect("TAB0.KOR");
    std::fs::write(
        &kor,
        table.replace("02: R=8.0 Z=-120.25", "02: R=8.0 Z=-119.75"),
    )
    .expect("write");
    let last_z = |extra: &[&str]| {
        let traj = dir.path().join("t.jsonl");
        let mut args = vec!["--trajectory", s(&traj)];
        args.extend_from_slice(extra);
        let (ok, text) = run(&mill, s(&prog), &args);
        assert!(ok, "{text}");
        let t = std::fs::read_to_string(&traj).expect("trajectory");
        let r: serde_json::Value =
            serde_json::from_str(t.lines().last().expect("a line")).expect("json");
        (r["p"][2].as_f64().expect("z"), text)
    };
    let (z, text) = last_z(&[]);
    assert_eq!(z, -170.25);
    assert!(
        text.contains("process 1: tool-correction requests 1"),
        "{text}"
    );
    let trace = dir.path().join("k.jsonl");
    let (z, _) = last_z(&["--kor-change", s(&kor), "--record", s(&trace)]);
    assert_eq!(z, -169.75);
    let out = ncplc(&["replay", s(&mill), s(&trace)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("kernel signals and axis positions identical"),
        "{err}"
    );
}
