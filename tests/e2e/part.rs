//! End-to-end tests of part runs (`ncplc run --program`): the CNC kernel runs a partprogram
//! through the bundled PLC logic on the simulated machine.

use std::process::Output;

use crate::e2e_common;
use e2e_common::{Ncplc, Run, copy_dir, lathe_cut_at, root};

/// A copy of the lathe with `extra` appended to its sim.toml.
fn lathe_with(extra: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    let src = root().join("plc-programs/lathe");
    copy_dir(&src, dir.path());
    let sim = dir.path().join("sim.toml");
    let mut text = std::fs::read_to_string(&sim).expect("sim.toml");
    text.push_str(extra);
    std::fs::write(&sim, text).expect("write");
    dir
}

/// PART1 on `machine` in virtual time for at most 20 000 ticks.
fn part_run(machine: &std::path::Path) -> Run {
    Ncplc::run(machine)
        .virtual_time()
        .program("PART1")
        .ticks(20000)
}

#[test]
fn a_part_script_may_not_set_what_the_kernel_writes() {
    let m = lathe_with("[[part.at]]\ntick = 3\nset = { I1K5 = 1 }\n");
    let out = part_run(m.path()).output();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    // The located diagnostic of `check` (issue 23: one validation for check and run).
    assert!(
        err.starts_with("error[E3606]: I1K5 is written by the CNC kernel in a part run\n")
            && err.contains("sim.toml:138:9\n")
            && err.contains("\n1 error, 0 warnings\n"),
        "{err}"
    );
}

#[test]
fn a_part_script_may_not_name_an_undeclared_input_nor_issue_functions() {
    // IOCFIL IN0=0,1: connector 2 of packet A is not an input of the lathe.
    let m = lathe_with("[[part.at]]\ntick = 3\nset = { I2A0 = 1 }\n");
    let err = String::from_utf8_lossy(&part_run(m.path()).output().stderr).into_owned();
    assert!(
        err.starts_with("error[E3602]: I2A0 is not an input signal of this machine\n")
            && err.contains("sim.toml:138:9\n")
            && err.contains("help: packet-A inputs are on the IN connectors IOCFIL declares\n"),
        "{err}"
    );
    let m = lathe_with("[[part.at]]\ntick = 3\nm = [8]\n");
    let err = String::from_utf8_lossy(&part_run(m.path()).output().stderr).into_owned();
    assert!(
        err.starts_with(
            "error[E3606]: tick 3: m, s and t come from the partprogram in a part run\n"
        ) && err.contains("sim.toml:138:1\n"),
        "{err}"
    );
}

/// The README's first command: the lathe runs PART1 (spindle with at-speed wait, coolant, a feed
/// hold during the second pass, M30) to its end; the recording is the golden `traces/part1.jsonl`
/// with both engines (which the `replay` module replays).
#[test]
fn the_lathe_runs_part1_to_m30_identically_with_both_engines() {
    let machine = root().join("plc-programs/lathe");
    let golden = std::fs::read_to_string(machine.join("traces/part1.jsonl")).expect("golden");
    let dir = tempfile::tempdir().expect("tempdir");
    for engine in ["jit", "interp"] {
        let rec = dir.path().join(format!("{engine}.jsonl"));
        let out = part_run(&machine)
            .until_end()
            .stats()
            .engine(engine)
            .record(&rec)
            .output();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert_eq!(
            out.status.code(),
            Some(0),
            "{stdout}{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            stdout.contains("part PART1 (crc32 6d2bbce4): 17 canonical blocks\n"),
            "{stdout}"
        );
        assert!(
            stdout.contains("cycle time 42.40 s (ticks 12..4252), ended\n"),
            "{stdout}"
        );
        assert!(
            stdout.contains("process 1: 17 blocks; handshakes M 5 S 1 T 0;"),
            "{stdout}"
        );
        assert!(!stdout.contains("alarm:"), "{stdout}");
        let got = std::fs::read_to_string(&rec).expect("recorded");
        assert_eq!(got, golden, "{engine}");
        // The feed hold: FOLD at 400, HOLD reached at 403, released by START at 500.
        assert!(got.contains("{\"t\":403,\"in\":{\"I1K6\":1},\"pos\":{\"1Z\":"));
    }
}

/// The mill runs its PART1 (and process 2 its MAGAZINE program): M06 tool change (orient, drawbar, arm), spindle, coolant, a feed hold
/// while milling the square, M30; the recording is the golden `mill/traces/part1.jsonl`.
#[test]
fn the_mill_runs_part1_with_its_tool_change() {
    let machine = root().join("plc-programs/mill");
    let dir = tempfile::tempdir().expect("tempdir");
    let rec = dir.path().join("mill.jsonl");
    let out = part_run(&machine).until_end().stats().record(&rec).output();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(
        stdout.contains("cycle time 34.26 s (ticks 12..3438), ended\n"),
        "{stdout}"
    );
    assert!(
        stdout.contains("process 1: 13 blocks; handshakes M 6 S 1 T 1;"),
        "{stdout}"
    );
    // S2000 needs GM2 (GM1 reaches 1500 rev/min): one gear change acknowledged by the PLC.
    assert!(
        stdout.contains("top speed 2000.0 rev/min; gear changes 1\n"),
        "{stdout}"
    );
    // Process 2, the magazine, runs its program (M30) alongside: `sim.toml [cnc] programs`.
    assert!(
        stdout.contains("process 2: 1 blocks; handshakes M 1 S 0 T 0;"),
        "{stdout}"
    );
    let golden = std::fs::read_to_string(machine.join("traces/part1.jsonl")).expect("golden");
    assert_eq!(std::fs::read_to_string(&rec).expect("recorded"), golden);
}

/// An e-stop in the middle of the part stops it with an alarm: `--until-end` exits 1.
#[test]
fn an_estop_during_the_part_exits_1_with_the_alarm() {
    let m = lathe_with("[[part.at]]\ntick = 300\nset = { I0A0 = 0 }\n");
    let out = part_run(m.path()).until_end().stats().output();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains("started at tick 12, did not end\n"),
        "{stdout}"
    );
    assert!(
        stdout.ends_with("alarm: process 1: emergency stop\n"),
        "{stdout}"
    );
}

/// `--trajectory` writes the `ncplc nc run` JSON Lines: the header with the planner's limits and
/// contour control (off: PART1 has no G23), then
/// one line per 2 ms interpolation tick, ending at rest on the retract point.
#[test]
fn trajectory_of_the_lathe_part() {
    let machine = root().join("plc-programs/lathe");
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("traj.jsonl");
    let out = part_run(&machine).until_end().trajectory(&path).output();
    assert_eq!(out.status.code(), Some(0));
    let text = std::fs::read_to_string(&path).expect("trajectory");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        r#"{"tick_s":0.002,"axes":["X","Z"],"limits":{"X":{"v":166.666667,"a":200,"j":540},"Z":{"v":200,"a":200,"j":450}},"tolerance_mm":0.01,"law":"linear","contour":{"blocks":0,"smoothing":"off","shift_mm":0.005,"blend_mm":0.005,"max_len_mm":2.0,"max_turn_deg":20.0,"complex_speed":"R39 60°, R384 10 µm, R385 10000 mm/s², R386 0 mm, R236 the axes'"}}"#
    );
    // 4252 logic ticks of 10 ms = 21 260 interpolation ticks.
    assert_eq!(lines.len(), 1 + 21_260);
    assert_eq!(
        lines[lines.len() - 1],
        r#"{"t":21259,"p":[-20,-50],"block":null,"feed":0}"#
    );
    // During the first pass (N40, block index 3) Z feeds at 300 mm/min: 0.01 mm per tick.
    assert_eq!(
        lines[3001],
        r#"{"t":3000,"p":[-44,-113.6475],"block":3,"feed":300}"#
    );
}

/// `--mdi` blocks run in MDI mode (one program, shared modal state) and `--until-end` stops after
/// them: rapid to X-10 Z-20, then X-12: 2 mm of diameter, 1 mm of the X slide (a diameter
/// axis) at F100 (0.6 s). The operator types blocks: the second has no block number.
#[test]
fn mdi_blocks_run_and_end() {
    let machine = root().join("plc-programs/lathe");
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("mdi.jsonl");
    let out = Ncplc::run(&machine)
        .virtual_time()
        .mdi("N1 G00 X-10 Z-20")
        .mdi("G01 X-12 F100")
        .until_end()
        .stats()
        .trajectory(&path)
        .output();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(
        stdout.contains("cycle time 0.92 s (ticks 4..96), ended\n"),
        "{stdout}"
    );
    assert!(stdout.contains("process 1: 2 blocks;"), "{stdout}");
    let text = std::fs::read_to_string(&path).expect("trajectory");
    assert_eq!(
        text.lines().last(),
        Some(r#"{"t":479,"p":[-12,-20],"block":null,"feed":0}"#)
    );
}

/// A machine that is not referenced homes first (HOME, START: the MCZ cycle of X then Z against
/// the simulated switches), then runs the part when the operator presses START again.
#[test]
fn an_unreferenced_lathe_homes_then_runs_the_part() {
    let m = lathe_with(
        "\n[[axis]]\nname = \"X\"\nstart = -50\nhome_switch = 3\n\
         \n[[axis]]\nname = \"Z\"\nstart = -100\nhome_switch = 3\n\
         \n[[part.at]]\ntick = 1500\nset = { I0A3 = 1 }\n\
         \n[[part.at]]\ntick = 1505\nset = { I0A3 = 0 }\n",
    );
    let sim = m.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    std::fs::write(
        &sim,
        text.replace("referenced = true", "referenced = false"),
    )
    .expect("write");
    let out = part_run(m.path()).until_end().stats().output();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The first START (tick 10) falls into the homing cycle and is refused; the second runs it.
    assert!(
        stdout.contains("cycle time 41.40 s (ticks 1502..5642), ended\n"),
        "{stdout}"
    );
    assert!(
        String::from_utf8_lossy(&out.stderr).contains(
            "process 1: Start refused: can't do that while a program is active (reset first)"
        ),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// MDI blocks are planned from where the axes stand: after homing the lathe stands at X-0.4
/// Z-0.2 (the MCZ cycle's end: each slide stops 0.2 mm past the mark, shown on X as a diameter);
/// `G01 X-12 F100` moves X alone, 11.6 mm of diameter = 5.8 mm of slide at 100 mm/min = 3.48 s,
/// and Z stays at -0.2 (planned from zero it would have gone to Z0). Homing jogs at MAN 2000 mm/min
/// without feed-forward: the summary's largest errors are the steady lags v/KV, 33.3/20 = 1.667 mm
/// of Z's slide and twice that in X's diameter.
#[test]
fn mdi_starts_where_the_axes_stand() {
    let m = lathe_with(
        "\n[[axis]]\nname = \"X\"\nstart = -50\nhome_switch = 3\n\
         \n[[axis]]\nname = \"Z\"\nstart = -100\nhome_switch = 3\n",
    );
    let sim = m.path().join("sim.toml");
    let text = std::fs::read_to_string(&sim).expect("sim.toml");
    std::fs::write(
        &sim,
        text.replace("referenced = true", "referenced = false"),
    )
    .expect("write");
    let path = m.path().join("traj.jsonl");
    let out = Ncplc::run(m.path())
        .virtual_time()
        .ticks(20000)
        .mdi("N2 G01 X-12 F100")
        .until_end()
        .trajectory(&path)
        .output();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(
        stdout.contains("cycle time 3.48 s (ticks 997..1345), ended\n"),
        "{stdout}"
    );
    assert!(
        stdout.contains(
            "largest following error X 3.333 mm (SRV no-VFF 10 mm), Z 1.667 mm (SRV no-VFF 10 mm)\n"
        ),
        "{stdout}"
    );
    let text = std::fs::read_to_string(&path).expect("trajectory");
    let mdi: Vec<&str> = text.lines().filter(|l| l.contains("\"block\":0")).collect();
    assert!(mdi[0].contains("\"p\":[-0.400784,-0.2]"), "{}", mdi[0]);
    assert!(mdi.iter().all(|l| l.contains(",-0.2],")), "Z never moves");
    assert_eq!(
        text.lines().last(),
        Some(r#"{"t":6724,"p":[-12,-0.2],"block":null,"feed":0}"#)
    );
}

/// `program` of the bundled lathe to its end in virtual time: the run's output and its
/// trajectory (`--trajectory`, JSON Lines).
fn bundled_lathe_run(program: &str) -> (Output, String) {
    let machine = root().join("plc-programs/lathe");
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("traj.jsonl");
    let out = Ncplc::run(&machine)
        .virtual_time()
        .program(program)
        .until_end()
        .trajectory(&path)
        .output();
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    (out, text)
}

/// The bundled Fanuc lathe program O1000 runs end to end on the bundled lathe: G54 of TAB0.POS
/// puts the part zero at machine X−150 (diameter) Z−300, so the first pass N50 (block 3) feeds
/// along Z at X44 → machine X−106 at F150 (0.005 mm per 2 ms tick), and N170 ends at X100 Z50 →
/// machine X−50 Z−250.
#[test]
fn the_lathe_runs_the_fanuc_program_o1000_to_m30() {
    let (out, text) = bundled_lathe_run("O1000.nc");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stdout}{stderr}");
    assert!(stdout.contains("part O1000.nc (crc32 "), "{stdout}");
    assert!(stdout.contains("): 19 canonical blocks\n"), "{stdout}");
    assert!(stdout.contains(", ended\n"), "{stdout}");
    assert!(
        stdout.contains("process 1: 19 blocks; handshakes M 5 S 1 T 0;"),
        "{stdout}"
    );
    let last = text.lines().last().expect("lines");
    assert!(last.contains(r#""p":[-50,-250],"block":null"#), "{last}");
    let pass: Vec<serde_json::Value> = text
        .lines()
        .skip(1)
        .map(|l| serde_json::from_str(l).expect("json"))
        .filter(|v: &serde_json::Value| v["block"] == 3)
        .collect();
    // 42 mm at 150 mm/min: 16.8 s, more than 8000 ticks at F150 on the X−106 line.
    let cruise: Vec<&serde_json::Value> = pass.iter().filter(|v| v["feed"] == 150).collect();
    assert!(cruise.len() > 8000, "{}", cruise.len());
    // (Its end blends into N60 within the 0.01 mm tolerance: the cruise stays on the line.)
    assert!(cruise.iter().all(|v| v["p"][0] == -106));
}

/// The lathe's sim.toml presses FEED HOLD at logic tick 400 and CYCLE START at 500 (for PART1's
/// second pass). In THREAD that falls inside the G33 pass (N30, block 2): the hold is deferred
/// to the thread's end, so Z keeps following the spindle, lead 6 mm × 50/60 rev/s × 2 ms =
/// 0.01 mm per interpolation tick, through interpolation ticks 2000–2500 and beyond.
#[test]
fn a_feed_hold_does_not_stop_a_thread_in_a_part_run() {
    let (out, text) = bundled_lathe_run("THREAD");
    assert_eq!(out.status.code(), Some(0));
    let lines: Vec<serde_json::Value> = text
        .lines()
        .skip(1)
        .map(|l| serde_json::from_str(l).expect("json"))
        .collect();
    for t in 1950..2700 {
        assert_eq!(lines[t]["block"], 2, "tick {t}");
        let dz =
            lines[t + 1]["p"][1].as_f64().unwrap_or(0.0) - lines[t]["p"][1].as_f64().unwrap_or(0.0);
        assert!((dz + 0.01).abs() < 1e-6, "tick {t}: Z moved {dz}");
    }
}

/// A G33 thread waits for the spindle's index pulse: with the spindle never started (S without
/// M03) it would wait for ever, so the kernel stops with an alarm naming the block (exit 1);
/// after M03 the same thread runs to its end.
#[test]
fn a_thread_with_the_spindle_stopped_is_a_located_alarm() {
    let machine = root().join("plc-programs/lathe");
    let run = |mdi: &[&str]| {
        let run = Ncplc::run(&machine).virtual_time().ticks(3000).until_end();
        mdi.iter().fold(run, |run, block| run.mdi(block)).output()
    };
    let out = run(&["N1 S100 G33 Z-10 F1.5"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains(
            "alarm: process 1: G33 thread waits for the spindle's index pulse with the spindle stopped (block 1 (N1))\n"
        ),
        "{stdout}"
    );
    let out = run(&["N1 S100 M03", "N2 G33 Z-10 F1.5"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    assert!(stdout.contains(", ended\n"), "{stdout}");
}

/// In virtual time nobody but the script can press START: a `--until-end` run whose script never
/// does stops after ten minutes of machine time with nothing moving (60,000 ticks of 10 ms) and
/// says why, instead of spinning for ever.
#[test]
fn until_end_without_a_start_stops_after_ten_idle_minutes() {
    let dir = lathe_cut_at("# The operator presses CYCLE START.");
    let out = Ncplc::run(dir.path())
        .virtual_time()
        .program("PART1")
        .until_end()
        .output();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(
        stdout.contains("the cycle never started (START from the PLC)\n"),
        "{stdout}"
    );
    assert!(
        stdout.contains("alarm: nothing moved and no block ran from tick 1 to tick 60001:"),
        "{stdout}"
    );
}

/// An error-dense partprogram is refused by `run` as by `nc check`: the first 100 diagnostics
/// of the file (diag::DEFAULT_MAX_PER_FILE), the rest counted in one line and in the summary (issue 23: memory
/// bounded by the cap, not by the file).
#[test]
fn run_refuses_an_error_dense_program_with_the_first_diagnostics_and_a_count() {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/mill"), dir.path());
    let text = format!("%1\nN1{}\nN2 M30\n", " U1".repeat(300));
    std::fs::write(dir.path().join("nc/DENSE"), text).expect("write");
    let out = Ncplc::run(dir.path())
        .virtual_time()
        .program("DENSE")
        .ticks(10)
        .output();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    // The first 100 of the file: the long line's warning and 99 of its 300 errors.
    assert_eq!(
        err.matches("error[E2008]: the machine has no axis U")
            .count(),
        99,
        "{err}"
    );
    assert_eq!(err.matches("warning[E2012]").count(), 1, "{err}");
    assert!(
        err.contains(
            "note: 201 more errors in nc/DENSE (`ncplc nc check --max-errors 0` lists all)\n300 errors, 1 warning\n"
        ),
        "{err}"
    );
}
