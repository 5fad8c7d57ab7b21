//! Benchmarks: a generated 100,000-block CAM program checked and planned (target ≤ 1 s; with G42 radius
//! compensation on a 100,000-block circular contour), and parameter
//! arithmetic in native code against the reference interpreter (target ≥ 10× faster): the block
//! functions alone (`arith/*_16_ops`), the same operations as a planned parameter loop
//! (`arith/*_plan_16k_ops`, native regions), and a loop-heavy parameter program with a conditional
//! jump (`param_loop`).

use detmath::Det as _;
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use partprogram::arith::ArithState;
use partprogram::{Backend, Dialect, DoublePrecision, MachineSpec, PlanOptions, compile, plan};

fn cam_program(blocks: usize) -> String {
    let mut s = String::with_capacity(blocks * 40);
    s.push_str(
        "%1 \"generated CAM program\"\nN1 G54 G90 G17 G00 X0 Y0 Z5 M03 S2000\nN2 G01 Z-1 F800\n",
    );
    let (mut px, mut py) = (0.0f64, 0.0f64);
    let r3 = |v: f64| (v * 1000.0).round() / 1000.0;
    let mut n = 3;
    while n < blocks {
        if n % 10 == 0 {
            // A half circle of radius 1 from the current point, centre 1 mm along +X.
            px = r3(px + 2.0);
            s.push_str(&format!("N{n} G02 X{px:.3} Y{py:.3} I1 J0\n"));
        } else {
            let t = n as f64 * 0.01;
            px = r3(t.dcos() * 50.0);
            py = r3(t.dsin() * 50.0);
            let z = -1.0 - (n % 7) as f64 * 0.1;
            s.push_str(&format!("N{n} G01 X{px:.3} Y{py:.3} Z{z:.3}\n"));
        }
        n += 1;
    }
    s.push_str(&format!("N{n} G00 Z50 M05\nN{} M30\n", n + 1));
    s
}

/// A gouge-free contour for radius compensation: `blocks` chords of 0.5 mm along a circle of radius 50
/// (counter-clockwise, winding round many times), every 10th block a G03 arc on the same circle.
fn cam_contour(blocks: usize) -> String {
    let mut s = String::with_capacity(blocks * 40);
    s.push_str(
        "%1 \"generated CAM contour\"\nN1 G54 G90 G17 G00 X50 Y0 Z5 M03 S2000\nN2 G92 D1 R0=0.2\n\
         N3 G01 G42 D1 Z-1 F800\n",
    );
    let (mut px, mut py) = (50.0f64, 0.0f64);
    let r3 = |v: f64| (v * 1000.0).round() / 1000.0;
    let mut n = 4;
    while n < blocks {
        let t = n as f64 * 0.01;
        let (x, y) = (r3(t.dcos() * 50.0), r3(t.dsin() * 50.0));
        if n % 10 == 0 {
            s.push_str(&format!(
                "N{n} G03 X{x:.3} Y{y:.3} I{:.3} J{:.3}\n",
                -px, -py
            ));
        } else {
            let z = -1.0 - (n % 7) as f64 * 0.1;
            s.push_str(&format!("N{n} G01 X{x:.3} Y{y:.3} Z{z:.3}\n"));
        }
        (px, py) = (x, y);
        n += 1;
    }
    s.push_str(&format!("N{n} G00 G40 Z50 M05\nN{} M30\n", n + 1));
    s
}

fn bench_cam(c: &mut Criterion) {
    let src = cam_program(100_000);
    let machine = MachineSpec::new(Dialect::Mefi, &['X', 'Y', 'Z']);
    let mut g = c.benchmark_group("cam_100k");
    g.sample_size(10);
    g.bench_function("check_and_plan", |b| {
        b.iter(|| {
            let (prog, diags) = compile(&machine, "cam", black_box(&src));
            let prog = prog.unwrap_or_else(|| panic!("{diags:?}"));
            let p = plan(&prog, PlanOptions::default()).unwrap_or_else(|e| panic!("{}", e.1));
            assert_eq!(p.blocks.len(), 100_001);
            black_box(p.blocks.len())
        })
    });
    // Radius compensation on every block: G42 with a 0.2 mm radius on the circular contour (tool
    // outside, a corner arc inserted at every chord corner). The CAM program above is not used here:
    // its zigzag (lines back over the path next to the half circles) gouges with any tool radius
    // (2512, e.g. at N319 with 0.2 mm: the tool centre at the N318/N319 joint is 0.033 mm from the arc
    // N320), so the planner would stop after a few hundred blocks.
    let contour = cam_contour(100_000);
    g.bench_function("check_and_plan_g42", |b| {
        b.iter(|| {
            let (prog, diags) = compile(&machine, "cam", black_box(&contour));
            let prog = prog.unwrap_or_else(|| panic!("{diags:?}"));
            let p = plan(&prog, PlanOptions::default()).unwrap_or_else(|e| panic!("{}", e.1));
            assert!(p.blocks.len() > 100_001);
            black_box(p.blocks.len())
        })
    });
    g.bench_function("check_plan_and_json", |b| {
        b.iter(|| {
            let (prog, _) = compile(&machine, "cam", black_box(&src));
            let prog = prog.unwrap_or_else(|| panic!("compile"));
            let p = plan(&prog, PlanOptions::default()).unwrap_or_else(|e| panic!("{}", e.1));
            let mut out = String::with_capacity(p.blocks.len() * 150);
            for c in &p.blocks {
                out.push_str(&c.to_json_line());
                out.push('\n');
            }
            black_box(out.len())
        })
    });
    g.finish();
}

/// Four sequences of four operations each (sum, difference, product, quotient, comparison, abs,
/// negation, increment, decrement, int→real, odd test, square, real→int): they read R10..R33 and write
/// R40..R49 only, so repeated runs give the same values and no run-time errors.
fn words() -> Vec<Vec<i64>> {
    let w = |raw: bool, op: i64, a: i64, b: i64, c: i64| {
        (if raw { -1 } else { 1 }) * (op * 1_000_000 + a * 10_000 + b * 100 + c)
    };
    vec![
        vec![
            w(false, 1, 10, 11, 40),
            w(false, 2, 12, 13, 41),
            w(false, 3, 14, 15, 42),
            w(false, 3, 16, 17, 43),
        ],
        vec![
            w(false, 15, 18, 19, 44),
            w(false, 4, 20, 21, 45),
            w(false, 7, 22, 0, 46),
            w(false, 8, 23, 0, 47),
        ],
        vec![
            w(true, 41, 24, 2, 48),
            w(false, 42, 25, 3, 49),
            w(false, 23, 26, 0, 40),
            w(false, 19, 27, 28, 41),
        ],
        vec![
            w(false, 46, 29, 0, 42),
            w(false, 5, 30, 0, 43),
            w(false, 24, 31, 0, 44),
            w(true, 17, 32, 33, 45),
        ],
    ]
}

fn seeded() -> ArithState {
    let mut st = ArithState::default();
    for (i, r) in st.r.iter_mut().enumerate() {
        *r = 1000 + (i as i64 * 7919) % 50_000;
    }
    st
}

fn bench_arith(c: &mut Criterion) {
    let words = words();
    let todo: Vec<(usize, Vec<i64>)> = words.iter().cloned().enumerate().collect();
    let native = partprogram::jit::compile_words(&todo, DoublePrecision::Enabled)
        .unwrap_or_else(|e| panic!("{e}"));
    // Same results from both engines.
    let mut a = seeded();
    let mut b = seeded();
    for (i, w) in words.iter().enumerate() {
        assert_eq!(native.call(i, &mut a), 0);
        assert!(b.exec_seq(w).is_ok());
    }
    assert_eq!(a.r, b.r);
    let mut g = c.benchmark_group("arith");
    g.bench_function("native_16_ops", |bch| {
        let mut st = seeded();
        bch.iter(|| {
            for i in 0..4 {
                black_box(native.call(black_box(i), &mut st));
            }
            black_box(st.r[45])
        })
    });
    g.bench_function("interpreter_16_ops", |bch| {
        let mut st = seeded();
        bch.iter(|| {
            for w in &words {
                black_box(st.exec_seq(black_box(w)).is_ok());
            }
            black_box(st.r[45])
        })
    });
    // The same 16 operations as four G29 blocks of a planned program, looped 1000 times by G73.
    let mut src = String::from("%1\nN1");
    for (i, r) in seeded().r.iter().enumerate().skip(10).take(24) {
        src.push_str(&format!(" R{i}={r}"));
    }
    for (k, ws) in words.iter().enumerate() {
        src.push_str(&format!("\nN{} G29", k + 2));
        for (j, w) in ws.iter().enumerate() {
            src.push_str(&format!(" R{}={w:+}", 5 + j));
        }
    }
    src.push_str("\nN6 G73 L2 Q999\nN7 M30\n");
    let prog = compiled(&src);
    let a = planned(&prog, Backend::Native);
    let b = planned(&prog, Backend::Interpreter);
    assert_eq!((a.params, a.executed), (b.params, b.executed));
    assert_eq!(a.executed, 1 + 1000 * 5 + 1);
    for (name, backend) in [
        ("native_plan_16k_ops", Backend::Native),
        ("interpreter_plan_16k_ops", Backend::Interpreter),
    ] {
        g.bench_function(name, |bch| {
            bch.iter(|| black_box(planned(black_box(&prog), backend).params[45]))
        });
    }
    g.finish();
}

fn compiled(src: &str) -> partprogram::Program {
    let machine = MachineSpec::new(Dialect::Mefi, &['X', 'Y', 'Z']);
    let (prog, diags) = compile(&machine, "bench", src);
    prog.unwrap_or_else(|| panic!("{diags:?}"))
}

fn planned(prog: &partprogram::Program, backend: Backend) -> partprogram::Plan {
    plan(
        prog,
        PlanOptions {
            backend,
            ..PlanOptions::default()
        },
    )
    .unwrap_or_else(|e| panic!("{}", e.1))
}

/// A loop-heavy parameter program: 10,000 iterations of four operations (count, sum, product,
/// comparison) and a conditional jump `GR10 L2 Q9999`.
fn bench_param_loop(c: &mut Criterion) {
    let prog = compiled(
        "%1\nN1 R1=0 R2=0 R3=10000 R4=0 R9=3\n\
         N2 G29 R5=-41020002 R6=-01010201 R7=-03020904 R8=-17020310\n\
         N3 GR10 L2 Q9999\nN4 M30\n",
    );
    for backend in [Backend::Native, Backend::Interpreter] {
        let p = planned(&prog, backend);
        assert_eq!(p.params[1], 10_000 * 10_001 / 2);
        assert_eq!((p.params[2], p.params[4]), (10_000, 30_000));
        assert_eq!(p.executed, 1 + 10_000 * 2 + 1);
    }
    let mut g = c.benchmark_group("param_loop");
    for (name, backend) in [
        ("native_10k_iterations", Backend::Native),
        ("interpreter_10k_iterations", Backend::Interpreter),
    ] {
        g.bench_function(name, |bch| {
            bch.iter(|| black_box(planned(black_box(&prog), backend).params[1]))
        });
    }
    g.finish();
}

criterion_group!(benches, bench_cam, bench_arith, bench_param_loop);
criterion_main!(benches);
