//! Compile-time diagnostics: codes, locations and that bad input never panics.

use crate::common;

use common::*;
use partprogram::{MTiming, compile};
use proptest::prelude::*;

fn first(src: &str) -> diag::Diagnostic {
    let (_, d) = compile(&mill(), "t", src);
    d.into_iter()
        .find(diag::Diagnostic::is_error)
        .expect("an error")
}

#[test]
fn undeclared_m_function_is_an_error_when_iocfil_declares_ms() {
    let mut m = mill();
    m.check_m_declared = true;
    m.processes[0].declared_m.insert(
        3,
        MTiming {
            m_type: 0x45,
            m_request: 0,
            class: 0x21,
        },
    );
    m.processes[0].declared_m.insert(
        30,
        MTiming {
            m_type: 0x02,
            m_request: 0x24,
            class: 0,
        },
    );
    let (_, d) = compile(&m, "t", "%1\nN1 M03\nN2 M08\nN3 M30\n");
    let e: Vec<(u32, u32, u32)> = d.iter().map(|d| (d.code, d.line, d.column)).collect();
    assert_eq!(e, vec![(2016, 3, 4)]);
}

#[test]
fn declared_m_timing_orders_before_motion_first() {
    let mut m = mill();
    m.processes[0].declared_m.insert(
        8,
        MTiming {
            m_type: 0x02,
            m_request: 0,
            class: 0,
        },
    );
    m.processes[0].declared_m.insert(
        3,
        MTiming {
            m_type: 0x45,
            m_request: 0,
            class: 0,
        },
    );
    let p = run(
        &m,
        "%1\nN1 X1 M08 M03\nN2 M30\n",
        partprogram::PlanOptions::default(),
    );
    let ms: Vec<(u16, bool)> = p.blocks[0].m.iter().map(|f| (f.m, f.before)).collect();
    assert_eq!(ms, vec![(3, true), (8, false)]);
    assert!(
        p.blocks[0]
            .to_json_line()
            .contains("\"m\":[3,8],\"m_timing\":[\"before\",\"after\"]")
    );
}

#[test]
fn unknown_addresses_and_axes() {
    assert_eq!(first("%1\nN1 O5\nN2 M30\n").code, 2008);
    let (_, d) = compile(&lathe(), "t", "%1\nN1 Y5\nN2 M30\n");
    assert_eq!(d[0].code, 2008);
    assert!(d[0].message.contains("no axis Y"), "{}", d[0].message);
    assert_eq!(first("%1\nN1 R5\nN2 M30\n").code, 2033);
}

#[test]
fn values_out_of_range() {
    assert_eq!(first("%1\nN1 G100\nN2 M30\n").code, 2009);
    assert_eq!(first("%1\nN1 S99999\nN2 M30\n").code, 2009);
    assert!(codes(&mill(), "%1\nN1 G71 L0\nN2 M30\n").contains(&2009));
    assert_eq!(first("%1\nN1 R96=1\nN2 M30\n").code, 2011);
    assert_eq!(first("%1\nN1 R1=123456789\nN2 M30\n").code, 2009);
    assert_eq!(first("%1\nN1 X123456.5\nN2 M30\n").code, 2009);
    assert_eq!(first("%1\nN1 G12\nN2 M30\n").code, 2015);
    assert_eq!(first("%1\nN1 G1.5\nN2 M30\n").code, 2024);
    assert_eq!(first("%1\nN1 &1300\nN2 M30\n").code, 2009);
    assert_eq!(first("%1\nN1 E5\nN2 M30\n").code, 2030);
}

#[test]
fn word_rules() {
    let d = first("%1\nN1 X36. 12\nN2 M30\n");
    assert_eq!((d.code, d.line, d.column), (2013, 2, 9));
    assert_eq!(first("%1\nN1 X- 36.12\nN2 M30\n").code, 2001);
    assert_eq!(first("%1\nN1 x5\nN2 M30\n").code, 2001);
    assert_eq!(first("%1\nN1 X1 X2\nN2 M30\n").code, 2006);
    assert_eq!(first("%1\nN1 G0 G1\nN2 M30\n").code, 2007);
    assert_eq!(first("%1\nN1 M3 M4\nN2 M30\n").code, 2007);
    assert_eq!(first("%1\nN1 X1\nN1 X2\nN2 M30\n").code, 2005);
    assert_eq!(first("%1\nX1 N1 M30\n").code, 2004);
    assert_eq!(first("%1\nNR1 X1\nN2 M30\n").code, 2010);
    assert_eq!(first("%1\nN1 X1 Y1 Z1 X2\nN2 M30\n").code, 2006);
}

#[test]
fn jumps_and_calls_to_missing_targets() {
    assert_eq!(first("%1\nN1 G73 L5\nN2 M30\n").code, 2018);
    assert_eq!(first("%1\nN1 G71 L5\nN2 M30\n").code, 2019);
    assert_eq!(first("%1\nN1 G72 L5\nN2 M30\n").code, 2020);
    assert_eq!(first("%1\nN1 G71\nN2 M30\n").code, 2017);
    assert_eq!(first("%1\nN1 R1=73 N2 GR1 L7\nN3 M30\n").code, 2018);
    // A jump from the main program into a subprogram is not allowed.
    assert_eq!(
        first("%1\nN1 G73 L11\nN2 M30\nN10 G79 L1\nN11 X1\nN12 G70\n").code,
        2018
    );
}

#[test]
fn unbounded_recursion() {
    let d = first(
        "%1\nN1 G71 L1\nN2 M30\nN10 G79 L1\nN11 G71 L2\nN12 G70\nN20 G79 L2\nN21 G71 L1\nN22 G70\n",
    );
    assert_eq!((d.code, d.line), (2021, 8));
}

#[test]
fn program_structure() {
    assert_eq!(first("%1\nN1 X1\nN2 M30\nN3 X2\n").code, 2026);
    assert_eq!(first("%1\nN1 M30\nN10 G79 L1 X5\nN11 G70\n").code, 2022);
    assert_eq!(first("%1\nN1 M30\nN10 G79 L1\nN11 X1\n").code, 2025);
    let (_, d) = compile(
        &mill(),
        "t",
        &format!("%1\nN1 X1 \"{}\"\nN2 M30\n", "x".repeat(90)),
    );
    assert_eq!((d[0].code, d[0].severity), (2012, diag::Severity::Warning));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, .. ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        let text = String::from_utf8_lossy(&bytes);
        for dialect in [partprogram::Dialect::Mefi, partprogram::Dialect::Fanuc] {
            let mut m = mill();
            m.dialect = dialect;
            let (prog, _) = compile(&m, "fuzz", &text);
            if let Some(p) = prog {
                let _ = partprogram::plan(&p, partprogram::PlanOptions { max_blocks: 10_000, ..Default::default() });
            }
        }
    }

    #[test]
    fn token_soup_never_panics(words in proptest::collection::vec(
        prop_oneof![
            Just("N1".to_string()), Just("N2".to_string()), Just("G73".to_string()), Just("L1".to_string()),
            Just("G26".to_string()), Just("R5=".to_string()), Just("GR6".to_string()), Just("Q3".to_string()),
            Just("G71".to_string()), Just("G79".to_string()), Just("G70".to_string()), Just("M30".to_string()),
            (0i64..99_999_999).prop_map(|v| v.to_string()), (-100i64..100).prop_map(|v| format!("X{v}.5")),
            Just("G02".to_string()), Just("I5".to_string()), Just("G81".to_string()), Just("\n".to_string()),
        ], 0..40)) {
        let text = format!("%1\n{}\n", words.join(" "));
        let (prog, _) = compile(&mill(), "soup", &text);
        if let Some(p) = prog {
            for backend in [partprogram::Backend::Native, partprogram::Backend::Interpreter] {
                let _ = partprogram::plan(&p, partprogram::PlanOptions { max_blocks: 10_000, backend, ..Default::default() });
            }
        }
    }
}

#[test]
fn undeclared_m_in_a_macro_the_program_calls_is_reported_in_the_macro_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("L5"), "N1 G79 L5\nN2 M19\nN3 G70\n").expect("L5");
    std::fs::write(dir.path().join("L6"), "N1 G79 L6\nN2 M44\nN3 G70\n").expect("L6");
    let mut m = mill();
    m.macro_dir = dir.path().to_path_buf();
    m.check_m_declared = true;
    m.processes[0].declared_m.insert(
        30,
        MTiming {
            m_type: 0x02,
            m_request: 0x24,
            class: 0,
        },
    );
    let (_, d) = compile(&m, "t", "%1\nN1 G72 L5\nN2 M30\n");
    let got: Vec<(String, u32, u32)> = d.iter().map(|d| (d.file.clone(), d.code, d.line)).collect();
    assert_eq!(
        got,
        vec![("macros/L5".to_string(), 2016, 2)],
        "L6 is not called, so its M44 is not checked"
    );
}

/// "did you mean" for letters where a word's number belongs (issue 12): the letter `O` for the
/// digit `0`, and the process logic's three-letter instructions (or a misspelling of one).
#[test]
fn letter_runs_get_a_did_you_mean() {
    let d = first("%1\nN1 GO1 X10 F100\nN2 M30\n");
    assert_eq!((d.code, d.line, d.column), (2002, 2, 5));
    assert_eq!(
        d.hint,
        "did you mean `G01`? `O` is a letter; the digit is `0`"
    );
    let d = first("%1\nN1 RPT3\nN2 M30\n");
    assert_eq!((d.code, d.line, d.column), (2002, 2, 5));
    assert_eq!(
        d.hint,
        "`RPT` is an instruction of the process logic (PGCFIL), not a partprogram word; a block holds words of one address letter and a number"
    );
    let d = first("%1\nN1 UEP=1\nN2 M30\n");
    assert_eq!((d.code, d.line, d.column), (2002, 2, 5));
    assert_eq!(
        d.hint,
        "`UEP` (velocity feed-forward off) is a system variable of the process: set it with PGCFIL section 4 `ASS=UEP,1`; a partprogram block cannot change it"
    );
    let d = first("%1\nN1 EPX\nN2 M30\n");
    assert_eq!((d.code, d.line, d.column), (2002, 2, 5));
    assert_eq!(
        d.hint,
        "did you mean `EPP`? That is an instruction of the process logic (PGCFIL), not a partprogram word; a block holds words of one address letter and a number"
    );
}
