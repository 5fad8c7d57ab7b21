//! Source-level differential test: random PLC statement text (ladder rungs, comparisons, byte
//! arithmetic, SET/RES, one-shots, inline timers, IF zones, a SLOW part) goes through the front
//! end; the JIT and the interpreter must then agree bit for bit after every tick.

use std::sync::Arc;

use compiler::{Engine, Interpreter, MachineContext, compile};
use proptest::prelude::*;

fn bit_read() -> BoxedStrategy<String> {
    prop_oneof![
        (0u8..2, 0u8..32).prop_map(|(c, n)| format!("I{c}A{n}")),
        (4u8..6, 0u8..32).prop_map(|(c, n)| format!("U{c}A{n}")),
        (0u8..10, 0u8..32).prop_map(|(c, n)| format!("I{c}K{n}")),
        (100u8..104, 0u8..32).prop_map(|(c, n)| format!("U{c}K{n}")),
    ]
    .boxed()
}

fn byte_read() -> BoxedStrategy<String> {
    prop_oneof![
        (0u8..2, 0u8..4).prop_map(|(c, b)| format!("W{c}A{b}")),
        (0u8..10, 0u8..4).prop_map(|(c, b)| format!("W{c}K{b}")),
        (100u8..104, 0u8..4).prop_map(|(c, b)| format!("W{c}K{b}")),
    ]
    .boxed()
}

fn byte_expr() -> BoxedStrategy<String> {
    let lit = (0u16..256).prop_map(|v| v.to_string());
    let leaf = prop_oneof![byte_read(), lit].boxed();
    // The left operand is always a byte signal (two bare literals are typed DINT by the front end).
    (
        byte_read(),
        proptest::sample::select(vec!["+", "-", "*", "/", "MOD", "&", "|", "^"]),
        leaf,
    )
        .prop_map(|(a, op, b)| format!("{a} {op} {b}"))
        .boxed()
}

fn bool_expr(depth: u32) -> BoxedStrategy<String> {
    let cmp = (
        byte_read(),
        proptest::sample::select(vec!["=", "<>", "<", "<=", ">", ">="]),
        0u16..256,
    )
        .prop_map(|(a, op, v)| format!("[{a}{op}{v}]"));
    let leaf = prop_oneof![4 => bit_read(), 1 => cmp].boxed();
    if depth == 0 {
        return leaf;
    }
    let sub = bool_expr(depth - 1);
    prop_oneof![
        2 => leaf,
        1 => sub.clone().prop_map(|e| format!("/{e}")),
        1 => (sub.clone(), sub.clone()).prop_map(|(a, b)| format!("{a}*{b}")),
        1 => (sub.clone(), sub.clone()).prop_map(|(a, b)| format!("{a}+{b}")),
        1 => (sub.clone(), sub).prop_map(|(a, b)| format!("({a}+{b})")),
    ]
    .boxed()
}

fn bit_target() -> BoxedStrategy<String> {
    prop_oneof![
        (4u8..6, 0u8..32).prop_map(|(c, n)| format!("U{c}A{n}")),
        (100u8..104, 0u8..32).prop_map(|(c, n)| format!("U{c}K{n}")),
    ]
    .boxed()
}

/// One line (or an IF zone). Pulses get unique numbers from the caller through `slot`.
fn statement(depth: u32) -> BoxedStrategy<Vec<String>> {
    let flat = prop_oneof![
        4 => (bit_target(), bool_expr(2)).prop_map(|(t, e)| vec![format!("{t}={e}")]),
        1 => (any::<bool>(), bit_target(), bool_expr(1))
            .prop_map(|(s, t, e)| vec![format!("{} {t}={e}", if s { "SET" } else { "RES" })]),
        1 => ((100u8..104, 0u8..4), byte_expr()).prop_map(|((c, b), e)| vec![format!("W{c}K{b}={e}")]),
        1 => (bit_target(), proptest::sample::select(vec!["TON", "TOF", "TP"]), bool_expr(1), 0u32..60)
            .prop_map(|(t, k, e, ms)| vec![format!("{t}={k}({e}, {ms}ms)")]),
        1 => bool_expr(1).prop_map(|e| vec![format!("PULSE={e}")]),
    ]
    .boxed();
    if depth == 0 {
        return flat;
    }
    let zone = (
        bool_expr(1),
        proptest::collection::vec(statement(depth - 1), 1..4),
    )
        .prop_map(|(c, body)| {
            let mut v = vec![format!("IF {c} THEN")];
            v.extend(body.into_iter().flatten());
            v.push("END_IF".to_string());
            v
        });
    prop_oneof![5 => flat, 1 => zone].boxed()
}

fn source() -> impl Strategy<Value = String> {
    (
        proptest::collection::vec(statement(1), 1..12),
        proptest::collection::vec(statement(1), 0..6),
    )
        .prop_map(|(fast, slow)| {
            let mut pulse = 0;
            let mut text = String::new();
            let mut emit = |lines: Vec<Vec<String>>, text: &mut String| {
                for line in lines.into_iter().flatten() {
                    // Each one-shot gets its own number (a pulse has exactly one driving statement).
                    let line = if let Some(rest) = line.strip_prefix("PULSE=") {
                        pulse += 1;
                        format!("P{pulse}={rest}")
                    } else {
                        line
                    };
                    text.push_str(&line);
                    text.push('\n');
                }
            };
            emit(fast, &mut text);
            if !slow.is_empty() {
                text.push_str("$\n");
                emit(slow, &mut text);
            }
            text
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn compiled_source_runs_identically_on_both_engines(
        src in source(),
        ticks in proptest::collection::vec(proptest::collection::vec((0usize..1280, any::<u8>()), 0..6), 1..16),
    ) {
        let ctx = MachineContext { time_slow_ms: 0, ..MachineContext::lathe_like() };
        let c = compile("random", src.as_bytes(), &ctx);
        let errors: Vec<_> = c.diagnostics.iter().filter(|d| d.severity == diag::Severity::Error).collect();
        prop_assert!(c.program.is_some(), "front end rejected generated source:\n{src}\n{errors:#?}");
        let p = Arc::new(c.program.expect("checked above"));
        let mut interp = Interpreter::new(p.clone());
        let mut jit = compiler::jit::compile(&p).expect("jit");
        let (mut a, mut b) = (p.new_image(), p.new_image());
        for (t, pokes) in ticks.iter().enumerate() {
            for &(at, v) in pokes {
                a[at] = v;
                b[at] = v;
            }
            interp.tick(&mut a);
            jit.tick(&mut b);
            let diff: Vec<_> = (0..a.len()).filter(|&i| a[i] != b[i]).map(|i| (i, a[i], b[i])).collect();
            prop_assert!(diff.is_empty(), "tick {t}: (offset, interp, jit) {diff:?}\n{src}");
        }
    }
}
