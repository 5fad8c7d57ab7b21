//! End to end: a handwheel of the lathe (IOCFIL `ADV=0,0`) turned by the simulated machine
//! (`sim.toml [[handwheel]]`, `[[part.at]] turn`) moves Z by pulses × step through the PLC's
//! COMU, HW_ON1, HW_AXIS1 and HW_SCALE, and the recording replays identically; a block beyond the
//! active soft limits (LO1, or LO2 when the PLC sets ZONE2) is refused with an alarm.

use std::path::Path;

use crate::e2e_common;
use e2e_common::{Ncplc, copy_dir, ncplc, root};

/// The lathe with channel 1 on Z (axis 2) at 10 µm per pulse while the panel switch I1A1 is on.
fn lathe_with_handwheel(turns: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let edit = |file: &str, f: &dyn Fn(String) -> String| {
        let p = dir.path().join(file);
        let text = std::fs::read_to_string(&p).expect("read");
        std::fs::write(&p, f(text)).expect("write");
    };
    edit("MP0/IOCFIL", &|t| t.replace("ASM=S\n", "ASM=S\nADV=0,0\n"));
    edit("MP0/PLCPRG", &|t| {
        // Before the `$` that ends the fast logic.
        let end = t.rfind('$').expect("the closing $");
        format!(
            "{}; handwheel channel 1: Z at 10 um per pulse while the panel switch I1A1 is on\n\
             COMU = I1A1\nHW_ON1 = I1A1\nHW_AXIS1 = 2\nHW_SCALE = 1\n{}",
            &t[..end],
            &t[end..]
        )
    });
    edit("sim.toml", &|t| {
        t + "\n[[handwheel]]\nchannel = 1\ncounter = \"W1A3\"\n\n\
             [[part.at]]\ntick = 300\nset = { I1A1 = 1 }\n"
            + turns
    });
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// The last set points of the trajectory file.
fn last_set_points(path: &Path) -> String {
    let text = std::fs::read_to_string(path).expect("trajectory");
    let last = text.lines().last().expect("a line");
    let v: serde_json::Value = serde_json::from_str(last).expect("json");
    v["p"].to_string()
}

#[test]
fn pulses_times_the_step_move_z_and_the_run_replays() {
    // −250 pulses (2.5 revolutions, delivered at 100 per tick) × 10 µm = −2.5 mm (the run stops
    // before the bundled script presses CYCLE START again at tick 500).
    let m = lathe_with_handwheel("[[part.at]]\ntick = 310\nturn = { 1 = -250 }\n");
    let traj = m.path().join("hw.traj");
    let rec = m.path().join("hw.jsonl");
    let out = Ncplc::run(m.path())
        .virtual_time()
        .mdi("N1 G00 X-10 Z-20")
        .ticks(450)
        .trajectory(&traj)
        .record(&rec)
        .output();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(last_set_points(&traj), "[-10,-22.5]");
    let out = ncplc(&["replay", s(m.path()), s(&rec)]);
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("kernel signals and axis positions identical"),
        "{text}"
    );
}

#[test]
fn a_turn_of_an_unwired_channel_is_an_error() {
    let m = lathe_with_handwheel("[[part.at]]\ntick = 310\nturn = { 2 = 5 }\n");
    let out = Ncplc::run(m.path())
        .virtual_time()
        .mdi("N1 G00 X-10 Z-20")
        .ticks(10)
        .output();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.ends_with("sim script: tick 310: turn `2`: process 1 has no [[handwheel]] channel 2\n"),
        "{err}"
    );
}

fn mdi(machine: &Path, block: &str) -> std::process::Output {
    Ncplc::run(machine)
        .virtual_time()
        .mdi(block)
        .ticks(300)
        .until_end()
        .output()
}

#[test]
fn a_block_beyond_lo1_is_refused_and_zone2_selects_lo2() {
    let lathe = root().join("plc-programs/lathe");
    // Z's LO1 is 5 … −600 mm.
    let out = mdi(&lathe, "N1 G00 X-10 Z10");
    assert_eq!(out.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&out.stdout).contains(
            "alarm: process 1: block 1 (N1) refused: axis Z would reach 10.0000 mm, beyond the LO1 limit 5.0000 mm\n"
        ),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    // LO2 = 20 … −600 for Z, selected by the panel switch I1A1 through ZONE2.
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&lathe, dir.path());
    let edit = |file: &str, f: &dyn Fn(String) -> String| {
        let p = dir.path().join(file);
        let text = std::fs::read_to_string(&p).expect("read");
        std::fs::write(&p, f(text)).expect("write");
    };
    // AXCFIL is not UTF-8 (its comments are in the Russian code page): edit its bytes.
    let axcfil = dir.path().join("MP0/AXCFIL");
    let bytes = std::fs::read(&axcfil).expect("AXCFIL");
    let z = b"LO1=5,-600,2\r\n";
    let at = bytes
        .windows(z.len())
        .position(|w| w == z)
        .expect("Z's LO1")
        + z.len();
    let edited = [&bytes[..at], b"LO2=20,-600,2\r\n", &bytes[at..]].concat();
    std::fs::write(&axcfil, edited).expect("write");
    edit("MP0/PLCPRG", &|t| {
        let end = t.rfind('$').expect("the closing $");
        format!("{}ZONE2 = I1A1\n{}", &t[..end], &t[end..])
    });
    edit("sim.toml", &|t| {
        t + "\n[[part.at]]\ntick = 1\nset = { I1A1 = 1 }\n"
    });
    let out = mdi(dir.path(), "N1 G00 X-10 Z10");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(!stdout.contains("alarm"), "{stdout}");
    let out = mdi(dir.path(), "N1 G00 X-10 Z25");
    assert!(
        String::from_utf8_lossy(&out.stdout).contains(
            "alarm: process 1: block 1 (N1) refused: axis Z would reach 25.0000 mm, beyond the LO2 limit 20.0000 mm\n"
        ),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

/// A copy of the lathe whose simulated Z has its + switch at 8 mm and its − switch at −50 mm.
fn lathe_with_z_switches() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/lathe"), dir.path());
    let sim = dir.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    std::fs::write(
        &sim,
        text + "\n[[axis]]\nname = \"Z\"\nlimit_pos = 8.0\nlimit_neg = -50.0\n",
    )
    .expect("write");
    dir
}

/// The lathe's Z has MFC = I0A12 (+), I0A13 (−); the simulated machine presses the − switch from
/// Z = −50 mm down (inside LO1, so the soft limit does not refuse the block first). A rapid to
/// Z−100 runs onto it: the kernel stops every motion with a stopping alarm naming the input,
/// short of the programmed end, and the recording replays identically.
#[test]
fn a_move_onto_a_hardware_limit_switch_stops_the_run_with_an_alarm() {
    let dir = lathe_with_z_switches();
    let traj = dir.path().join("mfc.traj");
    let rec = dir.path().join("mfc.jsonl");
    let out = Ncplc::run(dir.path())
        .virtual_time()
        .mdi("N1 G00 Z-100")
        .ticks(300)
        .until_end()
        .trajectory(&traj)
        .record(&rec)
        .output();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains(
            "alarm: process 1: axis Z ran onto its - hardware limit switch (MFC I0A13)\n"
        ),
        "{stdout}"
    );
    let p: Vec<f64> = serde_json::from_str(&last_set_points(&traj)).expect("set points");
    assert!(p[1] < -50.0 && p[1] > -100.0, "Z stopped at {}", p[1]);
    // The contacts are normally closed: I0A13 opens on the switch, I0A12 stays closed.
    let trace = std::fs::read_to_string(&rec).expect("trace");
    assert!(trace.contains("\"I0A13\":0"), "I0A13 never opened");
    assert!(!trace.contains("\"I0A12\":0"), "I0A12 opened");
    let out = ncplc(&["replay", s(dir.path()), s(&rec)]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The stop on the limit switch decelerates Z at its AFC (1500 mm/s² in the lathe's AXCFIL, the
/// rapid's RAP acceleration is 800): from the rapid's 200 mm/s (RAP 12000 mm/min) the set point
/// comes to rest 200²/(2·1500) = 13.333 mm after its last tick at full speed (the normal abort
/// would take 200²/(2·784) = 25.5 mm at 98 % of RAP).
#[test]
fn the_limit_switch_stop_uses_the_afc_emergency_deceleration() {
    let dir = lathe_with_z_switches();
    let traj = dir.path().join("afc.traj");
    let out = Ncplc::run(dir.path())
        .virtual_time()
        .mdi("N1 G00 Z-100")
        .ticks(100)
        .trajectory(&traj)
        .output();
    assert!(out.status.code().is_some(), "{out:?}");
    let z: Vec<f64> = std::fs::read_to_string(&traj)
        .expect("trajectory")
        .lines()
        .skip(1)
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).expect("json");
            v["p"][1].as_f64().expect("z")
        })
        .collect();
    let dt = 0.002;
    let v: Vec<f64> = z.windows(2).map(|w| (w[1] - w[0]) / dt).collect();
    let full = v
        .iter()
        .rposition(|x| (x + 200.0).abs() < 1e-3)
        .expect("full rapid speed");
    let end = *z.last().expect("set points");
    assert!(
        (end - z[full + 1] + 200.0 * 200.0 / 3000.0).abs() < 1e-5,
        "stopped at {end}, full speed until {}",
        z[full + 1]
    );
    let peak = v
        .windows(2)
        .map(|w| (w[1] - w[0]) / dt)
        .fold(0.0f64, f64::max);
    assert!((peak - 1500.0).abs() < 1e-3, "deceleration {peak}");
}
