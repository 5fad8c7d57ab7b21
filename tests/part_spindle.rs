//! End-to-end: the spindle in part runs — G96 constant surface speed on the lathe (FACE96), gear
//! ranges with the GEARREQ/GEARACK handshake on a two-range copy of the lathe, and the alarm for
//! an S no range reaches.

mod e2e_common;
use e2e_common::{copy_dir, ncplc, root};

fn s(p: &std::path::Path) -> &str {
    p.to_str().expect("utf-8 path")
}

fn run(machine: &std::path::Path, program: &str, extra: &[&str]) -> (bool, String) {
    let mut args = vec![
        "run",
        s(machine),
        "--virtual-time",
        "--no-watch",
        "--program",
        program,
        "--until-end",
    ];
    args.extend_from_slice(extra);
    let out = ncplc(&args);
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
    // AXCFIL is CP866: edit it as Latin-1 so the Cyrillic comments survive byte for byte.
    let ax = dir.path().join("MP0/AXCFIL");
    let text: String = std::fs::read(&ax)
        .expect("AXCFIL")
        .iter()
        .map(|&b| char::from(b))
        .collect();
    let text = text.replace("GM1=3000,8.5,6,,", "GM1=1000,8.5,6,,\nGM2=3000,8.5,6,,");
    let bytes: Vec<u8> = text.chars().map(|c| c as u8).collect();
    std::fs::write(&ax, bytes).expect("write");
    let plc = dir.path().join("MP0/PLCPRG");
    let text = std::fs::read_to_string(&plc).expect("PLCPRG");
    let text = text.replace("TFIN = TSTB\n", "TFIN = TSTB\nGEARACK = GEARREQ\n");
    std::fs::write(&plc, text).expect("write");
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
