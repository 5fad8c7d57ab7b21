//! The reconstructed lathe fixed cycles G84–G87 of `plc-programs/lathe/macros/PEVNECY5.NCP`
//! (parameters-cycles §5.8–§5.11), planned from the example programs in `plc-programs/lathe/nc/`.
//! Every expected value is computed by hand from the listing's formulas in the comment above it,
//! with the arithmetic of §4.3 (decimal mode: `r` in µm; op 3 and op 4 truncate toward zero; op 28
//! rounds to nearest; op 9 is an arithmetic shift of `r`).

use crate::common;
use detmath::Det as _;

use common::*;
use partprogram::{Backend, Kind, MachineSpec, Plan, PlanOptions};

/// (N, kind, thread flag, X, Z) of one canonical block.
type Move = (u32, Kind, bool, f64, f64);

/// The lathe with machine constant 8 = 04000000: the run-out slope is in R04.
fn lathe_mc8() -> MachineSpec {
    let mut m = lathe();
    m.thread_constant = 4_000_000;
    m
}

/// Plans `plc-programs/lathe/nc/<name>` with both back ends, checks they agree, returns the plan.
fn plan_example(m: &MachineSpec, name: &str) -> Plan {
    let src = std::fs::read_to_string(machines().join("lathe/nc").join(name)).expect("example");
    let native = run(m, &src, PlanOptions::default());
    let interp = run(
        m,
        &src,
        PlanOptions {
            backend: Backend::Interpreter,
            ..PlanOptions::default()
        },
    );
    assert_eq!(native.blocks, interp.blocks, "{name}: back ends differ");
    native
}

/// The blocks of cycle unit `unit` as (N, kind, thread, X, Z).
fn cycle(p: &Plan, unit: &str) -> Vec<Move> {
    p.blocks
        .iter()
        .filter(|c| c.unit.as_deref() == Some(unit))
        .map(|c| (c.n.unwrap_or(0), c.kind, c.thread, end(c, 'X'), end(c, 'Z')))
        .collect()
}

const R: Kind = Kind::Rapid;
const L: Kind = Kind::Linear;

#[test]
fn g84_infeed_in_the_axis_cuts_a_geometric_series_of_chips() {
    let p = plan_example(&lathe(), "G84THREAD");
    // Start X0 = 24 (op 26 gives the radius 12.000, R14=+01333333 doubles it), Z0 = 5.
    // n = R29 = 4 (r 4), op 23 -> 4.000; op 28: (0.8^4 - 1)/(0.8 - 1) = 2.952.
    // First chip |R30|/2.952 = 1.840/2.952 = 0.623306.. -> 0.623 (op 4 truncates), negative as R30.
    // Xw = 24 - 4 = 20; final Xf = 20 - 1.840 = 18.160; X1 = 20 - 0.623 = 19.377.
    // Z end = 5 - 5 - 30 = -30. R10 = R02 + R29 = -2 + 4 = 2: G73 L50 Q2 runs N50..N8 3 times.
    // Chip 2: -0.623 x 0.8 = -0.4984 -> -0.498, X2 = 18.879; chip 3: -0.498 x 0.8 = -0.3984 ->
    // -0.398, X3 = 18.481. Final passes: R39 = R23 = 1, N9 decrements to 0 (0 >= 0: again), then
    // -1: R23 + 1 = 2 passes at Xf.
    let mut want: Vec<Move> = Vec::new();
    for x in [19.377, 18.879, 18.481] {
        want.extend([
            (50, R, false, x, 5.0),
            (6, L, true, x, -30.0),
            (7, R, false, 24.0, -30.0),
            (8, R, false, 24.0, 5.0),
        ]);
    }
    for _ in 0..2 {
        want.extend([
            (9, R, false, 18.16, 5.0),
            (10, L, true, 18.16, -30.0),
            (11, R, false, 24.0, -30.0),
            (12, R, false, 24.0, 5.0),
        ]);
    }
    assert_eq!(cycle(&p, "L84"), want);
    // G33 without F cuts with the lead of FR26 (R26=1.5 mm) at S500: 1.5 x 500 = 750 mm/min.
    let feeds: Vec<Option<f64>> = p
        .blocks
        .iter()
        .filter(|c| c.thread)
        .map(|c| c.feed)
        .collect();
    assert_eq!(feeds, vec![Some(750.0); 5]);
    // The cycle's work parameters are restored after it (§5.1).
    assert_eq!(
        (p.params[10], p.params[11], p.params[30], p.params[31]),
        (0, 0, -1_840, -30_000)
    );
}

#[test]
fn g84_alternating_infeed_shifts_the_start_by_the_metric_formula() {
    let p = plan_example(&lathe(), "G84ALTERN");
    // Chips as in G84THREAD: X1 = 19.377, X2 = 18.879, X3 = 18.481, Xf = 18.160 (n = 4).
    // N40: R41 = 34 x S = 34 x 1.5 = 51.000 (spec §4.3: `R18=34.000 R26=1.5`, `R5=+03182641`).
    // Alternating chips: R21 = R10 - R21 + 2 = 2 - 2 + 2 = 2.
    // Chip 1: T = R46 = -0.623; R32=-1 shifts r -623 right: -312 (-0.312, radius);
    //   55.426 x -0.312 = -17.292912 -> -17.292, abs 17.292; 51.000 - 17.292 = 33.708;
    //   P = 33.708/96 = 0.351125 -> 0.351; less the allowance R47 = R19 = 0.050: 0.301.
    //   First pass starts at Z 5 - 0.301 = 4.699, the second at 5 + 0.301 = 5.301.
    // Chip 2: T = -0.623 - 0.498 = -1.121 -> -561 (-0.561); 55.426 x 0.561 = 31.093986 -> 31.093;
    //   51.000 - 31.093 = 19.907; /96 = 0.207364 -> 0.207; - 0.050 = 0.157: Z 4.843 and 5.157.
    // R21 is then 0: N190 clears R48, R20, R47, so chip 3 is one pass in the axis (Z 5), N200
    // returns to Z 5 in place; R23 = 0 gives one final pass at Xf.
    let mut want: Vec<Move> = Vec::new();
    for (x, dz) in [(19.377, 0.301), (18.879, 0.157)] {
        want.extend([
            (60, R, false, x, um(5.0 - dz)),
            (70, L, true, x, -30.0),
            (80, R, false, 24.0, -30.0),
            (90, R, false, 24.0, 5.0),
            (120, R, false, x, um(5.0 + dz)),
            (130, L, true, x, -30.0),
            (150, R, false, 24.0, -30.0),
            (200, R, false, 24.0, 5.0),
        ]);
    }
    want.extend([
        (60, R, false, 18.481, 5.0),
        (70, L, true, 18.481, -30.0),
        (80, R, false, 24.0, -30.0),
        (90, R, false, 24.0, 5.0),
        (200, R, false, 24.0, 5.0),
        (210, R, false, 18.16, 5.0),
        (220, L, true, 18.16, -30.0),
        (230, R, false, 24.0, -30.0),
        (240, R, false, 24.0, 5.0),
    ]);
    assert_eq!(cycle(&p, "L84"), want);
    assert!(
        p.blocks
            .iter()
            .filter(|c| c.thread)
            .all(|c| c.feed == Some(750.0))
    );
}

#[test]
fn g85_ends_every_pass_with_the_run_out_of_r22() {
    let p = plan_example(&lathe_mc8(), "G85RUNOUT");
    // n = 3: op 28 (0.8^3 - 1)/(0.8 - 1) = 2.44; first chip 1.840/2.44 = 0.754098 -> 0.754,
    // X1 = 20 - 0.754 = 19.246; chip 2: 0.754 x 0.8 = 0.6032 -> 0.603, X2 = 18.643; Xf = 18.16.
    // R10 = -2 + 3 = 1: two loop passes; R23 = 0: one final pass.
    // G33 J5 (R22) with R04=120.0 (X, +20°): straight to Z -30 + 5 = -25, then the run-out
    // raises the diameter by 2 x 5 x tan 20° = 3.639702 at Z -30 (R31 includes the run-out).
    let ro = 2.0 * 5.0 * 20f64.to_radians().dtan();
    let mut want: Vec<Move> = Vec::new();
    for x in [19.246, 18.643] {
        want.extend([
            (50, R, false, x, 5.0),
            (6, L, true, x, -25.0),
            (6, L, true, um(x + ro), -30.0),
            (7, R, false, 24.0, -30.0),
            (8, R, false, 24.0, 5.0),
        ]);
    }
    want.extend([
        (9, R, false, 18.16, 5.0),
        (10, L, true, 18.16, -25.0),
        (10, L, true, um(18.16 + ro), -30.0),
        (11, R, false, 24.0, -30.0),
        (12, R, false, 24.0, 5.0),
    ]);
    assert_eq!(um(ro), 3.64);
    assert_eq!(cycle(&p, "L85"), want);
}

#[test]
fn g85_alternating_branch_runs_the_g84_passes_with_run_out() {
    let src = "%1\nN10 G54 M3 S500\nN20 G00 X24 Z5\nN30 R04=120.0 R19=0.050 R21=2 R22=5.000\n R23=0 R24=-4.000 R25=-5.000 R26=1.5 R27=0 R28=0.8 R29=4\n R30=-1.840 R31=-30.000 G85\nN40 G80\nN50 M30\n";
    let p = run(&lathe_mc8(), src, PlanOptions::default());
    // The chips and shifts of G84ALTERN (n = 4): passes 1/2 of chip 1 start at Z 4.699/5.301 and
    // every G33 runs out over the last 5 mm: X 19.377 -> 19.377 + 3.639702 = 23.016702.
    let c = cycle(&p, "L85");
    assert_eq!(
        &c[..5],
        &[
            (60, R, false, 19.377, 4.699),
            (70, L, true, 19.377, -25.0),
            (70, L, true, 23.017, -30.0),
            (80, R, false, 24.0, -30.0),
            (90, R, false, 24.0, 5.0),
        ]
    );
    assert_eq!(c[5], (120, R, false, 19.377, 5.301));
    // 2 alternating chips x 2 passes + chip 3 + 1 final pass = 6 threads of 2 segments each.
    assert_eq!(c.iter().filter(|m| m.2).count(), 12);
    assert_eq!(
        c.last().copied(),
        Some((240, R, false, 24.0, 5.0)),
        "N240 returns in Z"
    );
}

#[test]
fn g86_chamfer_follows_the_spec_trace() {
    let p = plan_example(&lathe(), "G86CHAMFER");
    // Xp = Zp = 2, Dx = Dz = 4, Tx = 1: Tz = 1·4/4 = 1, a = 2·4/4 = 2, b = 2, A = 4, B = 4;
    // ΔX = A + Tx, ΔZ = B + Tz for Tx = 1, 2, 3, 4 and once more Tx = Dx = 4 (the last pass,
    // N310/N315, because Tx = Dx is not > Dx): (5,5) (6,6) (7,7) (8,8) (8,8) (spec §5.10 trace).
    // Each pass from (30, 10), incremental: G00 X+Δ; G01 X-Δ Z+Δ at F100; G00 Z-Δ.
    let mut want: Vec<Move> = Vec::new();
    for d in [5.0, 6.0, 7.0, 8.0, 8.0] {
        want.extend([
            (240, R, false, 30.0 + d, 10.0),
            (250, L, false, 30.0, 10.0 + d),
            (260, R, false, 30.0, 10.0),
        ]);
    }
    assert_eq!(cycle(&p, "L86"), want);
    assert!(
        p.blocks
            .iter()
            .filter(|c| c.n == Some(250))
            .all(|c| c.feed == Some(100.0))
    );
}

#[test]
fn g86_signs_of_r24_r25_give_the_direction_and_g90_is_restored() {
    let src = "%1\nN10 G54 M3 S500\nN20 G00 X30 Z10\nN30 R24=-2. R25=-2. R26=100 R28=1.5 R30=-3. R31=6.\n G86\nN40 G80 X40\nN50 M30\n";
    let p = run(&lathe(), src, PlanOptions::default());
    // Signs from R24, R25 only: sX = sZ = -1; |R30| = 3, |R31| = 6, Tx = 1.5.
    // Tz = 1.5·6/3 = 3; a = 2·3/6 = 1; b = 2·6/3 = 4; A = 1 + 2 = 3; B = 4 + 2 = 6.
    // Tx = 1.5: ΔX = -(3 + 1.5) = -4.5, ΔZ = -(6 + 3) = -9.
    // Tx = 3 (= Dx, a normal pass): Tz = 6, ΔX = -6, ΔZ = -12.
    // Tx = 4.5 > 3: Tx := 3, last pass again: ΔX = -6, ΔZ = -12.
    let mut want: Vec<Move> = Vec::new();
    for (dx, dz) in [(-4.5, -9.0), (-6.0, -12.0), (-6.0, -12.0)] {
        want.extend([
            (240, R, false, 30.0 + dx, 10.0),
            (250, L, false, 30.0, 10.0 + dz),
            (260, R, false, 30.0, 10.0),
        ]);
    }
    assert_eq!(cycle(&p, "L86"), want);
    // The cycle's G91 is undone after it: X40 in N40 is absolute.
    let n40 = p.blocks.iter().find(|c| c.n == Some(40)).expect("N40");
    assert_eq!((end(n40, 'X'), end(n40, 'Z')), (40.0, 10.0));
}

#[test]
fn g87_taper_thread_rises_by_r22_and_tests_r39_greater_than_zero() {
    let p = plan_example(&lathe(), "G87TAPER");
    // Chips as in G85RUNOUT (n = 3): X1 = 19.246, X2 = 18.643, Xf = 18.16; every G33 ends at
    // X + R22 = X + 2 at Z -30. Final passes: R39 = R23 = 2, N9 decrements to 1 (1 > 0: again),
    // then 0 (not > 0): 2 passes, where G84's >= would make R23 + 1 = 3.
    let mut want: Vec<Move> = Vec::new();
    for x in [19.246, 18.643] {
        want.extend([
            (50, R, false, x, 5.0),
            (6, L, true, um(x + 2.0), -30.0),
            (7, R, false, 24.0, -30.0),
            (8, R, false, 24.0, 5.0),
        ]);
    }
    for _ in 0..2 {
        want.extend([
            (9, R, false, 18.16, 5.0),
            (10, L, true, 20.16, -30.0),
            (11, R, false, 24.0, -30.0),
            (12, R, false, 24.0, 5.0),
        ]);
    }
    assert_eq!(cycle(&p, "L87"), want);
}

#[test]
fn g84_setup_words_give_the_spec_values() {
    // Spec §4.3 vectors from lathe G84 N30/N40, run as the cycle runs them (declarations first).
    let p = run(
        &lathe(),
        "%1\nN1 R26=1.5 R03=+2.000 G26 R05=+04260337\nN2 R18=34.000 G26 R05=+03182641\nN3 M30\n",
        PlanOptions::default(),
    );
    assert_eq!((p.params[37], p.params[41]), (750, 51_000));
}
