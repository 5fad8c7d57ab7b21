//! Property test of part runs: random lathe programs from the bundled dialect subset (rapid and
//! feed lines, arcs, dwell, S changes, coolant M08/M09, spindle M03/M05, M30), in MEFI and in
//! Fanuc, run through the CNC kernel on the bundled lathe to M30 without an alarm, and their
//! recordings replay identically (kernel signals and axis positions) with both engines; the same
//! for random mill programs (T2 M06 through the magazine of process 2, XYZ lines, XY arcs, the
//! scripted feed hold).

use proptest::prelude::*;

use crate::e2e_common;
use e2e_common::{Ncplc, copy_dir, lathe_cut_at, ncplc, root};

/// The lathe without the scripted feed hold of PART1 (the operator only presses START) and
/// without its zero-offset table: the programs are written in the machine frame (a Fanuc
/// program starts in G54, which `MP0/TAB0.POS` would move to the part).
fn lathe() -> tempfile::TempDir {
    let dir = lathe_cut_at("# Feed hold from the panel during the second pass");
    std::fs::remove_file(dir.path().join("MP0/TAB0.POS")).expect("the lathe's TAB0.POS");
    dir
}

/// One step of a random program.
#[derive(Debug, Clone)]
enum Op {
    Rapid(i32, i32),
    Line(i32, i32, u32),
    /// Quarter arc of radius r: clockwise towards −X, or counter-clockwise towards +X.
    Arc(bool, i32),
    Dwell(u32),
    Speed(u32),
    Coolant(bool),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        (-150i32..=-20, -500i32..=-20).prop_map(|(x, z)| Op::Rapid(x, z)),
        (-150i32..=-20, -500i32..=-20, 50u32..=400).prop_map(|(x, z, f)| Op::Line(x, z, f)),
        (any::<bool>(), 2i32..=10).prop_map(|(cw, r)| Op::Arc(cw, r)),
        (5u32..=50).prop_map(Op::Dwell),
        (300u32..=1500).prop_map(Op::Speed),
        any::<bool>().prop_map(Op::Coolant),
    ]
}

/// The program text in `fanuc` or MEFI form; arcs that would leave the X −170..−10 / Z −590..
/// box are left out.
fn program(ops: &[Op], fanuc: bool) -> String {
    let mut lines = Vec::new();
    let (mut x, mut z) = (-40, -50);
    lines.push("S800 M03".to_string());
    lines.push(format!("G00 X{x} Z{z}"));
    for o in ops {
        match *o {
            Op::Rapid(a, b) => {
                (x, z) = (a, b);
                lines.push(format!("G00 X{x} Z{z}"));
            }
            Op::Line(a, b, f) => {
                (x, z) = (a, b);
                lines.push(format!("G01 X{x} Z{z} F{f}"));
            }
            Op::Arc(cw, r) => {
                // X is a diameter: the radius change r is 2r in X.
                let nx = if cw { x - 2 * r } else { x + 2 * r };
                let nz = z - r;
                if !(-170..=-10).contains(&nx) || nz < -590 {
                    continue;
                }
                let g = if cw { "G02" } else { "G03" };
                lines.push(if fanuc {
                    format!("{g} X{nx} Z{nz} R{r} F200")
                } else {
                    format!("{g} X{nx} Z{nz} I-{r} J0 F200")
                });
                (x, z) = (nx, nz);
            }
            Op::Dwell(cs) => lines.push(if fanuc {
                format!("G04 P{}", cs * 10)
            } else {
                format!("G04 Q{cs}")
            }),
            Op::Speed(s) => lines.push(format!("S{s}")),
            Op::Coolant(on) => lines.push(if on { "M08" } else { "M09" }.to_string()),
        }
    }
    lines.push("M09".into());
    lines.push("M05".into());
    lines.push("M30".into());
    let body: Vec<String> = lines
        .iter()
        .enumerate()
        .map(|(i, l)| format!("N{} {l}", (i + 1) * 10))
        .collect();
    if fanuc {
        format!("O0042\n{}\n", body.join("\n"))
    } else {
        format!("%42\n{}\n", body.join("\n"))
    }
}

fn run_and_replay(ops: &[Op], fanuc: bool) {
    run_and_replay_on(&lathe(), &program(ops, fanuc), fanuc);
}

/// One step of a random mill program (mm, within X −800..0, Y −500..0, Z −450..0).
#[derive(Debug, Clone)]
enum MillOp {
    Rapid(i32, i32, i32),
    Line(i32, i32, i32, u32),
    /// Quarter arc of radius r in XY around (x, y − r): clockwise to (x + r, y − r), else
    /// counter-clockwise to (x − r, y − r).
    Arc(bool, i32),
    Dwell(u32),
    Speed(u32),
    Coolant(bool),
}

fn mill_op() -> impl Strategy<Value = MillOp> {
    prop_oneof![
        (-700i32..=-50, -450i32..=-50, -400i32..=-10).prop_map(|(x, y, z)| MillOp::Rapid(x, y, z)),
        (-700i32..=-50, -450i32..=-50, -400i32..=-10, 100u32..=900)
            .prop_map(|(x, y, z, f)| MillOp::Line(x, y, z, f)),
        (any::<bool>(), 2i32..=40).prop_map(|(cw, r)| MillOp::Arc(cw, r)),
        (5u32..=50).prop_map(MillOp::Dwell),
        (500u32..=3000).prop_map(MillOp::Speed),
        any::<bool>().prop_map(MillOp::Coolant),
    ]
}

/// The mill program text (MEFI); arcs that would leave the X −750..−10 / Y −480.. box are left out.
fn mill_program(ops: &[MillOp]) -> String {
    let (mut x, mut y, mut z) = (-100, -100, -50);
    let mut lines = vec![
        "T2 M06".to_string(),
        "S2000 M03".to_string(),
        format!("G00 X{x} Y{y} Z{z}"),
    ];
    for o in ops {
        match *o {
            MillOp::Rapid(a, b, c) => {
                (x, y, z) = (a, b, c);
                lines.push(format!("G00 X{x} Y{y} Z{z}"));
            }
            MillOp::Line(a, b, c, f) => {
                (x, y, z) = (a, b, c);
                lines.push(format!("G01 X{x} Y{y} Z{z} F{f}"));
            }
            MillOp::Arc(cw, r) => {
                let nx = if cw { x + r } else { x - r };
                let ny = y - r;
                if !(-750..=-10).contains(&nx) || ny < -480 {
                    continue;
                }
                let g = if cw { "G02" } else { "G03" };
                lines.push(format!("{g} X{nx} Y{ny} I0 J-{r} F500"));
                (x, y) = (nx, ny);
            }
            MillOp::Dwell(cs) => lines.push(format!("G04 Q{cs}")),
            MillOp::Speed(s) => lines.push(format!("S{s}")),
            MillOp::Coolant(on) => lines.push(if on { "M08" } else { "M09" }.to_string()),
        }
    }
    lines.extend(["M09", "M05", "M30"].map(String::from));
    let body: Vec<String> = lines
        .iter()
        .enumerate()
        .map(|(i, l)| format!("N{} {l}", (i + 1) * 10))
        .collect();
    format!("%42\n{}\n", body.join("\n"))
}

/// MEFI only: `--dialect fanuc` would apply to process 2's MEFI MAGAZINE program too.
fn mill_run_and_replay(ops: &[MillOp]) {
    let dir = tempfile::tempdir().expect("tempdir");
    copy_dir(&root().join("plc-programs/mill"), dir.path());
    run_and_replay_on(&dir, &mill_program(ops), false);
}

/// Runs `text` as program RANDOM of the machine copy `m` to its end and replays the recording.
fn run_and_replay_on(m: &tempfile::TempDir, text: &str, fanuc: bool) {
    let prog = m.path().join("nc/RANDOM");
    std::fs::write(&prog, text).expect("write program");
    let rec = m.path().join("random.jsonl");
    let machine = m.path().to_str().expect("utf-8");
    let run = Ncplc::run(machine)
        .virtual_time()
        .program("RANDOM")
        .ticks(60000)
        .until_end()
        .record(&rec);
    let out = if fanuc { run.dialect("fanuc") } else { run }.output();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{text}\n{stdout}{stderr}");
    assert!(stdout.contains("), ended\n"), "{text}\n{stdout}");
    assert!(!stdout.contains("alarm:"), "{text}\n{stdout}");
    for engine in ["jit", "interp"] {
        let out = ncplc(&[
            "replay",
            machine,
            rec.to_str().expect("utf-8"),
            "--engine",
            engine,
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{text}\n{engine}: {err}");
        assert!(
            err.contains("kernel signals and axis positions identical"),
            "{err}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2, ..ProptestConfig::default() })]

    #[test]
    fn random_mefi_programs_complete_and_replay(ops in prop::collection::vec(op(), 1..6)) {
        run_and_replay(&ops, false);
    }

    #[test]
    fn random_fanuc_programs_complete_and_replay(ops in prop::collection::vec(op(), 1..6)) {
        run_and_replay(&ops, true);
    }

    #[test]
    fn random_mill_programs_complete_and_replay(ops in prop::collection::vec(mill_op(), 1..6)) {
        mill_run_and_replay(&ops);
    }
}
