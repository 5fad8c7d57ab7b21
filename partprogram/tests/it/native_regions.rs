//! Golden tests of the native regions: parameter loops with hand-computed results, run by both back
//! ends, and checks that the regions are actually compiled for the blocks they should cover.

use crate::common;

use common::*;
use partprogram::{Backend, Kind, PlanOptions, Program, compile, plan};

fn prog(src: &str) -> Program {
    let (p, diags) = compile(&mill(), "golden", src);
    p.unwrap_or_else(|| panic!("{diags:#?}"))
}

fn both(p: &Program, opts: PlanOptions) -> [partprogram::Plan; 2] {
    [Backend::Native, Backend::Interpreter].map(|backend| {
        plan(p, PlanOptions { backend, ..opts }).unwrap_or_else(|(_, d)| panic!("{backend:?}: {d}"))
    })
}

/// The error each back end stops `p` with (native first), panicking with `what` if one plans it.
fn both_err(p: &Program, what: &str) -> [(Backend, diag::Diagnostic); 2] {
    [Backend::Native, Backend::Interpreter].map(|backend| {
        let opts = PlanOptions {
            backend,
            ..PlanOptions::default()
        };
        match plan(p, opts) {
            Err((_, d)) => (backend, d),
            Ok(_) => panic!("{backend:?}: {what}"),
        }
    })
}

/// Regions of the blocks with the given indices (None: interpreted).
fn regions(p: &Program, blocks: std::ops::Range<usize>) -> Vec<Option<usize>> {
    let native = p.native.as_ref().expect("native code");
    blocks.map(|bi| native.region_at(bi)).collect()
}

#[test]
fn loop_sums_one_to_hundred() {
    // R2 counts 1..100 (raw increment), R1 sums, R10 = R2 < R3 ? 73 : 78; `GR10 L2 Q9999` loops.
    // N4 and N5 read the G groups 4 and 7 through op 49 (table 5, column 2).
    let p = prog(
        "%1\nN1 R1=0 R2=0 R3=100\nN2 G28 R5=-41020002 R6=-01010201 R7=-17020310\n\
         N3 GR10 L2 Q9999\nN4 G26 R5=49520411\nN5 G26 R5=49520712\nN6 M30\n",
    );
    assert_eq!(
        regions(&p, 0..6),
        vec![Some(0), Some(0), Some(0), Some(0), Some(0), None]
    );
    for plan in both(&p, PlanOptions::default()) {
        assert_eq!(plan.params[1], 5050);
        assert_eq!(plan.params[2], 100);
        assert_eq!(plan.params[10], 78);
        assert_eq!(plan.params[11], 28, "group 4 before N4: G28 of N2");
        assert_eq!(plan.params[12], 78, "group 7: the G78 of the last N3");
        assert_eq!(plan.executed, 1 + 100 * 2 + 3);
        assert_eq!(plan.blocks.len(), 1, "only the M30 block");
    }
}

#[test]
fn nested_g73_counts() {
    // The inner jump runs N2 three times per pass (Q2), the outer four passes (Q3): its counter
    // re-arms after it has run out.
    let p = prog(
        "%1\nN1 R1=0 R2=0\nN2 G26 R5=-41010001\nN3 G73 L2 Q2\nN4 G26 R5=-41020002\n\
         N5 G73 L2 Q3\nN6 M30\n",
    );
    assert!(regions(&p, 0..5).iter().all(Option::is_some));
    for plan in both(&p, PlanOptions::default()) {
        assert_eq!((plan.params[1], plan.params[2]), (12, 4));
        assert_eq!(plan.executed, 1 + 4 * (3 + 3 + 1 + 1) + 1);
    }
}

#[test]
fn endless_loop_stops_at_the_exact_block() {
    // N1/N2 alternate 10,000 times (#1..#20000), N3 jumps back (#20001), N1/N2 again
    // (#20002..#40001, N1 at even counts), N3 (#40002), then N1 at odd counts from #40003.
    let p = prog("%1\nN1 G26 R5=-41010001\nN2 G73 L1 Q9999\nN3 G73 L1 Q9999\nN4 M30\n");
    for (max_blocks, line) in [(50_000u64, 2u32), (50_001, 3), (20_000, 4), (40_001, 4)] {
        for backend in [Backend::Native, Backend::Interpreter] {
            let opts = PlanOptions {
                backend,
                max_blocks,
                ..PlanOptions::default()
            };
            let Err((blocks, d)) = plan(&p, opts) else {
                panic!("{backend:?} {max_blocks}: no error");
            };
            assert_eq!(d.code, 2504, "{backend:?}");
            assert_eq!(d.line, line, "{backend:?} {max_blocks}");
            assert_eq!(
                d.message,
                format!("more than {max_blocks} blocks executed: endless loop?")
            );
            assert!(blocks.is_empty());
        }
    }
}

#[test]
fn motion_inside_a_parameter_loop() {
    let p = prog(
        "%1\nN1 R1=0 R2=5\nN2 G26 R5=-41010001\nN3 G91 G1 X1 F100\nN4 G26 R5=+17010210\n\
         N5 GR10 L2 Q9999\nN6 M30\n",
    );
    for plan in both(&p, PlanOptions::default()) {
        let lines: Vec<f64> = plan
            .blocks
            .iter()
            .filter(|c| c.kind == Kind::Linear)
            .map(|c| end(c, 'X'))
            .collect();
        assert_eq!(lines, vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        assert_eq!(plan.params[1], 5);
        assert_eq!(plan.executed, 1 + 5 * 4 + 1);
    }
}

#[test]
fn computed_g_other_than_73_78_leaves_the_region() {
    // R10=1: `GR10 L4` is G01, which has no use for L: the native region hands N2 to the
    // interpreter, which refuses the L it would ignore (2530) for both back ends.
    let p = prog("%1\nN1 R10=1 R20=0\nN2 GR10 L4\nN3 G26 R5=-41200020\nN4 X5 F100\nN5 M30\n");
    assert!(regions(&p, 0..3).iter().all(Option::is_some));
    for (backend, d) in both_err(&p, "L of a computed G01 was ignored") {
        assert_eq!((d.code, d.line), (2530, 3), "{backend:?}");
    }
    // Without L, the computed G01 is a G01: N4 then moves at feed.
    let p = prog("%1\nN1 R10=1 R20=0\nN2 GR10\nN3 G26 R5=-41200020\nN4 X5 F100\nN5 M30\n");
    for plan in both(&p, PlanOptions::default()) {
        assert_eq!(plan.blocks[0].kind, Kind::Linear);
        assert_eq!(end(&plan.blocks[0], 'X'), 5.0);
        assert_eq!(plan.params[20], 1);
        assert_eq!(plan.executed, 5);
    }
    // R10=123 does not fit G: the interpreter reports it at N2 for both back ends.
    let p = prog("%1\nN1 R10=123\nN2 GR10 L1\nN3 M30\n");
    for (backend, d) in both_err(&p, "no error") {
        assert_eq!((d.code, d.line), (2502, 3), "{backend:?}");
    }
}

#[test]
fn arithmetic_error_in_a_loop_is_located() {
    // R1 = 2, 1, 0: the third pass divides by zero in N2.
    let p = prog("%1\nN1 R1=3 R3=100\nN2 G27 R5=-42010001 R6=-04030104\nN3 G73 L2 Q9\nN4 M30\n");
    for (backend, d) in both_err(&p, "no error") {
        assert_eq!((d.code, d.line), (2500, 3), "{backend:?}");
        assert_eq!(d.message, "parameter arithmetic: division by zero");
    }
}

#[test]
fn block_skip_inside_a_region() {
    let p = prog(
        "%1\nN1 R1=0 R2=0\nN2 / G26 R5=-41010001\nN3 G26 R5=-41020002\nN4 G73 L2 Q4\nN5 M30\n",
    );
    for (block_skip, r1) in [(false, 5), (true, 0)] {
        for plan in both(
            &p,
            PlanOptions {
                block_skip,
                ..PlanOptions::default()
            },
        ) {
            assert_eq!((plan.params[1], plan.params[2]), (r1, 5));
            assert_eq!(plan.executed, 1 + 5 * 3 + 1);
        }
    }
}

#[test]
fn active_fixed_cycle_runs_after_every_region_block() {
    // With G81 active every block calls the cycle, so the loop must not run as a region.
    let p = prog(
        "%1\nN20 X50 G0\nN30 R26=400 R27=200 R30=5.0 R31=-85.0 R32=25.0 R1=0\nN40 M3 M41\n\
         N50 X100 G00 G81\nN60 G26 R5=-41010001\nN70 G73 L60 Q2\nN80 G80\nN90 M30\n",
    );
    let [a, b] = both(&p, PlanOptions::default());
    assert_eq!(a.params[1], 3);
    assert_eq!(a.params, b.params);
    assert_eq!(a.blocks, b.blocks);
    assert_eq!(a.executed, b.executed);
    // The cycle runs after N50, 3 × N60 and 3 × N70: seven drillings at X100.
    let plunges = a.blocks.iter().filter(|c| c.kind == Kind::Linear).count();
    let per_cycle = plunges / 7;
    assert_eq!(plunges, per_cycle * 7);
    assert!(per_cycle >= 1);
}

#[test]
fn division_boundaries_agree() {
    // R12 = 65536 · −32768 = i32::MIN (raw); i32::MIN / 1 fits, i32::MIN / −1 does not.
    let p = prog("%1\nN1 R10=65536 R11=-32768 R13=1 G27 R5=-03101112 R6=-04121314\nN2 M30\n");
    for plan in both(&p, PlanOptions::default()) {
        assert_eq!(plan.params[14], -2_147_483_648);
    }
    let p = prog("%1\nN1 R10=65536 R11=-32768 R13=-1 G27 R5=-03101112 R6=-04121314\nN2 M30\n");
    for (backend, d) in both_err(&p, "no error") {
        assert_eq!((d.code, d.line), (2500, 2), "{backend:?}");
        assert_eq!(
            d.message,
            "parameter arithmetic: result does not fit a parameter"
        );
    }
    // Decimal 5000 / 3 (the scaled dividend 5·10⁹ needs 64 bits) and raw −7 / 2 (truncation).
    let p =
        prog("%1\nN1 R10=5000000 R11=3000 R12=-7 R13=2 G27 R5=+04101120 R6=-04121321\nN2 M30\n");
    for plan in both(&p, PlanOptions::default()) {
        assert_eq!((plan.params[20], plan.params[21]), (1_666_666, -3));
    }
}

#[test]
fn products_beyond_64_bits_overflow_in_both_back_ends() {
    // N1 writes −1 to the pair R40/R41 (R41 = 2³² − 1); R41 · R41 needs more than 64 bits.
    for word in ["-03414142", "+03414142", "+05410042"] {
        let p = prog(&format!(
            "%1\nN1 R10=-1 G26 R5=100090\nN2 G26 R5={word}\nN3 M30\n"
        ));
        assert!(regions(&p, 0..2).iter().all(Option::is_some));
        for (backend, d) in both_err(&p, &format!("{word}: no error")) {
            assert_eq!((d.code, d.line), (2500, 3), "{word} {backend:?}");
            assert_eq!(
                d.message,
                "parameter arithmetic: result does not fit a parameter"
            );
        }
    }
}
