//! End-to-end tests of `ncplc nc run`: the bundled partprograms through the motion kernel, the
//! trajectory format, a hand-computed motion time and the soft-limit refusal.

use std::process::Command;

use detmath::Det as _;

use crate::e2e_common::{ncplc_at_root as ncplc, root as repo};

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn one_line_takes_the_trapezoid_time() {
    let dir = tempfile::tempdir().expect("tempdir");
    let prog = dir.path().join("ONELINE");
    std::fs::write(&prog, "%1 \"one line\nN10 G1 X-100 F6000\nN20 M30\n").expect("write");
    let out = ncplc(&[
        "nc",
        "run",
        "plc-programs/mill",
        prog.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // 100 mm at 100 mm/s with X's MAN acceleration 300 mm/s² (the line starts at rest and ends
    // at the stop of the M30 block, so it keeps no kink reserve): T = 100/100 + 100/300 =
    // 1.333 s → 667 ticks of 2 ms.
    let s = text(&out.stdout);
    assert!(
        s.contains("motion time: 1.334 s (667 ticks of 2.0 ms)\n"),
        "{s}"
    );
    assert!(s.contains("X            0.400         1.000"), "{s}");
}

/// The lathe's X is a diameter axis (AXCFIL `TPA=41`): X-100 is programmed and shown as a
/// diameter but moves the slide 50 mm. At F4800 (80 mm/s) with X's MAN acceleration 200 mm/s²:
/// T = 50/80 + 80/200 = 1.025 s → 513 ticks of 2 ms (100 mm of slide would take 1.65 s). At
/// t = 0.512 s the slide is at 16 + 80 · 0.112 = 24.96 mm: the set point shows diameter 49.92.
#[test]
fn a_diameter_axis_moves_the_slide_by_the_radius() {
    let dir = tempfile::tempdir().expect("tempdir");
    let prog = dir.path().join("DIAX");
    std::fs::write(&prog, "%1\nN10 G53 G1 X-100 F4800\nN20 M30\n").expect("write");
    let traj = dir.path().join("t.jsonl");
    let out = ncplc(&[
        "nc",
        "run",
        "plc-programs/lathe",
        prog.to_str().expect("utf-8"),
        "--trajectory",
        traj.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    assert!(
        s.contains("motion time: 1.026 s (513 ticks of 2.0 ms)\n"),
        "{s}"
    );
    // Peak X speed 80 / 166.667 mm/s (GM0 10000 mm/min) of the slide.
    assert!(s.contains("X            0.480         1.000"), "{s}");
    let t = std::fs::read_to_string(&traj).expect("trajectory");
    let lines: Vec<&str> = t.lines().collect();
    assert_eq!(
        lines[257],
        r#"{"t":256,"p":[-49.92,0.0],"block":0,"feed":4800.0}"#
    );
    assert_eq!(
        lines.last().copied(),
        Some(r#"{"t":513,"p":[-100.0,0.0],"block":1,"feed":0.0}"#)
    );
}

/// In the machine frame (G53, offset 0) Z50 lies above the mill's LO1 zone (Z -450..0): refused
/// before any motion; `--soft-limits off` still runs it.
#[test]
fn soft_limit_refuses_the_block_before_motion() {
    let dir = tempfile::tempdir().expect("tempdir");
    let prog = dir.path().join("HIGHZ");
    std::fs::write(&prog, "%1\nN10 G53 G0 X-10 Z50\nN20 M30\n").expect("write");
    let p = prog.to_str().expect("utf-8");
    let out = ncplc(&["nc", "run", "plc-programs/mill", p]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.ends_with(
            "HIGHZ (N10): block 0: axis Z would reach 50.0000 mm, beyond its soft limit 0.0000 mm\n"
        ),
        "{err}"
    );
    assert!(out.stdout.is_empty());
    let off = ncplc(&["nc", "run", "plc-programs/mill", p, "--soft-limits", "off"]);
    assert!(off.status.success(), "{}", text(&off.stderr));
}

#[test]
fn bundled_programs_run_end_to_end() {
    let dir = tempfile::tempdir().expect("tempdir");
    // Soft limits on: each machine's TAB0.POS puts G54 inside its LO1 zones.
    for (machine, prog, laws) in [
        ("mill", "CONTOUR", &["linear", "s", "exp"][..]),
        ("mill", "GRID", &["linear", "s", "exp"]),
        ("mill", "O00023.nc", &["linear", "s", "exp"]),
        ("mill", "O00050.nc", &["linear", "s", "exp"]),
        ("mill", "O01000.nc", &["linear"]),
        ("mill", "SUBPRG", &["linear"]),
        ("mill", "PART1", &["linear"]),
        ("lathe", "G84THREAD", &["linear", "s", "exp"]),
        ("lathe", "G84ALTERN", &["linear", "s", "exp"]),
        ("lathe", "G85RUNOUT", &["linear", "s", "exp"]),
        ("lathe", "G86CHAMFER", &["linear", "s", "exp"]),
        ("lathe", "G87TAPER", &["linear", "s", "exp"]),
        ("lathe", "THREAD", &["linear", "s"]),
        ("lathe", "PART1", &["linear"]),
    ] {
        for &law in laws {
            let traj = dir.path().join(format!("{prog}.{law}.jsonl"));
            let m = format!("plc-programs/{machine}");
            let t = traj.to_str().expect("utf-8");
            let args = ["nc", "run", &m, prog, "--law", law, "--trajectory", t];
            let out = ncplc(&args);
            assert!(out.status.success(), "{prog} {law}: {}", text(&out.stderr));
            let plan = ncplc(&["nc", "plan", &m, prog]);
            let blocks: Vec<serde_json::Value> = text(&plan.stdout)
                .lines()
                .map(|l| serde_json::from_str(l).expect("json"))
                .collect();
            let lines: Vec<serde_json::Value> = std::fs::read_to_string(&traj)
                .expect("trajectory")
                .lines()
                .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
                .collect();
            let head = &lines[0];
            assert_eq!(head["law"], law);
            assert_eq!(head["tolerance_mm"], 0.01);
            let axes: Vec<String> = head["axes"]
                .as_array()
                .expect("axes")
                .iter()
                .map(|a| a.as_str().expect("name").to_string())
                .collect();
            // Ticks numbered from 0, starting and ending at rest at the last block's end point.
            for (i, l) in lines[1..].iter().enumerate() {
                assert_eq!(l["t"], i as u64);
            }
            let first = &lines[1];
            let last = lines.last().expect("ticks");
            assert_eq!(first["feed"], 0.0);
            assert_eq!(last["feed"], 0.0);
            let end = &blocks.last().expect("blocks")["end"];
            for (i, a) in axes.iter().enumerate() {
                assert_eq!(
                    last["p"][i].as_f64(),
                    end[a].as_f64(),
                    "{prog} {law} axis {a}"
                );
            }
            assert_eq!(last["block"].as_u64(), Some(blocks.len() as u64 - 1));
            // The summary's peaks: no axis beyond its limits, no set point beyond the tolerance.
            let s = text(&out.stdout);
            for l in s
                .lines()
                .filter(|l| axes.iter().any(|a| l.starts_with(a.as_str())))
            {
                let f: Vec<f64> = l
                    .split_whitespace()
                    .skip(1)
                    .filter_map(|x| x.parse().ok())
                    .collect();
                assert!(f.iter().all(|x| *x <= 1.0), "{prog} {law}: {l}");
            }
            let dev: f64 = s
                .split("path deviation: max ")
                .nth(1)
                .and_then(|x| x.split(' ').next())
                .and_then(|x| x.parse().ok())
                .expect("deviation");
            assert!(dev <= 0.01, "{prog} {law}: deviation {dev}");
        }
    }
}

#[test]
fn trajectory_header_states_the_limits_used() {
    let dir = tempfile::tempdir().expect("tempdir");
    let traj = dir.path().join("t.jsonl");
    let t = traj.to_str().expect("utf-8");
    let out = ncplc(&[
        "nc",
        "run",
        "plc-programs/mill",
        "O00050.nc",
        "--law",
        "s",
        "--trajectory",
        t,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let head = std::fs::read_to_string(&traj).expect("trajectory");
    // X, Y: GM0 15000 mm/min = 250 mm/s, MAN 300 mm/s² × ACC lin_s 1.5 = 450, jerk
    // 450² / (2 · 0.5 · 250) = 810; Z: 200 mm/s, 300, 300² / (2 · 0.5 · 200) = 450.
    assert_eq!(
        head.lines().next(),
        Some(
            "{\"tick_s\":0.002,\"axes\":[\"X\",\"Y\",\"Z\"],\"limits\":{\"X\":{\"v\":250.0,\"a\":450.0,\"j\":810.0},\"Y\":{\"v\":250.0,\"a\":450.0,\"j\":810.0},\"Z\":{\"v\":200.0,\"a\":300.0,\"j\":450.0}},\"tolerance_mm\":0.01,\"law\":\"s\",\"contour\":{\"blocks\":0,\"smoothing\":\"off\",\"shift_mm\":0.005,\"blend_mm\":0.005,\"max_len_mm\":2.0,\"max_turn_deg\":20.0,\"complex_speed\":\"R39 60°, R384 10 µm, R385 10000 mm/s², R386 0 mm, R236 the axes'\"}}"
        )
    );
}

/// A Fanuc chord circle (r 20 mm, 0.08 mm chords, coordinates rounded to 0.001 mm, F6000):
/// `G05.1 Q1` puts its chords under contour control (smoothing and complex speed), which the
/// summary and the trajectory header say; the run stays within the limits and the tolerance and
/// is faster than the same program without it.
#[test]
fn g05_1_q1_smooths_a_rounded_chord_circle_and_says_so() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut body = String::from("G01 X20. Y0. F6000\n");
    let n = 1571;
    for k in 1..=n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        let (x, y) = (20.0 * a.dcos(), 20.0 * a.dsin());
        body.push_str(&format!("X{:.3} Y{:.3}\n", x, y));
    }
    let run = |on: bool| {
        let prog = dir.path().join(if on { "O1.nc" } else { "O2.nc" });
        let head = if on {
            "O1\nG21 G90 G17 G05.1 Q1\n"
        } else {
            "O2\nG21 G90 G17\n"
        };
        std::fs::write(&prog, format!("{head}{body}M30\n")).expect("write");
        let traj = dir.path().join(if on { "on.jsonl" } else { "off.jsonl" });
        let out = ncplc(&[
            "nc",
            "run",
            "plc-programs/mill",
            prog.to_str().expect("utf-8"),
            "--dialect",
            "fanuc",
            "--soft-limits",
            "off",
            "--trajectory",
            traj.to_str().expect("utf-8"),
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let head = std::fs::read_to_string(&traj).expect("trajectory");
        let head: serde_json::Value =
            serde_json::from_str(head.lines().next().expect("header")).expect("json");
        let s = text(&out.stdout);
        let secs: f64 = s
            .split("motion time: ")
            .nth(1)
            .and_then(|x| x.split(' ').next())
            .and_then(|x| x.parse().ok())
            .expect("motion time");
        let dev: f64 = s
            .split("path deviation: max ")
            .nth(1)
            .and_then(|x| x.split(' ').next())
            .and_then(|x| x.parse().ok())
            .expect("deviation");
        assert!(dev <= 0.01, "deviation {dev}: {s}");
        (s, head, secs)
    };
    let (s_on, h_on, t_on) = run(true);
    let (s_off, h_off, t_off) = run(false);
    // After G05.1 Q1: the G01 to the start, the 1571 chords and the M30 record.
    assert!(
        s_on.contains("contour control: 1573 blocks; lines ≤ 2 mm smoothed within 0.005 mm"),
        "{s_on}"
    );
    assert_eq!(h_on["contour"]["blocks"], 1573);
    assert_eq!(h_on["contour"]["smoothing"], "tolerance band");
    assert!(s_off.contains("contour control: off"), "{s_off}");
    assert_eq!(h_off["contour"]["blocks"], 0);
    assert!(t_on < t_off, "{t_on} s with G05.1 Q1, {t_off} s without");
}

/// A complex-speed constant out of range in nc/CONSTANTS stops `nc run` (exit 2, as other machine-file errors) with the file and line.
#[test]
fn a_complex_speed_constant_out_of_range_is_refused_with_its_line() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = dir.path().join("mill");
    let copy = Command::new("cp")
        .args(["-r", "plc-programs/mill", m.to_str().expect("utf-8")])
        .current_dir(repo())
        .status()
        .expect("cp");
    assert!(copy.success());
    std::fs::write(
        m.join("nc").join("CONSTANTS"),
        "R39: 00060.000\nR385: 9.0000000\n",
    )
    .expect("write");
    let out = ncplc(&["nc", "run", m.to_str().expect("utf-8"), "CONTOUR"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stdout));
    let e = text(&out.stderr);
    assert!(
        e.contains("CONSTANTS: line 2: R385: 90000000 is out of range (decades 1–7 an acceleration of 1…9999999 mm/s², decade 8 0…4)"),
        "{e}"
    );
}

#[test]
fn a_linear_move_without_feed_is_refused_with_its_block() {
    let dir = tempfile::tempdir().expect("tempdir");
    let prog = dir.path().join("NOFEED");
    // The priority block leaves G1 and F0: a positioning block without G0 or F cannot move.
    std::fs::write(&prog, "%1\nN10 M03 S50\nN20 Z5. X64.\nN30 M30\n").expect("write");
    let out = ncplc(&[
        "nc",
        "run",
        "plc-programs/lathe",
        prog.to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.ends_with("NOFEED (N20): block 1: linear move without a feed (F)\n"),
        "{err}"
    );
}

#[test]
fn thread_waits_for_the_spindle_index_and_advances_one_lead_per_revolution() {
    // THREAD: N10 M03 S50, N20 rapid to Z−295 (machine frame), N30 G33 Z−388 F6 J12 (a run-out
    // segment to Z−400 after it). The virtual spindle turns at S50 from tick 2 on: 50/60 rev/s ×
    // 2 ms = 1/600 rev per tick, at (t − 1)/600 rev after tick t. The rapid ends between the
    // index pulses of ticks 601 (1 rev) and 1201 (2 rev), so the thread waits for tick 1201 and
    // then Z advances 6 mm/rev = 0.01 mm per tick, through the run-out too (the lead is along Z).
    let dir = tempfile::tempdir().expect("tempdir");
    let traj = dir.path().join("thread.jsonl");
    let t = traj.to_str().expect("utf-8");
    let out = ncplc(&[
        "nc",
        "run",
        "plc-programs/lathe",
        "THREAD",
        "--trajectory",
        t,
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(&traj)
        .expect("trajectory")
        .lines()
        .skip(1)
        .map(|l| serde_json::from_str(l).expect("json"))
        .collect();
    let tick = |l: &serde_json::Value| l["t"].as_u64().expect("t");
    let z = |l: &serde_json::Value| l["p"][1].as_f64().expect("z");
    let reached = lines
        .iter()
        .find(|l| l["block"] == 2)
        .map(tick)
        .expect("thread");
    assert!((602..1201).contains(&reached), "reached at {reached}");
    let cut: Vec<&serde_json::Value> = lines
        .iter()
        .filter(|l| (l["block"] == 2 || l["block"] == 3) && z(l) < -295.0)
        .collect();
    assert_eq!(tick(cut[0]), 1202);
    for l in &cut {
        let want = (-295.0 - 0.01 * (tick(l) - 1201) as f64).max(-400.0);
        assert!(
            (z(l) - want).abs() < 1e-6,
            "tick {}: Z {} want {want}",
            tick(l),
            z(l)
        );
    }
    // 105 mm at 0.01 mm per tick: the run-out ends within tick 1201 + 10 500, where the rapid
    // N50 takes over; the last set point on the thread is Z −399.99 at tick 11 700.
    assert_eq!(cut.last().map(|l| tick(l)), Some(11_700));
    let end = lines
        .iter()
        .find(|l| tick(l) == 11_701)
        .expect("tick 11701");
    assert_eq!(end["block"], 4);
}
