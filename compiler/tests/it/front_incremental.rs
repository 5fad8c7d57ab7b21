//! `diagnose_incremental` (the editor's front end: cached parse segments and replayed statement
//! checks) against `compile`: the same diagnostics on every version of a text, whatever the
//! edits; and a one-character edit checks one statement again.

use compiler::parse_cache::ParseCache;
use compiler::sema::memo::CheckCache;
use compiler::{MachineContext, compile, diagnose_incremental};
use proptest::prelude::*;

/// The editor's caches for one document.
#[derive(Default)]
struct Editor {
    parse: ParseCache,
    check: CheckCache,
}

impl Editor {
    /// Diagnoses `text` incrementally and asserts it gives `compile`'s diagnostics.
    fn diagnose(&mut self, text: &str, ctx: &MachineContext) -> Vec<diag::Diagnostic> {
        let (d, _) = diagnose_incremental("t", text, ctx, &mut self.parse, &mut self.check);
        assert_eq!(d, compile("t", text.as_bytes(), ctx).diagnostics, "{text}");
        d
    }
}

fn lathe() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../plc-programs/lathe/MP0/PLCPRG"
    ))
    .expect("the lathe program")
}

#[test]
fn a_one_character_edit_checks_one_statement_again() {
    let ctx = MachineContext {
        spl: 5000,
        ..MachineContext::lathe_like()
    };
    let src = compiler::synth::synthetic_program(2_000);
    let mut ed = Editor::default();
    ed.diagnose(&src, &ctx);
    // Statements of the same text share one check (the synthetic program repeats some).
    let total = ed.check.checked + ed.check.reused;
    assert!(
        ed.check.checked > total / 2,
        "{} of {total}",
        ed.check.checked
    );
    // `V5 = V6 + DINT(W…) * 3 - V7` becomes `… * 4 …`: one statement changes.
    let at = src.len() / 2 + src[src.len() / 2..].find(") * 3").expect("a product") + 4;
    let mut edited = src.clone();
    edited.replace_range(at..at + 1, "4");
    ed.diagnose(&edited, &ctx);
    assert_eq!((ed.check.checked, ed.check.reused), (1, total - 1));
    // A new statement on top moves every span and line: all replayed, the new one checked.
    let edited = format!("U4A0 = I0A0\n{edited}");
    ed.diagnose(&edited, &ctx);
    assert_eq!((ed.check.checked, ed.check.reused), (1, total));
    // A changed DEF may change any statement's meaning: everything is checked again.
    let edited = edited.replacen("DEF V0 : DINT := 0", "DEF V0 : INT := 0", 1);
    ed.diagnose(&edited, &ctx);
    assert!(
        ed.check.checked > total / 2,
        "{} of {total}",
        ed.check.checked
    );
    assert_eq!(ed.check.checked + ed.check.reused, total + 1);
}

#[test]
fn effects_on_other_statements_are_replayed_against_the_current_text() {
    let ctx = MachineContext::lathe_like();
    let mut ed = Editor::default();
    let base = "DEF T1 : TON(100ms)\nT1 = I0A0\nU4A0 = T1 * P3\nP3 = I0A1\nT1 = I0A2\n";
    let d = ed.diagnose(base, &ctx);
    // The second driver of T1 is the only error; it names the first one's place.
    let errors: Vec<_> = d.iter().filter(|d| d.is_error()).collect();
    assert_eq!(errors.len(), 1);
    assert_eq!((errors[0].line, errors[0].column), (5, 1));
    assert_eq!(
        errors[0].message,
        "this timer's input is already driven at 2:1"
    );
    // A line above moves the first driver: the replayed error names its new place.
    let moved = format!("; a comment\n{base}");
    let d = ed.diagnose(&moved, &ctx);
    assert_eq!(ed.check.checked, 0);
    let e = d.iter().find(|d| d.is_error()).expect("the error");
    assert_eq!(e.message, "this timer's input is already driven at 3:1");
    // Without the first driver, the replayed second one is the only one: no error, and with
    // `P3 = …` gone the replayed read of P3 is never set.
    let cut = base.replace("T1 = I0A0\n", "").replace("P3 = I0A1\n", "");
    let d = ed.diagnose(&cut, &ctx);
    assert_eq!(ed.check.checked, 0);
    assert!(d.iter().all(|d| !d.is_error()));
    assert!(
        d.iter()
            .any(|d| d.message.contains("P3 is read but never assigned"))
    );
    // An undefined name is checked every time (its hint depends on the names around it).
    let undefined = format!("{cut}U4A1 = T2\n");
    ed.diagnose(&undefined, &ctx);
    ed.diagnose(&undefined, &ctx);
    assert_eq!(ed.check.checked, 1);
}

/// One edit of a text.
#[derive(Debug, Clone)]
enum Edit {
    /// Replace `del` bytes at a place with a string.
    Splice(prop::sample::Index, usize, String),
    /// Copy a line below itself (a second driver, a duplicate DEF, …).
    Duplicate(prop::sample::Index),
    /// Delete a line.
    Delete(prop::sample::Index),
    /// Change a digit.
    Digit(prop::sample::Index, u8),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        4 => (
            any::<prop::sample::Index>(),
            0usize..6,
            "[ A-Z0-9=+*/()\\[\\];$\n.:\x0b]{0,8}"
        )
            .prop_map(|(a, d, s)| Edit::Splice(a, d, s)),
        // A NUL ends what is read (1010): the text before it is parsed as a whole file.
        1 => any::<prop::sample::Index>().prop_map(|a| Edit::Splice(a, 0, "\0".into())),
        4 => any::<prop::sample::Index>().prop_map(Edit::Duplicate),
        4 => any::<prop::sample::Index>().prop_map(Edit::Delete),
        4 => (any::<prop::sample::Index>(), 0u8..10).prop_map(|(a, d)| Edit::Digit(a, d)),
    ]
}

fn apply(text: &mut String, e: &Edit) {
    let line_at = |i: &prop::sample::Index, text: &str| {
        let starts: Vec<usize> = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .filter(|&s| s < text.len())
            .collect();
        if starts.is_empty() {
            return None;
        }
        let s = starts[i.index(starts.len())];
        let e = text[s..].find('\n').map_or(text.len(), |n| s + n + 1);
        Some(s..e)
    };
    match e {
        Edit::Splice(at, del, ins) => {
            let mut a = at.index(text.len() + 1);
            while !text.is_char_boundary(a) {
                a -= 1;
            }
            let mut b = (a + del).min(text.len());
            while !text.is_char_boundary(b) {
                b -= 1;
            }
            text.replace_range(a..b, ins);
        }
        Edit::Duplicate(i) => {
            if let Some(r) = line_at(i, text) {
                let mut line = text[r.clone()].to_string();
                if !line.ends_with('\n') {
                    line.insert(0, '\n');
                }
                text.insert_str(r.end, &line);
            }
        }
        Edit::Delete(i) => {
            if let Some(r) = line_at(i, text) {
                text.replace_range(r, "");
            }
        }
        Edit::Digit(at, d) => {
            let digits: Vec<usize> = text
                .match_indices(|c: char| c.is_ascii_digit())
                .map(|(i, _)| i)
                .collect();
            if !digits.is_empty() {
                let i = digits[at.index(digits.len())];
                text.replace_range(i..i + 1, &d.to_string());
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]
    /// Random edit sequences over the lathe's program and a synthetic one: every incremental
    /// diagnosis equals `compile`'s diagnostics.
    #[test]
    fn random_edits_diagnose_exactly(
        synthetic in any::<bool>(),
        edits in proptest::collection::vec(edit(), 1..16),
    ) {
        let (mut text, ctx) = if synthetic {
            (compiler::synth::synthetic_program(300), MachineContext { spl: 5000, ..MachineContext::lathe_like() })
        } else {
            (lathe(), MachineContext::lathe_like())
        };
        let mut ed = Editor::default();
        ed.diagnose(&text, &ctx);
        for e in &edits {
            apply(&mut text, e);
            let (d, _) = diagnose_incremental("t", &text, &ctx, &mut ed.parse, &mut ed.check);
            prop_assert_eq!(d, compile("t", text.as_bytes(), &ctx).diagnostics);
        }
    }
}

/// Found by the `lsp_edits` fuzz target: a statement continued by its last `+` into a line of
/// invalid characters, diagnosed first without that line.
#[test]
fn a_continued_statement_then_junk_on_the_next_line() {
    let ctx = MachineContext::lathe_like();
    let first = "M_DONE = ([MCODE = 03H] + [MCODE = 04H]) * SP_READY +\n";
    let mut ed = Editor::default();
    ed.diagnose(first, &ctx);
    ed.diagnose(&format!("{first}\0\u{8}\u{8}"), &ctx);
}
