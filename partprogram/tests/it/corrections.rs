//! The correction table: `TAB0.KOR` (fixture F25 and every located error), MEFI length correction
//! methods A/B/C with a table from the file, and Fanuc G43/G44/G49 with H.

use crate::common;

use common::*;
use partprogram::{
    Dialect, Kind, KorEntry, LengthMethod, MachineSpec, PlanOptions, compile, parse_kor, plan,
};
use proptest::prelude::*;

const MILL: [char; 3] = ['X', 'Y', 'Z'];
const LATHE: [char; 2] = ['X', 'Z'];

/// F25, first file (000:1317–1322), without the second `$KOR` of the seed.
const F25: &str = "Comment before the table\n$KOR\n01:\tR=10.0\tX = 20.0\tY = 30.0\tZ=40.0\t\n02:\tR = 0.8\tX=0.0\t2 = 0.0\t\t\n03:\tR = 0.8\tX=0.0\tY=120.0\tZ=0.0\t4 = 0.0\n25:\t\tX = 85.0\tY = 45.5\tZ=0.0\t\n95:\tR = 0.0\t1=12.55\t2 = 0.0\t3 = 0.0\t4 = 0.0\n";

fn errors(text: &str, axes: &[char]) -> Vec<(u32, u32, u32)> {
    let (_, d) = parse_kor("TAB0.KOR", text, axes);
    d.iter().map(|d| (d.code, d.line, d.column)).collect()
}

#[test]
fn f25_gives_the_stated_table() {
    let (t, d) = parse_kor("TAB0.KOR", F25, &MILL);
    assert!(d.is_empty(), "{d:?}");
    let rows = t.rows();
    assert_eq!(rows.len(), 100);
    assert_eq!(rows[1], [10.0, 20.0, 30.0, 40.0, 0.0]);
    assert_eq!(rows[2], [0.8, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(rows[3], [0.8, 0.0, 120.0, 0.0, 0.0]);
    assert_eq!(rows[25], [0.0, 85.0, 45.5, 0.0, 0.0]);
    assert_eq!(rows[95], [0.0, 12.55, 0.0, 0.0, 0.0]);
    let zero: Vec<usize> = (0..100).filter(|n| rows[*n] == [0.0; 5]).collect();
    assert_eq!(zero.len(), 95, "all other entries are zero");
    assert_eq!(
        t.entries.keys().copied().collect::<Vec<_>>(),
        vec![1, 2, 3, 25, 95]
    );
}

#[test]
fn f25_lathe_entries_with_ordinal_z_and_tool_tip() {
    let (t, d) = parse_kor(
        "TAB0.KOR",
        "$KOR\n01: R=0.8 X=120.0 2=340.5 P=3\n02: R=0.0 X=0.0 2=0.0\n",
        &LATHE,
    );
    assert!(d.is_empty(), "{d:?}");
    assert_eq!(
        t.entries.get(&1),
        Some(&KorEntry {
            data: [0.8, 120.0, 340.5, 0.0, 0.0],
            tip: Some(3)
        })
    );
    assert_eq!(t.tip(2), None);
    assert_eq!(t.data(2), [0.0; 5]);
    // A value without a decimal point is in mm, as a coordinate word.
    let (t, d) = parse_kor("TAB0.KOR", "$KOR\n07: X=20 2=-3\n", &LATHE);
    assert!(d.is_empty(), "{d:?}");
    assert_eq!(t.data(7), [0.0, 20.0, -3.0, 0.0, 0.0]);
}

#[test]
fn the_seeds_second_kor_is_an_error_after_the_first_table() {
    let text = format!("{F25}$KOR\n01:\tR=0.0\tX=0.0\tY = 0.0\tZ=0.0\t4 = 0.0\n");
    let (t, d) = parse_kor("TAB0.KOR", &text, &MILL);
    assert_eq!(
        d.iter()
            .map(|d| (d.code, d.line, d.column))
            .collect::<Vec<_>>(),
        vec![(2048, 8, 1)]
    );
    assert_eq!(
        t.data(1),
        [10.0, 20.0, 30.0, 40.0, 0.0],
        "the first table is kept"
    );
}

#[test]
fn every_kor_error_is_located() {
    assert_eq!(
        errors("no keyword here\n01: R=1.0\n", &MILL),
        vec![(2040, 1, 1)]
    );
    assert_eq!(errors("$KOR extra\n", &MILL), vec![(2041, 1, 6)]);
    assert_eq!(errors("$KOR\n1: R=1.0\n", &MILL), vec![(2041, 2, 1)]);
    assert_eq!(errors("$KOR\n00: R=1.0\n", &MILL), vec![(2041, 2, 1)]);
    assert_eq!(errors("$KOR\n01 R=1.0\n", &MILL), vec![(2041, 2, 1)]);
    assert_eq!(
        errors("$KOR\n01: R=1.0\n01: R=2.0\n", &MILL),
        vec![(2042, 3, 1)]
    );
    assert_eq!(
        errors("$KOR\n01: R=1.0 Q=2.0\n", &MILL),
        vec![(2043, 2, 11)]
    );
    assert_eq!(
        errors("$KOR\n01: R=1.0 x=2.0\n", &MILL),
        vec![(2043, 2, 11)]
    );
    // The lathe writes its Z length as `2=`; U= needs a 4th axis named U.
    assert_eq!(
        errors("$KOR\n01: X=1.0 Z=2.0\n", &LATHE),
        vec![(2044, 2, 11)]
    );
    assert_eq!(errors("$KOR\n01: U=1.0\n", &MILL), vec![(2044, 2, 5)]);
    assert_eq!(errors("$KOR\n01: R 1.0\n", &MILL), vec![(2045, 2, 5)]);
    assert_eq!(errors("$KOR\n01: R=\n", &MILL), vec![(2045, 2, 7)]);
    assert_eq!(errors("$KOR\n01: R=1.0X=2.0\n", &MILL), vec![(2045, 2, 7)]);
    assert_eq!(errors("$KOR\n01: X=1.2.3\n", &MILL), vec![(2045, 2, 7)]);
    assert_eq!(errors("$KOR\n01: X=1.2345\n", &MILL), vec![(2046, 2, 7)]);
    assert_eq!(errors("$KOR\n01: X=1000.0\n", &MILL), vec![(2046, 2, 7)]);
    assert_eq!(errors("$KOR\n01: P=0\n", &LATHE), vec![(2046, 2, 7)]);
    assert_eq!(errors("$KOR\n01: P=3.0\n", &LATHE), vec![(2046, 2, 7)]);
    assert_eq!(
        errors("$KOR\n01: X=1.0 1=2.0\n", &MILL),
        vec![(2047, 2, 11)]
    );
    assert_eq!(errors("$KOR\n01: R=1.0\n$KOR\n", &MILL), vec![(2048, 3, 1)]);
    // Errors are reported line by line; the good lines are kept.
    let (t, d) = parse_kor(
        "TAB0.KOR",
        "$KOR\r\n01: R=1.5\r\n02: R=oops\r\n03: Z=-5.25\r\n\r\n",
        &MILL,
    );
    assert_eq!(
        d.iter().map(|d| (d.code, d.line)).collect::<Vec<_>>(),
        vec![(2045, 3)]
    );
    assert_eq!(
        (t.data(1)[0], t.data(3)[3], t.data(2)),
        (1.5, -5.25, [0.0; 5])
    );
}

fn with_table(mut m: MachineSpec, kor: &str, method: LengthMethod) -> MachineSpec {
    let axes = m.axes();
    let (t, d) = parse_kor("TAB0.KOR", kor, &axes);
    assert!(d.is_empty(), "{d:?}");
    m.corrections = t;
    m.length_method = method;
    m
}

/// Block number and machine end position (µm-rounded) of a motion block.
type Move = (Option<u32>, Vec<(char, f64)>);

fn rapids(m: &MachineSpec, src: &str) -> Vec<Move> {
    let p = run(m, src, PlanOptions::default());
    p.blocks
        .iter()
        .filter(|c| matches!(c.kind, Kind::Rapid | Kind::Linear))
        .map(|c| (c.n, c.end.iter().map(|(a, v)| (*a, um(*v))).collect()))
        .collect()
}

const MILL_KOR: &str = "$KOR\n01: R=6.0 X=1.5 Y=-2.0 Z=-150.0\n02: R=8.0 Z=-120.25\n";

#[test]
fn method_a_uses_the_table_from_the_file() {
    let m = with_table(mill(), MILL_KOR, LengthMethod::A);
    let got = rapids(
        &m,
        "%1\nN1 G0 X10 Y10 Z10 &1021 D1\nN2 G0 X10 Y10 Z10 &0\nN3 M30\n",
    );
    assert_eq!(
        got,
        vec![
            (Some(1), vec![('X', 11.5), ('Y', 10.0), ('Z', 160.0)]),
            (Some(2), vec![('X', 10.0), ('Y', 10.0), ('Z', 10.0)]),
        ]
    );
}

#[test]
fn method_b_adds_every_length_of_entry_d_and_d0_cancels() {
    let m = with_table(mill(), MILL_KOR, LengthMethod::B);
    let got = rapids(
        &m,
        "%1\nN1 G0 X10 Y10 Z10 D1\nN2 G0 Z10 D2\nN3 G92 D2 R3=-5.0\nN4 G0 Z10 D2\nN5 G0 X0 Y0 Z0 D0\nN6 M30\n",
    );
    assert_eq!(
        got,
        vec![
            (Some(1), vec![('X', 11.5), ('Y', 8.0), ('Z', -140.0)]),
            // D2 has no X or Y length: X and Y keep their machine position until they move.
            (Some(2), vec![('X', 11.5), ('Y', 8.0), ('Z', -110.25)]),
            (Some(4), vec![('X', 11.5), ('Y', 8.0), ('Z', 5.0)]),
            (Some(5), vec![('X', 0.0), ('Y', 0.0), ('Z', 0.0)]),
        ]
    );
}

#[test]
fn method_c_activates_with_amp_1_and_cancels_with_amp_0() {
    let m = with_table(mill(), MILL_KOR, LengthMethod::C);
    let got = rapids(
        &m,
        "%1\nN1 G0 Z10 D1\nN2 G0 Z10 &1\nN3 G0 Z10 D2\nN4 G0 Z10 &0\nN5 M30\n",
    );
    let z: Vec<(Option<u32>, f64)> = got.iter().map(|(n, e)| (*n, e[2].1)).collect();
    assert_eq!(
        z,
        vec![
            (Some(1), 10.0),
            (Some(2), -140.0),
            (Some(3), -110.25),
            (Some(4), 10.0)
        ]
    );
    // & other than 0/1 is a compile error under method C, and a run-time error through a parameter.
    assert_eq!(codes(&m, "%1\nN1 G0 Z10 &2 D1\nN2 M30\n"), vec![2009]);
    let (prog, d) = compile(&m, "t", "%1\nN1 R5=2\nN2 G0 Z10 &R5 D1\nN3 M30\n");
    assert!(d.is_empty(), "{d:?}");
    let err = plan(&prog.expect("compiles"), PlanOptions::default()).expect_err("&2 under C");
    assert_eq!((err.1.code, err.1.line), (2502, 3));
}

#[test]
fn method_a_rejects_a_parameter_with_digits_above_2() {
    let m = with_table(mill(), MILL_KOR, LengthMethod::A);
    let (prog, _) = compile(&m, "t", "%1\nN1 R5=1300\nN2 G0 Z10 &R5 D1\nN3 M30\n");
    let err = plan(&prog.expect("compiles"), PlanOptions::default()).expect_err("digit 3");
    assert_eq!((err.1.code, err.1.line), (2502, 3));
}

#[test]
fn lathe_lengths_come_from_axis_ordinals() {
    let m = with_table(
        lathe(),
        "$KOR\n02: R=0.4 X=10.0 2=-30.5 P=3\n",
        LengthMethod::A,
    );
    let got = rapids(&m, "%1\nN1 G0 X100 Z50 &1100 D2\nN2 M30\n");
    assert_eq!(got, vec![(Some(1), vec![('X', 110.0), ('Z', 19.5)])]);
}

fn haas(kor: &str) -> MachineSpec {
    let mut m = with_table(
        MachineSpec::new(Dialect::Fanuc, &MILL),
        kor,
        LengthMethod::A,
    );
    m.macro_dir = machines().join("mill/macros");
    m
}

fn fanuc_z(m: &MachineSpec, src: &str) -> Vec<(Option<u32>, f64)> {
    rapids(m, src)
        .into_iter()
        .map(|(n, e)| {
            (
                n,
                e.iter().find(|(a, _)| *a == 'Z').map_or(f64::NAN, |p| p.1),
            )
        })
        .collect()
}

#[test]
fn fanuc_g43_adds_g44_subtracts_g49_cancels() {
    let m = haas(MILL_KOR);
    let z = fanuc_z(
        &m,
        "O1\nN1 G90 G54 G00 X0 Y0\nN2 G43 H01 Z2.\nN3 G01 Z-5. F100.\nN4 G49 Z2.\nN5 G44 H02 Z2.\nN6 H00 Z2.\nN7 M30\n",
    );
    assert_eq!(
        z,
        vec![
            (Some(1), 0.0),
            (Some(2), -148.0),
            (Some(3), -155.0),
            (Some(4), 2.0),
            (Some(5), 122.25),
            (Some(6), 2.0),
        ]
    );
}

#[test]
fn fanuc_length_is_taken_once_by_an_incremental_move_and_g28_cancels() {
    let m = haas(MILL_KOR);
    let z = fanuc_z(
        &m,
        "O1\nN1 G90 G00 Z10.\nN2 G91 G43 H01 Z-5.\nN3 Z-5.\nN4 G90 Z0.\nN5 G28 G91 Z0.\nN6 G90 G00 Z0.\nN7 M30\n",
    );
    // N5: the intermediate point is the current position (without the length), then machine zero.
    assert_eq!(
        z,
        vec![
            (Some(1), 10.0),
            (Some(2), -145.0),
            (Some(3), -150.0),
            (Some(4), -150.0),
            (Some(5), -150.0),
            (Some(5), 0.0),
            (Some(6), 0.0),
        ]
    );
}

#[test]
fn fanuc_g43_on_the_haas_example_and_the_h_range() {
    let m = haas(MILL_KOR);
    let p = run(
        &m,
        &std::fs::read_to_string(machines().join("mill/nc/O00050.nc")).expect("O00050"),
        PlanOptions::default(),
    );
    let n15 = p.blocks.iter().find(|c| c.n == Some(15)).expect("N15");
    assert_eq!(end(n15, 'Z'), -148.0, "G43 H01 Z2. with Z length -150");
    // The G13 pocket below it keeps the length: Z-12. is machine -162.
    let arc = p
        .blocks
        .iter()
        .find(|c| c.kind == Kind::ArcCcw)
        .expect("pocket arc");
    assert_eq!(end(arc, 'Z'), -162.0);
    // N18 G53 G49: machine Y0 Z0.
    let n18 = p.blocks.iter().find(|c| c.n == Some(18)).expect("N18");
    assert_eq!(end(n18, 'Z'), 0.0);
    assert_eq!(codes(&m, "O1\nN1 G43 H100 Z2.\nN2 M30\n"), vec![2009]);
    assert_eq!(codes(&m, "O1\nN1 G43 Z2.\nN2 M30\n"), vec![2034]);
    assert_eq!(
        codes(&m, "O1\nN1 G43 H99 Z2. D99\nN2 M30\n"),
        Vec::<u32>::new()
    );
    assert_eq!(codes(&m, "O1\nN1 G41 X1. D201\nN2 M30\n"), vec![2009]);
}

#[test]
fn fanuc_tool_axis_follows_the_plane_at_g43() {
    let m = haas("$KOR\n01: X=1.0 Y=2.0 Z=3.0\n");
    let got = rapids(
        &m,
        "O1\nN1 G19 G43 H01 X0 Y0 Z0\nN2 G17 X0 Y0 Z0\nN3 G43 H01 X0 Y0 Z0\nN4 M30\n",
    );
    assert_eq!(
        got,
        vec![
            (Some(1), vec![('X', 1.0), ('Y', 0.0), ('Z', 0.0)]),
            (Some(2), vec![('X', 1.0), ('Y', 0.0), ('Z', 0.0)]),
            (Some(3), vec![('X', 0.0), ('Y', 0.0), ('Z', 3.0)]),
        ]
    );
    // A machine without the tool axis: a located run-time error.
    let m = with_table(
        MachineSpec::new(Dialect::Fanuc, &['X', 'Z']),
        "$KOR\n01: X=1.0\n",
        LengthMethod::A,
    );
    let (prog, _) = compile(
        &m,
        "t",
        "O1\nN1 G17 G43 H01 X0 Z0\nN2 G18 G43 H01 X0 Z0\nN3 M30\n",
    );
    let (blocks, e) = plan(&prog.expect("compiles"), PlanOptions::default()).expect_err("no Y");
    assert_eq!((blocks.len(), e.code, e.line), (1, 2508, 3));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn kor_reader_never_panics(text in "(\\$KOR|[0-9]{1,3}:|[RXYZUP1-4]|=|[ \\t]|-?[0-9]{0,4}\\.?[0-9]{0,4}|\\r?\\n|é|.){0,40}") {
        let (t, d) = parse_kor("TAB0.KOR", &text, &MILL);
        for diag in &d {
            prop_assert!(diag.line >= 1 && diag.span.end <= text.len());
        }
        prop_assert!(t.entries.keys().all(|n| (1..=99).contains(n)));
    }
}

/// Writes thousandths as a table value (`-12.345`).
fn value(milli: i32) -> String {
    let sign = if milli < 0 { "-" } else { "" };
    let a = milli.unsigned_abs();
    format!("{sign}{}.{:03}", a / 1000, a % 1000)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]
    #[test]
    fn any_written_table_reads_back_exactly(
        entries in proptest::collection::btree_map(1u8..=99, (proptest::array::uniform5(-999_999i32..=999_999), any::<[bool; 4]>(), any::<bool>()), 0..12)
    ) {
        let mut text = String::from("table written by the test\n$KOR\n");
        for (n, (data, by_name, spaced)) in &entries {
            let eq = if *spaced { " = " } else { "=" };
            text.push_str(&format!("{n:02}:\tR{eq}{}", value(data[0])));
            for k in 0..3 {
                let key = if by_name[k] { MILL[k].to_string() } else { (k + 1).to_string() };
                text.push_str(&format!("\t{key}{eq}{}", value(data[k + 1])));
            }
            text.push_str(&format!(" 4{eq}{}\n", value(data[4])));
        }
        let (t, d) = parse_kor("TAB0.KOR", &text, &MILL);
        prop_assert!(d.is_empty(), "{:?}", d);
        let rows = t.rows();
        for n in 0..100u8 {
            let want = entries
                .get(&n)
                .map_or([0.0; 5], |(data, _, _)| data.map(|m| f64::from(m) / 1000.0));
            prop_assert_eq!(rows[usize::from(n)], want);
        }
    }
}
