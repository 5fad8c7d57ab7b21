//! One minimal PGCFIL per error number of Table 7.3 (and the Table 7.1 codes PGCFIL adds) that a
//! file alone can trigger: each test checks the number, the line and the column.

use characterization::pgcfil;
use characterization::reader::{Grammar, read_with};

/// (code, line, column) of every diagnostic of reading + decoding `src` as PGCFIL.
fn run(src: &str) -> Vec<(u32, u32, u32)> {
    let (file, mut diags) = read_with("PGCFIL", src.as_bytes(), Grammar::PGCFIL);
    let (_, more) = pgcfil::parse(&file);
    diags.extend(more);
    diags.iter().map(|d| (d.code, d.line, d.column)).collect()
}

/// Line and column of the `nth` (0-based) occurrence of `needle` in `src`; a `^` in `needle`
/// marks the expected position inside it (default: its start).
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

/// A valid file with `s1`…`s6` as the bodies of sections 1…6 (each ends with a newline or is empty).
fn file(s1: &str, s2: &str, s3: &str, s4: &str, s5: &str, s6: &str) -> String {
    format!("NEW\n*1\n{s1}*2\n{s2}*3\n{s3}*4\n{s4}*5\n{s5}*6\n{s6}")
}

const S4: &str = "PRO=1\nNDD=MP1\n";
const S5: &str = "PRO=1\nNIP=1\nTOF=2\nNAM=Z\nNPD=Z,X\n";

/// Asserts that `src` yields exactly one diagnostic `code` at the `nth` occurrence of `needle`.
fn one(src: &str, code: u32, needle: &str, nth: usize) {
    let (l, c) = at(src, needle, nth);
    assert_eq!(run(src), [(code, l, c)], "source:\n{src}");
}

#[test]
fn base_file_is_valid() {
    assert_eq!(run(&file("", "", "", S4, S5, "")), []);
}

#[test]
fn e001_missing_section_5() {
    // Seven lines, so the end of the file is line 8, column 1.
    let src = format!("NEW\n*1\n*2\n*3\n*4\n{S4}");
    assert_eq!(run(&src), [(1, 8, 1)]);
}

#[test]
fn e006_instruction_not_allowed_in_section() {
    one(
        &file("", "", "", &format!("{S4}NIP=1\n"), S5, ""),
        6,
        "NIP=1",
        0,
    );
}

#[test]
fn e010_e011_parameter_counts() {
    one(
        &file("", "", "", S4, &format!("{S5}GXX=01,,,70,95\n"), ""),
        10,
        "GXX=01,,,70,95^\n",
        0,
    );
    let src = file("", "", "", "PRO=1\nNDD=MP1,MP2\n", S5, "");
    let (l, c) = at(&src, ",MP2", 0);
    assert_eq!(run(&src), [(11, l, c)]);
}

#[test]
fn e023_ascii_too_long() {
    one(
        &file("", "", "", "PRO=1\nFIL=FILEORIGIN/MP0,,,,\n", S5, ""),
        23,
        "FILEORIGIN",
        0,
    );
}

#[test]
fn e018_plc_variable_limits() {
    one(
        &file("", "", "", S4, &format!("{S5}INU=U256K20,1\n"), ""),
        18,
        "U256K20",
        0,
    );
}

#[test]
fn e025_no_new_or_old() {
    let src = "*1\n*2\n*3\n*4\nPRO=1\n*5\nPRO=1\nNIP=1\nTOF=2\nNAM=Z\nNPD=Z,X\n";
    assert_eq!(run(src), [(25, 1, 1)]);
    let src = "NEU\n*1\n*2\n*3\n*4\nPRO=1\n*5\nPRO=1\nNIP=1\nTOF=2\nNAM=Z\nNPD=Z,X\n";
    assert_eq!(run(src), [(25, 1, 1)]);
}

#[test]
fn e101_duplicated_instruction() {
    one(
        &file("", "", "", "PRO=1\nNDD=MP1\nNDD=MP2\n", S5, ""),
        101,
        "NDD",
        1,
    );
}

#[test]
fn e102_e103_e104_tri() {
    one(&file("TRI=XYZ,ABC,\n", "", "", S4, S5, ""), 102, "XYZ", 0);
    one(&file("TRI=CLS,DD,\n", "", "", S4, S5, ""), 103, "DD", 0);
    one(&file("TRI=CLS,D,5\n", "", "", S4, S5, ""), 104, "5", 0);
}

#[test]
fn e105_to_e109_sim() {
    one(&file("", "SIM=TMR,,5,,,\n", "", S4, S5, ""), 105, "5", 0);
    one(&file("", "SIM=E,,,8,,\n", "", S4, S5, ""), 106, "8", 0);
    one(&file("", "SIM=E,,,,128,\n", "", S4, S5, ""), 107, "128", 0);
    one(&file("", "SIM=E,,,,,5\n", "", S4, S5, ""), 108, "5", 0);
    one(
        &file("", "SIM=NEW,USO,1,1,1,3\n", "", S4, S5, ""),
        109,
        "USO",
        0,
    );
}

#[test]
fn e110_npl() {
    one(
        &file("", "", "", "PRO=1\nNPL=256,10\n", S5, ""),
        110,
        "256",
        0,
    );
}

#[test]
fn e112_ndd() {
    one(&file("", "", "", "PRO=1\nNDD=MP7\n", S5, ""), 112, "MP7", 0);
}

#[test]
fn e113_interpolator_name() {
    let s5 = "PRO=1\nNIP=12\nTOF=2\nNAM=Z\nNPD=Z,X\n";
    one(&file("", "", "", S4, s5, ""), 113, "12", 0);
}

#[test]
fn e115_axis_name_one_character() {
    let s5 = "PRO=1\nNIP=1\nTOF=2\nNAM=ZZ\nNPD=Z,X\n";
    one(&file("", "", "", S4, s5, ""), 115, "ZZ", 0);
}

#[test]
fn e118_missing_nip_nam_npd_tof() {
    let s5 = "PRO=1\nNIP=1\nTOF=2\nNAM=Z\n";
    one(&file("", "", "", S4, s5, ""), 118, "PRO=1", 1);
}

#[test]
fn e119_more_than_20_new_variables() {
    let s2: String = (0..21)
        .map(|i| format!("SIM=NEW,NV{i},1,1,1,3\n"))
        .collect();
    one(&file("", &s2, "", S4, S5, ""), 119, "SIM=NEW,NV20", 0);
}

#[test]
fn e120_e122_e123_probe() {
    one(
        &file("", "", "", S4, &format!("{S5}INU=I1A0,2\n"), ""),
        120,
        "INU=I1A0,^2",
        0,
    );
    one(
        &file("", "", "", S4, &format!("{S5}TAS=I1A0,1,Z*,S,,\n"), ""),
        122,
        "Z*",
        0,
    );
    one(
        &file("", "", "", S4, &format!("{S5}TAS=I1A0,1,Z-,Q,,\n"), ""),
        123,
        "Q",
        0,
    );
}

#[test]
fn e124_e126_e132_mas() {
    one(
        &file("", "", "", S4, S5, "PRO=1\nMAS=XZX\n"),
        124,
        "MAS=XZ^X",
        0,
    );
    one(
        &file("", "", "", S4, S5, "PRO=1\nMAS=ABCDUVWXY\n"),
        126,
        "ABCDUVWXY",
        0,
    );
    one(
        &file("", "", "", S4, S5, "PRO=1\nMAS=X1\n"),
        132,
        "MAS=X^1",
        0,
    );
}

#[test]
fn e125_nam_before_nip() {
    let s5 = "PRO=1\nNAM=Z\nNIP=1\nTOF=2\nNPD=Z,X\n";
    let src = file("", "", "", S4, s5, "");
    let (l1, c1) = at(&src, "NAM", 0);
    let (l2, c2) = at(&src, "NIP", 0);
    // NIP is then also not the first instruction of the block (project rule 950).
    assert_eq!(run(&src), [(125, l1, c1), (950, l2, c2)]);
}

#[test]
fn e128_e129_ass() {
    one(&file("", "", "", "PRO=1\nASS=,1\n", S5, ""), 128, "ASS", 0);
    one(
        &file("", "", "", "PRO=1\nASS=XYZ,1\n", S5, ""),
        129,
        "XYZ",
        0,
    );
}

#[test]
fn p901_a_boolean_ass_takes_0_or_1() {
    // ASS=UEP,value has the boolean format (003:4607-4610).
    one(&file("", "", "", "PRO=1\nASS=UEP,7\n", S5, ""), 901, "7", 0);
    one(
        &file("", "", "", "PRO=1\nASS=USO,0.5\n", S5, ""),
        901,
        "0.5",
        0,
    );
}

#[test]
fn e133_tof() {
    one(
        &file("", "", "", S4, "PRO=1\nNIP=1\nTOF=13\nNAM=Z\nNPD=Z,X\n", ""),
        133,
        "13",
        0,
    );
}

#[test]
fn e134_fil_syntax() {
    one(
        &file("", "", "", "PRO=1\nFIL=FI1EOR,,,,\n", S5, ""),
        134,
        "FI1EOR",
        0,
    );
}

#[test]
fn e135_str() {
    one(&file("", "", "", "PRO=1\nSTR=256\n", S5, ""), 135, "256", 0);
}

#[test]
fn e139_e140_gxx() {
    let s5 = "PRO=1\nNIP=1\nGXX=01,,,70,95,97\nTOF=2\nNAM=Z\nNPD=Z,X\n";
    one(&file("", "", "", S4, s5, ""), 139, "GXX", 0);
    one(
        &file("", "", "", S4, &format!("{S5}GXX=01,,,72,95,97\n"), ""),
        140,
        "72",
        0,
    );
    one(
        &file("", "", "", S4, &format!("{S5}GXX=001,,,70,95,97\n"), ""),
        140,
        "001",
        0,
    );
}

#[test]
fn e147_tga_angle() {
    one(
        &file("", "", "", S4, &format!("{S5}TGA=C,400\n"), ""),
        147,
        "400",
        0,
    );
}

#[test]
fn e184_process_declared_twice() {
    let s4 = "PRO=1\nNDD=MP1\nPRO=1\n";
    one(&file("", "", "", s4, S5, ""), 184, "PRO=^1", 1);
    one(&file("", "", "", "PRO=6\n", S5, ""), 184, "6", 0);
}

#[test]
fn project_rules_950_to_960() {
    one(
        &file("", "", "", S4, "PRO=1\nTOF=2\nNIP=1\nNAM=Z\nNPD=Z,X\n", ""),
        950,
        "NIP",
        0,
    );
    one(&file("", "", "JCL=XYZ,ABC,\n", S4, S5, ""), 952, "XYZ", 0);
    let src = file("", "", "JCL=VTU,UTV,2\n", S4, S5, "");
    let (l, c) = at(&src, "UTV,^2", 0);
    assert_eq!(run(&src), [(953, l, c)]);
    one(
        &file("", "", "", "PRO=1\nNPL=10,300\n", S5, ""),
        954,
        "300",
        0,
    );
    one(
        &file("", "", "", "PRO=1\nFLC=,,FI1MSG,\n", S5, ""),
        955,
        "FI1MSG",
        0,
    );
    one(
        &file("", "", "", S4, &format!("{S5}CWP=C000,2\n"), ""),
        956,
        "C000,^2",
        0,
    );
    one(
        &file("", "", "", S4, &format!("{S5}G70=2\n"), ""),
        957,
        "G70=^2",
        0,
    );
    one(
        &file("", "", "", S4, &format!("{S5}MBR=0\n"), ""),
        958,
        "MBR=^0",
        0,
    );
    one(
        &file("", "", "", S4, &format!("{S5}TAS=I1A0,1,,,I1A0,1\n"), ""),
        959,
        "I1A0",
        1,
    );
    one(
        &file(
            "",
            "",
            "",
            S4,
            S5,
            "PRO=1\nFMO=-1,-.5,-.2,-.05,-.01,0,.01,.05,.2,.5,1,.9\n",
        ),
        960,
        ".9",
        0,
    );
}

#[test]
fn every_error_of_a_file_comes_out_of_one_run() {
    let s4 = "PRO=1\nNDD=MP9\nNPL=300,10\n";
    let s5 = "PRO=1\nNIP=1\nTOF=13\nNAM=Z\nNPD=Z,X\n";
    let src = file("TRI=CLS,D,7\n", "", "", s4, s5, "");
    let codes: Vec<u32> = run(&src).into_iter().map(|(c, _, _)| c).collect();
    assert_eq!(codes, [104, 112, 110, 133]);
}

#[test]
fn table_7_1_value_errors_in_pgcfil() {
    one(&file("", "", "", "PRO=1\nNPL=2X,10\n", S5, ""), 13, "2X", 0);
    one(
        &file("", "", "", "PRO=1\nNPL=40000,10\n", S5, ""),
        14,
        "40000",
        0,
    );
    one(&file("", "", "", "PRO=1\nSTR=12A\n", S5, ""), 15, "12A", 0);
    one(
        &file("", "", "", "PRO=1\nSTR=70000\n", S5, ""),
        16,
        "70000",
        0,
    );
    one(
        &file("", "", "", S4, &format!("{S5}SMC=1.2.3\n"), ""),
        20,
        "1.2.3",
        0,
    );
    let src = format!("{}*7\n", file("", "", "", S4, S5, ""));
    one(&src, 24, "*7", 0);
    let src = file("", "", "", S4, S5, "").replace("*3\n", "*3 x\n");
    one(&src, 5, "*3^ x", 0);
}
