//! One minimal IOCFIL per error number of Table 7.4 (and the Table 7.1 codes) that a file alone can
//! trigger: each test checks the number, the line and the column.

use characterization::iocfil;
use characterization::reader::read;

/// (code, line, column) of every diagnostic of reading + decoding `src` as IOCFIL.
fn run(src: &str) -> Vec<(u32, u32, u32)> {
    let (file, mut diags) = read("IOCFIL", src.as_bytes());
    let (_, more) = iocfil::parse(&file);
    diags.extend(more);
    diags.iter().map(|d| (d.code, d.line, d.column)).collect()
}

/// Line and column of the `nth` occurrence of `needle` (a `^` marks the position inside it).
fn at(src: &str, needle: &str, nth: usize) -> (u32, u32) {
    let mark = needle.find('^').unwrap_or(0);
    let needle = needle.replace('^', "");
    let offset = mark
        + src
            .match_indices(&needle)
            .nth(nth)
            .map(|(i, _)| i)
            .unwrap_or_else(|| panic!("{needle} not in source"));
    let line = src[..offset].matches('\n').count() + 1;
    let col = offset - src[..offset].rfind('\n').map_or(0, |i| i + 1) + 1;
    (line as u32, col as u32)
}

/// A file with section bodies `s1`…`s4`.
fn file(s1: &str, s2: &str, s3: &str, s4: &str) -> String {
    format!("*1\n{s1}*2\n{s2}*3\n{s3}*4\n{s4}")
}

const S1: &str = "IN0=0,1,,,,,,\nOU0=4,5,,,,,,\nCLO=10,2\n";

fn one(src: &str, code: u32, needle: &str, nth: usize) {
    let (l, c) = at(src, needle, nth);
    assert_eq!(run(src), [(code, l, c)], "source:\n{src}");
}

#[test]
fn base_file_is_valid() {
    assert_eq!(
        run(&file(
            S1,
            "PRO=1\nM03=45,00,21\n",
            "PRO=1\nASM=S\n",
            "T01=10\n"
        )),
        []
    );
}

#[test]
fn e001_e003_e006_structure() {
    let src = format!("*1\n{S1}*2\n*3\n");
    assert_eq!(run(&src), [(1, 7, 1)]);
    let src = format!("PRO=1\n*1\n{S1}*2\n*3\n*4\n");
    assert_eq!(run(&src), [(3, 1, 1)]);
    one(&file(S1, "PRO=1\nM100=45,00,21\n", "", ""), 6, "M100", 0);
    one(&file(S1, "", "", "T65=1\n"), 6, "T65", 0);
    one(
        &file(&format!("{S1}IN4=0,,,,,,,\n"), "", "", ""),
        6,
        "IN4",
        0,
    );
    one(&file(&format!("PRO=1\n{S1}"), "", "", ""), 6, "PRO", 0);
}

#[test]
fn e010_e021_e022_syntax() {
    one(
        &file(S1, "PRO=1\nM03=45,00\n", "", ""),
        10,
        "M03=45,00^\n",
        0,
    );
    one(&file(S1, "PRO=1\nM03=4G,00,21\n", "", ""), 21, "M03=4^G", 0);
    one(
        &file(S1, "PRO=1\nM03=045,00,21\n", "", ""),
        22,
        "M03=^045",
        0,
    );
}

#[test]
fn e101_duplicated_instruction() {
    one(&file(&format!("{S1}CLO=10,2\n"), "", "", ""), 101, "CLO", 1);
    one(
        &file(S1, "PRO=1\nM03=45,00,21\nM03=45,00,21\n", "", ""),
        101,
        "M03",
        1,
    );
    one(&file(S1, "", "PRO=1\nASM=S\nASM=S\n", ""), 101, "ASM", 1);
    one(&file(S1, "", "", "T01=1\nT01=2\n"), 101, "T01", 1);
}

#[test]
fn e103_e106_clo() {
    one(&file("CLO=0,0\n", "", "", ""), 103, "CLO=^0", 0);
    one(&file("CLO=256,2\n", "", "", ""), 103, "CLO=^256", 0);
    one(&file("CLO=10,6\n", "", "", ""), 106, "CLO=10,^6", 0);
}

#[test]
fn e107_to_e111_connectors() {
    one(
        &file("IN0=0,4,,,,,,\nCLO=10,2\n", "", "", ""),
        107,
        "0,^4",
        0,
    );
    one(
        &file("OU0=4,3,,,,,,\nCLO=10,2\n", "", "", ""),
        107,
        "4,^3",
        0,
    );
    one(
        &file("IN0=0,1,,,,,,\nIN1=1,,,,,,,\nCLO=10,2\n", "", "", ""),
        108,
        "IN1=^1",
        0,
    );
    one(
        &file("OU0=4,,,,,,,\nIN0=4,,,,,,,\nCLO=10,2\n", "", "", ""),
        109,
        "IN0=^4",
        0,
    );
    one(
        &file("OU0=4,5,,,,,,\nOU1=5,,,,,,,\nCLO=10,2\n", "", "", ""),
        110,
        "OU1=^5",
        0,
    );
    one(
        &file("IN0=0,,,,,,,\nOU0=0,,,,,,,\nCLO=10,2\n", "", "", ""),
        111,
        "OU0=^0",
        0,
    );
    one(
        &file(&format!("{S1}SPL=5001\n"), "", "", ""),
        107,
        "5001",
        0,
    );
}

#[test]
fn e113_m_type_zero() {
    one(
        &file(S1, "PRO=1\nM05=00,00,21\n", "", ""),
        113,
        "M05=^00",
        0,
    );
}

#[test]
fn e114_e129_index_axis() {
    one(&file(S1, "", "PRO=1\nAS1=B,2,0,360\n", ""), 114, "B,^2", 0);
    one(
        &file(S1, "", "PRO=1\nAS1=B,0,3,360\n", ""),
        114,
        "B,0,^3",
        0,
    );
    one(
        &file(S1, "", "PRO=1\nAS1=B,0,0,0\n", ""),
        129,
        "B,0,0,^0",
        0,
    );
}

#[test]
fn e115_axis_name_one_character() {
    one(&file(S1, "", "PRO=1\nASM=SP\n", ""), 115, "SP", 0);
    one(&file(S1, "", "PRO=1\nADV=PQ,0\n", ""), 115, "PQ", 0);
}

#[test]
fn e116_clo_missing() {
    let src = file("IN0=0,,,,,,,\n", "", "", "");
    assert_eq!(run(&src), [(116, 1, 1)]);
}

#[test]
fn e117_e120_ptp_axis() {
    one(
        &file(S1, "", "PRO=1\nTA1=,E,0,32,.7,.3\n", ""),
        117,
        "TA1=^,",
        0,
    );
    one(
        &file(S1, "", "PRO=1\nTA1=V,E,0,32,0,.3\n", ""),
        120,
        "32,^0",
        0,
    );
}

#[test]
fn e124_e127_ucda() {
    one(&file(S1, "", "PRO=1\nUCDA=ABCDE\n", ""), 124, "ABCDE", 0);
    one(&file(S1, "", "PRO=1\nUCDA=B1\n", ""), 127, "UCDA=B^1", 0);
}

#[test]
fn e130_gps() {
    one(&file(S1, "PRO=1\nGPS=2\n", "", ""), 130, "GPS=^2", 0);
}

#[test]
fn e184_process() {
    one(&file(S1, "PRO=1\nPRO=1\n", "", ""), 184, "PRO=^1", 1);
    one(&file(S1, "", "PRO=0\n", ""), 184, "PRO=^0", 0);
}

#[test]
fn project_rules() {
    one(
        &file(S1, "PRO=1\nM30=02,20,00\n", "", ""),
        962,
        "M30=02,^20",
        0,
    );
    let src = file(S1, "", "PRO=1\nUCDA=ABCD\n", "");
    let (l, c) = at(&src, "ABCD", 0);
    assert_eq!(run(&src), [(963, l, c)]);
    one(&file(S1, "", "PRO=1\nADC=1,9,,,,\n", ""), 107, "1,^9", 0);
    one(
        &file(S1, "", "PRO=1\nDAC=1,-200,,,,,,\n", ""),
        107,
        "-200",
        0,
    );
}

#[test]
fn all_errors_of_the_file_in_one_run() {
    let src = file(
        "IN0=0,4,,,,,,\nCLO=0,0\n",
        "PRO=1\nM05=00,00,21\nGPS=3\n",
        "PRO=1\nAS1=B,0,0,0\n",
        "T01=1\nT01=2\n",
    );
    let codes: Vec<u32> = run(&src).into_iter().map(|(c, _, _)| c).collect();
    assert_eq!(codes, [107, 103, 113, 130, 129, 101]);
}
