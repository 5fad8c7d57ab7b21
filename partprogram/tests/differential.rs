//! Differential tests: random parameter programs run natively and in the reference interpreter must
//! give the same parameters, canonical blocks and errors.

mod common;

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
