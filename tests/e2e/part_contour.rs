//! End-to-end tests of contour control in part runs (`ncplc run --program`): Fanuc `G05.1 Q1`
//! and MEFI G23 reach the CNC kernel's motion kernel, which then smooths and plans a CAM program
//! exactly as `ncplc nc run` does — the same set points tick for tick — and a recorded part
//! trace of such a run replays with identical axis positions.

use std::path::Path;

use crate::e2e_common;
use detmath::Det as _;
use e2e_common::{Ncplc, copy_dir, ncplc, root};

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// A Fanuc program: a circle of radius 20 mm about X-100 Y-100 (in the mill's negative work
/// space) as 1571 chords of 0.08 mm with coordinates rounded to 0.001 mm, at F6000, preceded by
/// the G01 from the machine zero to its start; `head` goes on the line after `O1`.
fn chord_circle(head: &str) -> String {
    let mut p = format!("O1\nG21 G90 G17 {head}\nG01 X-80. Y-100. F6000\n");
    let n = 1571;
    for k in 1..=n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        let (x, y) = (-100.0 + 20.0 * a.dcos(), -100.0 + 20.0 * a.dsin());
        p.push_str(&format!("X{x:.3} Y{y:.3}\n"));
    }
    p.push_str("M30\n");
    p
}

/// The set points of a trajectory file (JSON Lines after the header), one per tick.
fn set_points(path: &Path) -> (serde_json::Value, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).expect("trajectory");
    let mut lines = text.lines();
    let head = serde_json::from_str(lines.next().expect("header")).expect("json");
    let pts = lines
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).expect("json");
            v["p"]
                .as_array()
                .expect("p")
                .iter()
                .map(|x| x.as_f64().expect("number"))
                .collect()
        })
        .collect();
    (head, pts)
}

/// The ticks from the first set point off the start to the last one that moves.
fn moving(pts: &[Vec<f64>]) -> &[Vec<f64>] {
    let first = pts.iter().position(|p| p != &pts[0]).expect("moves") - 1;
    let last = pts.len()
        - pts
            .iter()
            .rev()
            .position(|p| p != &pts[pts.len() - 1])
            .expect("moves");
    &pts[first..last]
}

/// A copy of the bundled mill without the feed hold its part script presses at tick 900.
fn mill_without_hold() -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/mill"), dir.path());
    let sim = dir.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    let hold = "[[part.at]]\ntick = 900\nset = { I0A4 = 1 }\n";
    assert!(text.contains(hold), "the mill's feed hold moved");
    std::fs::write(&sim, text.replace(hold, "")).expect("write");
    dir
}

/// `ncplc nc run` of `prog` on `mill`: its trajectory.
fn nc_run(mill: &Path, prog: &Path, traj: &Path) -> (serde_json::Value, Vec<Vec<f64>>, String) {
    let out = ncplc(&[
        "nc",
        "run",
        s(mill),
        s(prog),
        "--dialect",
        "fanuc",
        "--trajectory",
        s(traj),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (head, pts) = set_points(traj);
    (head, pts, stdout)
}

/// The part run of `prog` on `mill` (its sim.toml presses START at tick 10), recorded.
fn part_run(
    mill: &Path,
    prog: &Path,
    traj: &Path,
    rec: &Path,
) -> (serde_json::Value, Vec<Vec<f64>>, String) {
    let out = Ncplc::run(mill)
        .virtual_time()
        .program(prog)
        .dialect("fanuc")
        .ticks(5000)
        .until_end()
        .stats()
        .trajectory(traj)
        .record(rec)
        .output();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (head, pts) = set_points(traj);
    (head, pts, stdout)
}

/// With and without `G05.1 Q1` the part run's set points are `nc run`'s, tick for tick (2 ms),
/// from the first tick that leaves the machine zero to the last that moves; contour control
/// shortens the cycle from 9.94 s to 8.33 s, the summary and the trajectory header say it is on,
/// and the recorded trace replays with identical axis positions.
#[test]
fn a_part_run_under_g05_1_follows_nc_run_tick_for_tick_and_replays() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mill = mill_without_hold();
    let mill = mill.path();
    let mut cycles = Vec::new();
    for (name, head) in [("ON.nc", "G05.1 Q1"), ("OFF.nc", "")] {
        let prog = dir.path().join(name);
        std::fs::write(&prog, chord_circle(head)).expect("write");
        let (nc_head, nc, nc_out) = nc_run(mill, &prog, &dir.path().join("nc.jsonl"));
        let rec = dir.path().join(format!("{name}.trace"));
        let (part_head, part, part_out) =
            part_run(mill, &prog, &dir.path().join("part.jsonl"), &rec);
        let (a, b) = (moving(&nc), moving(&part));
        assert_eq!(a.len(), b.len(), "{name}: moving ticks nc run vs part run");
        let diff: Vec<usize> = (0..a.len()).filter(|&k| a[k] != b[k]).collect();
        if let Some(&k) = diff.first() {
            panic!(
                "{name}: {} of {} ticks differ, first {k} of the motion: nc run {:?}, part run {:?}; last {:?}",
                diff.len(),
                a.len(),
                a[k],
                b[k],
                diff.last()
            );
        }
        let on = !head.is_empty();
        assert_eq!(nc_head["contour"], part_head["contour"], "{name}");
        assert_eq!(
            part_head["contour"]["smoothing"],
            if on { "tolerance band" } else { "off" }
        );
        let line = "contour control: 1573 blocks; lines ≤ 2 mm smoothed within 0.005 mm";
        assert_eq!(nc_out.contains(line), on, "{nc_out}");
        assert_eq!(part_out.contains(line), on, "{part_out}");
        let cycle = part_out
            .lines()
            .find(|l| l.starts_with("cycle time "))
            .expect("cycle time")
            .to_string();
        cycles.push((a.len(), cycle));
        let out = ncplc(&["replay", s(mill), s(&rec)]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{name}: {err}");
        assert!(
            err.contains("outputs identical, kernel signals and axis positions identical"),
            "{name}: {err}"
        );
    }
    // 4152 and 4956 interpolation ticks of 2 ms from the first move to the last (the G01 from
    // the machine zero to the circle's start at the mill's G54 offset, then the chords); the
    // cycle counts logic ticks of 10 ms from START to M30's end.
    assert_eq!(
        cycles,
        [
            (4152, "cycle time 8.33 s (ticks 12..845), ended".to_string()),
            (
                4956,
                "cycle time 9.94 s (ticks 12..1006), ended".to_string()
            )
        ]
    );
}
