//! Differential tests: random parameter programs run natively and in the reference interpreter must
//! give the same parameters, canonical blocks and errors.

use crate::common;

use common::*;
use partprogram::{Backend, PlanOptions, compile, plan};
use proptest::prelude::*;

fn word() -> impl Strategy<Value = String> {
    let op = prop_oneof![
        8 => prop::sample::select(vec![0u8, 1, 2, 3, 4, 5, 7, 8, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 29, 30, 31, 32, 41, 42, 46, 47]),
        2 => prop::sample::select(vec![6u8, 9, 10, 14, 27, 28, 34, 35, 37, 38, 44, 45, 48]),
    ];
    let field = prop_oneof![9 => 10u8..40, 1 => 0u8..99];
    (any::<bool>(), op, field.clone(), field.clone(), field).prop_map(|(neg, op, a, b, c)| {
        let (a, b, c) = if op == 48 {
            (10 + a % 80, b % 40, c % 40)
        } else {
            (a, b, c)
        };
        format!("{}{op:02}{a:02}{b:02}{c:02}", if neg { "-" } else { "+" })
    })
}

fn value() -> impl Strategy<Value = String> {
    prop_oneof![
        (-99_999i64..99_999).prop_map(|v| v.to_string()),
        (-9_999i64..9_999, 0u32..1000).prop_map(|(i, f)| format!("{i}.{f:03}")),
        Just("0".to_string()),
    ]
}

fn block() -> impl Strategy<Value = String> {
    (
        proptest::collection::vec((10u8..40, value()), 0..6),
        proptest::collection::vec(word(), 1..5),
    )
        .prop_map(|(decls, words)| {
            let mut s = String::new();
            for (p, v) in decls {
                s.push_str(&format!(" R{p}={v}"));
            }
            let g = 25 + words.len();
            s.push_str(&format!(" G{g}"));
            for (k, w) in words.iter().enumerate() {
                s.push_str(&format!(" R{}={w}", 5 + k));
            }
            s
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, .. ProptestConfig::default() })]

    #[test]
    fn native_matches_interpreter(blocks in proptest::collection::vec(block(), 1..8)) {
        let mut src = String::from("%1\n");
        for (i, b) in blocks.iter().enumerate() {
            src.push_str(&format!("N{}{b} XR{}\n", i + 1, 10 + i));
        }
        src.push_str("N99 M30\n");
        let (prog, diags) = compile(&mill(), "diff", &src);
        let prog = prog.unwrap_or_else(|| panic!("{src}\n{diags:?}"));
        let run = |backend| match plan(&prog, PlanOptions { backend, ..PlanOptions::default() }) {
            Ok(p) => Ok((p.params, p.blocks)),
            Err((b, d)) => Err((b, d.code, d.message)),
        };
        let a = run(Backend::Interpreter);
        let b = run(Backend::Native);
        prop_assert_eq!(a, b, "{}", src);
    }
}

#[test]
fn native_code_is_generated_for_static_words() {
    let (prog, _) = compile(
        &mill(),
        "t",
        "%1\nN1 R1=5 G26 R5=01010102\nN2 G26\nN3 M30\n",
    );
    let prog = prog.expect("compiles");
    assert!(
        prog.blocks[0].native.is_some(),
        "declared control word → native"
    );
    assert!(
        prog.blocks[1].native.is_none(),
        "control word from an earlier block → interpreter"
    );
}

/// One block of a random parameter program with control flow; targets are block positions taken
/// modulo the program length by [`flow_program`].
fn flow_item() -> impl Strategy<Value = (u8, String, u8, bool)> {
    let q = prop_oneof![
        (0u8..4).prop_map(|q| format!(" Q{}", q.max(1))),
        Just(String::new()),
        Just(" Q9999".to_string()),
        (40u8..45).prop_map(|p| format!(" QR{p}")),
    ];
    let flag = prop_oneof![
        (10u8..21).prop_map(|p| p.to_string()),
        (40u8..45).prop_map(|p| p.to_string())
    ];
    let body = prop_oneof![
        4 => block(),
        2 => q.clone().prop_map(|q| format!(" G73 L@{q}")),
        3 => ((40u8..45), q).prop_map(|(p, q)| format!(" GR{p} L@{q}")),
        3 => ((15u8..20), (10u8..21), (10u8..21), flag.clone()).prop_map(|(op, a, b, c)| format!(" G26 R5=+{op}{a:02}{b:02}{c:0>2}")),
        1 => (10u8..21).prop_map(|p| format!(" G1 XR{p} F100")),
        2 => (flag, prop::sample::select(vec![73i64, 78, 0, 1, 5, 81, 120])).prop_map(|(p, v)| format!(" R{p}={v}")),
        1 => ((-3i64..3), (10u8..21)).prop_map(|(d, p)| format!(" R{p}={d} G26 R5=-41{p}00{p}")),
    ];
    (any::<u8>(), body, any::<u8>(), prop::bool::weighted(0.15))
}

/// Builds the text of a flow program: `N1` seeds the flags R40..R44, then the items, then `M30`.
fn flow_program(seed: &[bool; 5], items: &[(u8, String, u8, bool)]) -> String {
    let mut src = String::from("%1\nN1");
    for (i, &s) in seed.iter().enumerate() {
        src.push_str(&format!(" R{}={}", 40 + i, if s { 73 } else { 78 }));
    }
    src.push('\n');
    let n = items.len() + 1;
    for (i, (_, body, t, skip)) in items.iter().enumerate() {
        let target = 1 + usize::from(*t) % n;
        let body = body.replace('@', &target.to_string());
        let mark = if *skip { " /" } else { "" };
        src.push_str(&format!("N{}{mark}{body}\n", i + 2));
    }
    src.push_str(&format!("N{} M30\n", n + 1));
    src
}

type Outcome =
    Result<([i64; 96], Vec<partprogram::Canon>, u64), (Vec<partprogram::Canon>, u32, String, u32)>;

fn outcome(prog: &partprogram::Program, opts: PlanOptions) -> Outcome {
    match plan(prog, opts) {
        Ok(p) => Ok((p.params, p.blocks, p.executed)),
        Err((b, d)) => Err((b, d.code, d.message, d.line)),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, .. ProptestConfig::default() })]

    /// Loops, counted and conditional jumps, computed G words that leave the region, motion inside
    /// loops, block skip and the executed-block limit: native regions and the interpreter agree on
    /// parameters, canonical blocks, executed count and errors.
    #[test]
    fn native_regions_match_interpreter(
        seed in any::<[bool; 5]>(),
        items in proptest::collection::vec(flow_item(), 1..9),
        block_skip in any::<bool>(),
    ) {
        // Without a macro folder (compiling the mill's cycles for every case would dominate).
        let machine = partprogram::MachineSpec::new(partprogram::Dialect::Mefi, &['X', 'Y', 'Z']);
        let (a, b) = flow_outcomes(&machine, &seed, &items, block_skip);
        prop_assert_eq!(a, b, "{}", flow_program(&seed, &items));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, .. ProptestConfig::default() })]

    /// The same with the mill's macro folder: computed `GR<n>` = 81 starts its fixed cycle.
    #[test]
    fn native_regions_match_interpreter_with_cycles(
        seed in any::<[bool; 5]>(),
        items in proptest::collection::vec(flow_item(), 1..9),
        block_skip in any::<bool>(),
    ) {
        let (a, b) = flow_outcomes(&mill(), &seed, &items, block_skip);
        prop_assert_eq!(a, b, "{}", flow_program(&seed, &items));
    }
}

/// Plans the flow program with both back ends at two block limits; (interpreter, native).
fn flow_outcomes(
    machine: &partprogram::MachineSpec,
    seed: &[bool; 5],
    items: &[(u8, String, u8, bool)],
    block_skip: bool,
) -> (Vec<Outcome>, Vec<Outcome>) {
    let src = flow_program(seed, items);
    let (prog, diags) = compile(machine, "flow", &src);
    let prog = prog.unwrap_or_else(|| panic!("{src}\n{diags:?}"));
    let run = |backend| {
        [3000, 517]
            .map(|max_blocks| {
                let opts = PlanOptions {
                    backend,
                    block_skip,
                    max_blocks,
                    ..PlanOptions::default()
                };
                outcome(&prog, opts)
            })
            .to_vec()
    };
    (run(Backend::Interpreter), run(Backend::Native))
}
