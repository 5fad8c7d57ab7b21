//! One test per diagnostic number an AXCFIL can trigger (Table 7.1, Table 7.2 and the project's
//! 917–944): a minimal edit of a valid file, the exact set of codes it yields, and the line and
//! column of the diagnostic under test.

use characterization::axcfil::{self, FileRef};
use characterization::reader::read;

/// A valid one-process lathe: X (diameter), Z, spindle S with encoder.
const BASE: &str = "\
*1
NBP=1,ECDF
TIM=1,0,0,0,0
PRO=1
IN1=1,XZ,S,2,16
CAS=1,XZS,2
*2
PRO=1
NAS=X
TPA=41,
NTC=1,1
RAP=10000,800
GAS=0.004,0.002,,
PAS=5000,5,,
POS=.005,2
SRV=.5,2,10
MAN=2000,200
GM0=10000,7.5,20,,
NAS=Z
TPA=1,
NTC=2,2
RAP=12000,800
GAS=0.006,0.002,,
PAS=5000,10,,
POS=.005,2
SRV=.5,2,10
MAN=2000,200
GM0=12000,7.5,20,,
NAS=S
TPA=820,
NTC=3,3
PAS=4096,1,,
GAS=,,,
POS=0.05,
SRV=,,
GM1=3000,8.5,6,,
TSM=4,17
POM=0.5,100,0.1,U230K1
*3
";

/// A slave parallel axis Q of master X, appended to BASE.
const SLAVE: &str = "NAS=Q\nTPA=1001,\nNTC=4,4\nGAS=,,,\nPAS=5000,-5,,\nMCZ=I0A8,0,200\nMFC=I0A9,I0A10\nSKW=X,1,0,0\n";

/// Applies `(find, replace)` edits in order, each to the first occurrence; panics if absent.
fn edit(base: &str, edits: &[(&str, &str)]) -> String {
    let mut s = base.to_string();
    for (find, replace) in edits {
        assert!(s.contains(find), "`{find}` not in\n{s}");
        s = s.replacen(find, replace, 1);
    }
    s
}

/// All diagnostics of reading and validating `src` as (code, line, column).
fn diags(src: &str) -> Vec<(u32, u32, u32)> {
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    d.extend(axcfil::validate(&f).1);
    for x in &d {
        assert!(
            !x.hint.is_empty() && !x.message.is_empty(),
            "diagnostic without message or hint: {x:?}"
        );
        assert_eq!(x.file, "AXCFIL");
    }
    d.iter().map(|d| (d.code, d.line, d.column)).collect()
}

/// 1-based line and column of `needle` in `src` (nth occurrence, 0-based); a `^` in the needle
/// marks the position, otherwise its first character. An empty needle means the end of the text.
fn at(src: &str, needle: &str, nth: usize) -> (u32, u32) {
    if needle.is_empty() {
        return diag::line_column(src, src.len());
    }
    let offset = needle.find('^').unwrap_or(0);
    let plain = needle.replace('^', "");
    let start = src
        .match_indices(&plain)
        .nth(nth)
        .map(|(i, _)| i)
        .unwrap_or_else(|| panic!("`{plain}` #{nth} not in\n{src}"));
    diag::line_column(src, start + offset)
}

/// Checks that `code` is reported exactly at `needles`, and that the set of codes is `codes`.
fn check(src: &str, code: u32, needles: &[(&str, usize)], codes: &[u32]) {
    let d = diags(src);
    let got: Vec<(u32, u32)> = d
        .iter()
        .filter(|x| x.0 == code)
        .map(|x| (x.1, x.2))
        .collect();
    let want: Vec<(u32, u32)> = needles.iter().map(|(n, k)| at(src, n, *k)).collect();
    assert_eq!(got, want, "positions of {code} in {d:?}\n{src}");
    let mut set: Vec<u32> = d.iter().map(|x| x.0).collect();
    set.sort_unstable();
    set.dedup();
    let mut expected = codes.to_vec();
    expected.push(code);
    expected.sort_unstable();
    expected.dedup();
    assert_eq!(set, expected, "codes of {d:?}\n{src}");
}

macro_rules! case {
    ($name:ident, $base:expr, [$(($f:expr, $r:expr)),* $(,)?], $code:expr, [$(($n:expr, $k:expr)),* $(,)?], [$($o:expr),*]) => {
        #[test]
        fn $name() {
            let src = edit($base, &[$(($f, $r)),*]);
            check(&src, $code, &[$(($n, $k)),*], &[$($o),*]);
        }
    };
}

#[test]
fn base_files_are_valid() {
    assert_eq!(diags(BASE), []);
    assert_eq!(diags(&slave()), []);
}

fn slave() -> String {
    edit(
        BASE,
        &[
            ("CAS=1,XZS,2", "CAS=1,XZSQ,2"),
            ("*3\n", &format!("{SLAVE}*3\n")),
        ],
    )
}

// Table 7.1: grammar and value types.
case!(e001_missing_section, BASE, [("*3\n", "")], 1, [("", 0)], []);
case!(
    e002_line_start,
    BASE,
    [("GM0=10000", "1X=2\nGM0=10000")],
    2,
    [("1X=2", 0)],
    []
);
case!(
    e003_no_first_section,
    BASE,
    [("*1\n", "NBP=1,ECDF\n*1\n")],
    3,
    [("NBP", 0)],
    []
);
case!(
    e004_section_order,
    BASE,
    [("*3", "*4")],
    4,
    [("*4", 0)],
    [1, 24]
);
case!(
    e005_text_after_marker,
    BASE,
    [("*2", "*2 x")],
    5,
    [("*2^ x", 0)],
    []
);
case!(
    e006_not_allowed,
    BASE,
    [("GM0=10000", "ZZZ=1\nGM0=10000")],
    6,
    [("ZZZ", 0)],
    []
);
case!(
    e007_name_too_long,
    BASE,
    [("GM0=10000", "TOOLONG=1\nGM0=10000")],
    7,
    [("TOOLONG", 0)],
    []
);
case!(
    e008_no_equals,
    BASE,
    [("GM0=10000", "XYZ 5\nGM0=10000")],
    8,
    [("XYZ 5", 0)],
    []
);
case!(
    e009_bad_name_char,
    BASE,
    [("GM0=10000", "GA S=1,2\nGM0=10000")],
    9,
    [("GA^ S", 0)],
    []
);
case!(
    e010_too_few_params,
    BASE,
    [("GM0=10000", "LOP=1\nGM0=10000")],
    10,
    [("LOP=1^\n", 0)],
    []
);
case!(
    e011_too_many_params,
    BASE,
    [("GM0=10000", "LOP=1,2,3\nGM0=10000")],
    11,
    [("LOP=1,2^,3", 0)],
    []
);
case!(
    e013_integer,
    BASE,
    [("NTC=1,1", "NTC=1x,1")],
    13,
    [("1x", 0)],
    []
);
case!(
    e014_integer_overflow,
    BASE,
    [("NTC=1,1", "NTC=40000,1")],
    14,
    [("40000", 0)],
    []
);
case!(
    e015_word,
    BASE,
    [("TIM=1,", "TIM=1x,")],
    15,
    [("1x", 0)],
    []
);
case!(
    e016_word_overflow,
    BASE,
    [("TIM=1,", "TIM=70000,")],
    16,
    [("70000", 0)],
    []
);
case!(
    e017_signal_prefix,
    BASE,
    [("GM0=10000", "MFC=X1A0,I0A1\nGM0=10000")],
    17,
    [("X1A0", 0)],
    []
);
case!(
    e018_signal_number,
    BASE,
    [("GM0=10000", "MFC=I32A0,I0A1\nGM0=10000")],
    18,
    [("I32A0", 0)],
    []
);
case!(
    e019_signal_packet,
    BASE,
    [("GM0=10000", "MFC=I1B0,I0A1\nGM0=10000")],
    19,
    [("I1^B0", 0)],
    []
);
case!(
    e020_real,
    BASE,
    [("RAP=10000,800", "RAP=10000,8x0")],
    20,
    [("8x0", 0)],
    []
);
case!(
    e021_hex,
    BASE,
    [("TPA=41,", "TPA=4G,")],
    21,
    [("4^G,", 0)],
    [132]
);
case!(
    e022_hex_digits,
    BASE,
    [("TPA=41,", "TPA=123456789,")],
    22,
    [("123456789", 0)],
    [132]
);
case!(
    e023_ascii_too_long,
    BASE,
    [("POM=0.5", "ASM=ABCDEFGHIJK\nPOM=0.5")],
    23,
    [("ABCDEFGHIJK", 0)],
    []
);
case!(
    e024_too_many_sections,
    BASE,
    [("*3\n", "*3\n*4\n")],
    24,
    [("*4", 0)],
    []
);

// Table 7.2: AXCFIL.
case!(
    e101_tick_too_big,
    BASE,
    [("TIM=1,", "TIM=64,")],
    101,
    [("64", 0)],
    []
);
case!(
    e102_cpu_missing,
    BASE,
    [("CAS=1,", "CAS=,")],
    102,
    [("CAS", 0)],
    []
);
case!(
    e103_cas_cpu,
    BASE,
    [("CAS=1,", "CAS=2,")],
    103,
    [("CAS=^2", 0)],
    []
);
case!(
    e104_servo_tick,
    BASE,
    [("CAS=1,XZS,2", "CAS=1,XZS,0")],
    104,
    [("XZS,^0", 0)],
    []
);
case!(
    e105_interpolator_cpu,
    BASE,
    [("IN1=1,", "IN1=2,")],
    105,
    [("IN1=^2", 0)],
    []
);
case!(
    e106_elements,
    BASE,
    [("S,2,16", "S,2,65")],
    106,
    [("65", 0)],
    []
);
case!(
    e107_interpolator_tick,
    BASE,
    [("S,2,16", "S,64,16")],
    107,
    [("64", 0)],
    []
);
case!(
    e108_one_spindle,
    BASE,
    [("IN1=1,XZ,S,", "IN1=1,XZ,SQ,")],
    108,
    [("SQ", 0)],
    []
);
case!(
    e109_no_axes,
    BASE,
    [("CAS=1", "IN2=1,,,2,1\nCAS=1")],
    109,
    [("IN2", 0)],
    []
);
case!(
    e110_interpolator_table,
    BASE,
    [(
        "CAS=1",
        "IN2=1,,,2,1\nIN3=1,,,2,1\nIN4=1,,,2,1\nIN5=1,,,2,1\nIN6=1,,,2,1\nIN7=1,,,2,1\nIN8=1,,,2,1\nIN9=1,,,2,1\nINA=1,,,2,1\nCAS=1"
    )],
    110,
    [("INA", 0)],
    [109]
);
case!(
    e111_duplicate_interpolator,
    BASE,
    [("CAS=1", "IN1=1,,,2,1\nCAS=1")],
    111,
    [("IN1", 1)],
    [109]
);
case!(
    e112_cas_empty,
    BASE,
    [("CAS=1,XZS,2", "CAS=1,,2")],
    112,
    [("CAS", 0)],
    [119, 149]
);
case!(
    e113_cas_duplicate,
    BASE,
    [("CAS=1,XZS,2", "CAS=1,XZSX,2")],
    113,
    [("XZS^X", 0)],
    []
);
case!(
    e114_axis_table,
    BASE,
    [
        ("NBP=1,", "NBP=3,"),
        (
            "*2",
            "PRO=2\nCAS=1,ABCDEFGHIJ,2\nPRO=3\nCAS=1,ABCDEFGHIJ,2\n*2"
        )
    ],
    114,
    [("*1", 0)],
    [169, 922]
);
case!(
    e115_interpolator_axes,
    BASE,
    [("IN1=1,XZ,", "IN1=1,XZABCDEFG,")],
    115,
    [("XZABCDEFG", 0)],
    [119]
);
case!(
    e116_several_interpolators,
    BASE,
    [("CAS=1", "IN2=1,X,,2,1\nCAS=1")],
    116,
    [("IN2", 0)],
    []
);
case!(
    e118_second_cas,
    BASE,
    [("*2", "CAS=1,XZS,2\n*2")],
    118,
    [("CAS", 1)],
    []
);
case!(
    e119_not_in_cas,
    BASE,
    [("IN1=1,XZ,", "IN1=1,XZQ,")],
    119,
    [("IN1", 0)],
    []
);
case!(
    e120_int_tick_servo,
    BASE,
    [("S,2,16", "S,3,16")],
    120,
    [("IN1", 0)],
    []
);
case!(
    e121_tim_missing,
    BASE,
    [("TIM=1,0,0,0,0\n", "")],
    121,
    [("*1", 0)],
    []
);
case!(
    e124_tick_zero,
    BASE,
    [("TIM=1,", "TIM=0,")],
    124,
    [("TIM=^0", 0)],
    []
);
case!(
    e127_servo_tick_cpu,
    BASE,
    [
        ("TIM=1,", "TIM=2,"),
        ("XZS,2", "XZS,3"),
        ("S,2,16", "S,6,16")
    ],
    127,
    [("CAS", 0)],
    []
);
case!(
    e128_int_tick_cpu,
    BASE,
    [("TIM=1,", "TIM=2,"), ("S,2,16", "S,3,16")],
    128,
    [("IN1", 0)],
    []
);
case!(
    e131_duplicate,
    BASE,
    [("GM0=10000", "RAP=1,1\nGM0=10000")],
    131,
    [("RAP", 1)],
    []
);
case!(
    e132_tpa_missing,
    BASE,
    [("TPA=41,\n", "")],
    132,
    [("NAS=X", 0)],
    []
);
case!(
    e133_ntc_missing,
    BASE,
    [("NTC=1,1\n", "")],
    133,
    [("NAS=X", 0)],
    []
);
case!(
    e134_gas_missing,
    BASE,
    [("GAS=0.004,0.002,,\n", "")],
    134,
    [("NAS=X", 0)],
    []
);
case!(
    e135_pas_missing,
    BASE,
    [("PAS=5000,5,,\n", "")],
    135,
    [("NAS=X", 0)],
    []
);
case!(
    e137_rap_missing,
    BASE,
    [("RAP=10000,800\n", "")],
    137,
    [("NAS=X", 0)],
    []
);
case!(
    e138_man_missing,
    BASE,
    [("MAN=2000,200\nGM0=10000", "GM0=10000")],
    138,
    [("NAS=X", 0)],
    []
);
case!(
    e139_man_speed,
    BASE,
    [("MAN=2000,200", "MAN=20000,200")],
    139,
    [("MAN", 0)],
    []
);
case!(
    e140_man_accel,
    BASE,
    [("MAN=2000,200", "MAN=2000,2000")],
    140,
    [("MAN", 0)],
    []
);
case!(
    e141_pos_missing,
    BASE,
    [("POS=.005,2\n", "")],
    141,
    [("NAS=X", 0)],
    []
);
case!(
    e142_srv_missing,
    BASE,
    [("SRV=.5,2,10\n", "")],
    142,
    [("NAS=X", 0)],
    []
);
case!(
    e147_gm0_on_spindle,
    BASE,
    [("GM1=", "GM0=3000,8.5,6,,\nGM1=")],
    147,
    [("GM0", 2)],
    []
);
case!(
    e148_gm1_missing,
    BASE,
    [("GM1=3000,8.5,6,,\n", "")],
    148,
    [("NAS=S", 0)],
    []
);
case!(
    e149_nas_undeclared,
    BASE,
    [("*3", "NAS=Q\nTPA=1,\nNTC=0,0\n*3")],
    149,
    [("NAS=^Q", 0)],
    []
);
case!(
    e150_gm_not_zero,
    BASE,
    [("GM0=10000", "GM1=10000")],
    150,
    [("GM1", 0)],
    []
);
case!(
    e151_no_nas,
    BASE,
    [("PRO=1\nNAS=X", "PRO=1\nAFC=1\nNAS=X")],
    151,
    [("AFC", 0)],
    []
);
case!(
    e152_no_interpolator,
    BASE,
    [
        ("CAS=1,XZS,2", "CAS=1,XZSQ,2"),
        (
            "*3",
            "NAS=Q\nTPA=1,\nNTC=4,\nPAS=400,1,,\nGAS=,\nPOS=.01,2\nSRV=,,\n*3"
        )
    ],
    152,
    [("POS=.01", 0)],
    []
);
case!(
    e153_el_pitch_zero,
    BASE,
    [("PAS=5000,5,,", "PAS=0,5,,")],
    153,
    [("PAS=^0", 0)],
    []
);
case!(
    e154_mec_pitch_zero,
    BASE,
    [("PAS=5000,5,,", "PAS=5000,0,,")],
    154,
    [("5000,^0", 0)],
    []
);
case!(
    e155_spindle_type,
    BASE,
    [("TPA=820,", "TPA=801,")],
    155,
    [("TPA=801", 0)],
    [137, 138, 150, 181, 188]
);
case!(
    e157_coordinate_ptp,
    BASE,
    [("TPA=41,", "TPA=43,")],
    157,
    [("TPA=43", 0)],
    [931, 938]
);
case!(
    e158_switch_name,
    BASE,
    [("TPA=41,", "TPA=49,YZ")],
    158,
    [("TPA=49", 0)],
    []
);
case!(
    e159_switch_undeclared,
    BASE,
    [("TPA=41,", "TPA=49,Q")],
    159,
    [("TPA=49", 0)],
    []
);
case!(
    e160_transducer,
    BASE,
    [("NTC=1,1", "NTC=17,1")],
    160,
    [("17", 0)],
    []
);
case!(
    e161_converter,
    BASE,
    [("NTC=1,1", "NTC=1,17")],
    161,
    [("NTC=1,^17", 0)],
    []
);
case!(
    e163_direction,
    BASE,
    [("POS=.005,2", "MCZ=I0A8,2,200\nPOS=.005,2")],
    163,
    [("I0A8,^2", 0)],
    []
);
case!(
    e166_asm_name,
    BASE,
    [("POM=0.5", "ASM=XY\nPOM=0.5")],
    166,
    [("ASM=^XY", 0)],
    []
);
case!(
    e167_asm_undeclared,
    BASE,
    [("POM=0.5", "ASM=Q\nPOM=0.5")],
    167,
    [("ASM", 0)],
    []
);
case!(
    e168_switch_mismatch,
    BASE,
    [("TPA=41,", "TPA=49,Z")],
    168,
    [("TPA=49", 0)],
    []
);
case!(
    e169_axis_not_defined,
    BASE,
    [("CAS=1,XZS,2", "CAS=1,XZSQ,2")],
    169,
    [("*2", 0)],
    []
);
case!(
    e172_gm_range,
    BASE,
    [("GM0=10000", "GM100=1,1,1\nGM0=10000")],
    172,
    [("GM100", 0)],
    []
);
case!(
    e173_s3_no_nas,
    BASE,
    [("*3\n", "*3\nPRO=1\nE001=0\n")],
    173,
    [("E001", 0)],
    []
);
case!(
    e174_s3_order,
    BASE,
    [(
        "*3\n",
        "*3\nPRO=1\nNAS=Z\nPAS=50\nE002=0\nE001=0.002\nE003=0\nNM0=E002\n"
    )],
    174,
    [("E001", 0)],
    []
);
case!(
    e175_s3_too_few,
    BASE,
    [("*3\n", "*3\nPRO=1\nNAS=Z\nPAS=50\nE001=0\nNM0=E001\n")],
    175,
    [("NAS=Z", 1)],
    []
);
case!(
    e176_nm0_syntax,
    BASE,
    [(
        "*3\n",
        "*3\nPRO=1\nNAS=Z\nPAS=50\nE001=0\nE002=0.002\nNM0=X5\n"
    )],
    176,
    [("X5", 0)],
    []
);
case!(
    e177_nm0_unknown,
    BASE,
    [(
        "*3\n",
        "*3\nPRO=1\nNAS=Z\nPAS=50\nE001=0\nE002=0.002\nNM0=E009\n"
    )],
    177,
    [("E009", 0)],
    []
);
case!(
    e178_converter_mismatch,
    BASE,
    [("NTC=3,3", "NTC=3,")],
    178,
    [("NTC=3,", 0)],
    []
);
case!(
    e179_spindle_both,
    BASE,
    [("TPA=820,", "TPA=830,")],
    179,
    [("TPA=830", 0)],
    []
);
case!(
    e180_tsm_params,
    BASE,
    [("TSM=4,17", "TSM=4,0")],
    180,
    [("TSM", 0)],
    []
);
case!(
    e181_tsm_not_spindle,
    BASE,
    [("GM0=10000", "TSM=4,17\nGM0=10000")],
    181,
    [("TSM", 0)],
    []
);
case!(
    e182_before_ntc,
    BASE,
    [
        ("GM1=3000,8.5,6,,\n", ""),
        ("TPA=820,", "TPA=820,\nGM1=3000,8.5,6,,")
    ],
    182,
    [("GM1", 0)],
    []
);
case!(
    e183_nbp_too_many,
    BASE,
    [("NBP=1,", "NBP=6,")],
    183,
    [("NBP=^6", 0)],
    // No follow-on 922 for processes 2..5: the file's one PRO settles the number (issue 12).
    []
);
case!(
    e184_pro_above_nbp,
    BASE,
    [("GM1=3000", "PRO=2\nGM1=3000")],
    184,
    [("PRO=^2", 0)],
    [148, 151, 189, 932]
);
case!(
    e185_no_nbp,
    BASE,
    [("NBP=1,ECDF\n", ""), ("*2", "NBP=1,ECDF\n*2")],
    185,
    [("IN1", 0), ("CAS", 0)],
    []
);
case!(
    e187_pro_empty,
    BASE,
    [("*3\n", "*3\nPRO=\n")],
    187,
    [("PRO=\n", 0)],
    []
);
case!(
    e188_pom_not_spindle,
    BASE,
    [("GM0=10000", "POM=0.5,100\nGM0=10000")],
    188,
    [("POM", 0)],
    []
);
case!(
    e189_pom_missing,
    BASE,
    [("POM=0.5,100,0.1,U230K1\n", "")],
    189,
    [("NAS=S", 0)],
    []
);
case!(
    e190_adc_number,
    BASE,
    [("GM0=10000", "ADP=9,5,1,2\nGM0=10000")],
    190,
    [("ADP=^9", 0)],
    []
);
case!(
    e191_adp_zero,
    BASE,
    [("GM0=10000", "ADP=1,0,1,2\nGM0=10000")],
    191,
    [("ADP=1,^0", 0)],
    []
);
case!(
    e193_skw_not_slave,
    BASE,
    [("POM=0.5", "SKW=X,1,0,0\nPOM=0.5")],
    193,
    [("SKW", 0)],
    []
);
case!(
    e194_skw_name,
    &slave(),
    [("SKW=X,", "SKW=XZ,")],
    194,
    [("SKW", 0)],
    []
);
case!(
    e195_skw_undeclared,
    &slave(),
    [("SKW=X,", "SKW=R,")],
    195,
    [("SKW", 0)],
    []
);
case!(
    e196_master_twice,
    &slave(),
    [
        ("CAS=1,XZSQ,2", "CAS=1,XZSQR,2"),
        ("*3", "NAS=R\nTPA=1001,\nNTC=5,5\nGAS=,,,\nSKW=X,1,0,0\n*3")
    ],
    196,
    [("SKW", 1)],
    []
);
case!(
    e197_slave_twice,
    &slave(),
    [
        ("CAS=1,XZSQ,2", "CAS=1,XZSQR,2"),
        ("*3", "NAS=R\nTPA=1001,\nNTC=5,5\nGAS=,,,\nSKW=Q,1,0,0\n*3")
    ],
    197,
    [("SKW", 0)],
    []
);
case!(
    e198_slave_instructions,
    &slave(),
    [("SKW=X,", "POS=.01,1\nSKW=X,")],
    198,
    [("POS=.01", 0)],
    []
);
case!(
    e199_skw_self,
    &slave(),
    [("SKW=X,", "SKW=Q,")],
    199,
    [("SKW", 0)],
    []
);
case!(
    e200_slave_interpolated,
    &slave(),
    [
        ("IN1=1,XZ,", "IN1=1,XZQ,"),
        ("CAS=1,XZSQ,2", "CAS=1,XZQS,2")
    ],
    200,
    [("NAS=Q", 0)],
    [928]
);
case!(
    e201_slave_before_master,
    &slave(),
    [
        ("CAS=1,XZSQ,2", "CAS=1,QXZS,2"),
        (
            "NAS=Q\nTPA=1001,\nNTC=4,4\nGAS=,,,\nPAS=5000,-5,,\nMCZ=I0A8,0,200\nMFC=I0A9,I0A10\nSKW=X,1,0,0\n",
            ""
        ),
        ("PRO=1\nNAS=X", &format!("PRO=1\n{SLAVE}NAS=X"))
    ],
    201,
    [("SKW", 0)],
    []
);
case!(
    e203_control_point_asm,
    BASE,
    [("TPA=41,", "TPA=C1,")],
    203,
    [("TPA=C1", 0)],
    []
);
case!(
    e204_zone_type,
    BASE,
    [("POM=0.5", "CUB=1,-1,1\nPOM=0.5")],
    204,
    [("CUB", 0)],
    []
);
case!(
    e205_sw_packet_a,
    BASE,
    [("GM0=10000", "SW1=1,-1,I0A5\nGM0=10000")],
    205,
    [("I0A5", 0)],
    []
);
case!(
    e206_acc,
    BASE,
    [("PRO=1\nIN1", "PRO=1\nACC=0,0.5,1,4\nIN1")],
    206,
    [("ACC", 0)],
    []
);
case!(
    e209_before_pas,
    BASE,
    [("PAS=5000,5,,", "MCZ=I0A8,0,200\nPAS=5000,5,,")],
    209,
    [("MCZ", 0)],
    []
);
case!(
    e210_converter_above_200,
    BASE,
    [("NTC=1,1", "NTC=1,201")],
    210,
    [("201", 0)],
    []
);
case!(
    e211_type_not_2,
    BASE,
    [("PAS=5000,5,,", "PAS=5000,5,2,")],
    211,
    [("PAS=5000,5,2", 0)],
    []
);
case!(
    e212_frc_before_gm0,
    BASE,
    [(
        "GM0=10000",
        "FRC=10,50,10,50,100,300,0.95,0,U190K30\nGM0=10000"
    )],
    212,
    [("FRC", 0)],
    []
);
case!(
    e215_zno_signal,
    BASE,
    [("POS=.005,2", "ZNO=0,,100,,0\nPOS=.005,2")],
    215,
    [(",,^100", 0)],
    []
);
case!(
    e216_gra_signal,
    BASE,
    [
        ("TPA=41,", "TPA=80041,"),
        ("GM0=10000", "GRA=I0A3,12\nGM0=10000")
    ],
    216,
    [("I0A3", 0)],
    []
);
case!(
    e217_gra_bits,
    BASE,
    [
        ("TPA=41,", "TPA=80041,"),
        ("GM0=10000", "GRA=I0A8,17\nGM0=10000")
    ],
    217,
    [("17", 0)],
    []
);
case!(
    e218_gra_type,
    BASE,
    [("GM0=10000", "GRA=I0A8,12\nGM0=10000")],
    218,
    [("GRA", 0)],
    []
);
case!(
    e219_hwc_axis,
    BASE,
    [("GM0=10000", "HWC=Q,U140K0\nGM0=10000")],
    219,
    [("HWC", 0)],
    []
);
case!(
    e220_can_number,
    BASE,
    [("CAS=1", "CAN5=1\nCAS=1")],
    220,
    [("CAN5", 0)],
    []
);
case!(
    e221_mcz_kkrm_input,
    BASE,
    [
        ("TPA=41,", "TPA=40041,"),
        ("POS=.005,2", "MCZ=I0A8,0,200,20,0.02\nPOS=.005,2")
    ],
    221,
    [("MCZ", 0)],
    []
);
case!(
    e222_kc_above_10,
    BASE,
    [("GM0=10000,7.5", "GM0=10000,11")],
    222,
    [("11", 0)],
    []
);
case!(
    e224_fopp_not_ptp,
    BASE,
    [("GM0=10000", "FOPP=U222K16\nGM0=10000")],
    224,
    [("FOPP", 0)],
    []
);
case!(
    e225_adg_signals,
    BASE,
    [
        ("TPA=41,", "TPA=8041,"),
        (
            "GM0=10000",
            "ADG=1,0.2,3.8,,U150N0,I150N1,U150N2\nGM0=10000"
        )
    ],
    225,
    [("ADG=1,0.2,3.8,^,", 0)],
    []
);
case!(
    e227_atr_type,
    BASE,
    [("GM0=10000", "ATR=13,0\nGM0=10000")],
    227,
    [("ATR", 0)],
    []
);
case!(
    e228_atr_missing,
    BASE,
    [("TPA=41,", "TPA=200041,")],
    228,
    [("TPA=200041", 0)],
    []
);

// Project numbers 900–944.
case!(
    p900_non_ascii,
    BASE,
    [("NAS=X", "NAS=Х")],
    900,
    [("Х", 0), ("Х", 0)],
    [151, 169]
);
case!(
    p901_boolean,
    BASE,
    [("GM0=10000", "FBF=,,U230K0,2\nGM0=10000")],
    901,
    [("U230K0,^2", 0)],
    []
);
case!(
    p917_nbp_zero,
    BASE,
    [("NBP=1,", "NBP=0,")],
    917,
    [("NBP=^0", 0)],
    []
);
case!(
    p918_nbp_extension,
    BASE,
    [("NBP=1,ECDF", "NBP=1,5")],
    918,
    [("NBP=1,^5", 0)],
    [134, 135, 148, 189, 935]
);
case!(
    p920_no_process,
    BASE,
    [("PRO=1\nIN1", "IN0=1,,,2,1\nPRO=1\nIN1")],
    920,
    [("IN0", 0)],
    []
);
case!(
    p921_process_twice,
    BASE,
    [("CAS=1,XZS,2", "CAS=1,XZS,2\nPRO=1")],
    921,
    [("PRO=1", 1)],
    []
);
case!(
    p922_process_incomplete,
    BASE,
    [("NBP=1,", "NBP=2,")],
    922,
    [("*1", 0)],
    []
);
case!(
    p923_com_process,
    BASE,
    [("CAS=1", "COM=1,S\nCAS=1")],
    923,
    [("COM", 0)],
    [118]
);
case!(
    p925_axis_letter,
    BASE,
    [
        ("IN1=1,XZ,", "IN1=1,KZ,"),
        ("CAS=1,XZS", "CAS=1,KZS"),
        ("NAS=X", "NAS=K")
    ],
    925,
    [("NAS=K", 0)],
    []
);
case!(
    p926_block_num,
    BASE,
    [("S,2,16", "S,2,1")],
    926,
    [("IN1", 0)],
    []
);
case!(
    p927_cas_order,
    BASE,
    [("CAS=1,XZS", "CAS=1,ZXS")],
    927,
    [("CAS", 0)],
    [928]
);
case!(
    p928_nas_order,
    BASE,
    [("CAS=1,XZS", "CAS=1,XSZ")],
    928,
    [("NAS=Z", 0)],
    []
);
case!(
    p929_range,
    BASE,
    [("PAS=5000,5,,", "PAS=-5000,5,,")],
    929,
    [("-5000", 0)],
    []
);
case!(
    p930_tpa_bits,
    BASE,
    [("TPA=41,", "TPA=20041,")],
    930,
    [("20041", 0)],
    []
);
case!(
    p931_type_forbids,
    BASE,
    [("SRV=,,", "SRV=1,,")],
    931,
    [("SRV=1", 0)],
    []
);
case!(
    p932_tsm_missing,
    BASE,
    [("TSM=4,17\n", "")],
    932,
    [("TPA=820", 0)],
    []
);
case!(
    p934_section3,
    BASE,
    [(
        "*3\n",
        "*3\nPRO=1\nNAS=Z\nPAS=-1\nE001=0\nE002=0.002\nNM0=E001\n"
    )],
    934,
    [("-1", 0)],
    [173, 175]
);
case!(
    p935_ecdf_form,
    BASE,
    [
        ("NBP=1,ECDF", "NBP=1,0"),
        ("GAS=0.004,0.002,,", "GAS=0.004,0.002"),
        ("GAS=0.006,0.002,,", "GAS=0.006,0.002"),
        ("GAS=,,,", "GAS=,"),
        ("PAS=5000,5,,", "PAS=5000,5"),
        ("PAS=5000,10,,", "PAS=5000,10"),
        ("PAS=4096,1,,", "PAS=4096,1"),
        ("GM0=10000,7.5,20,,", "GM0=10000,7.5,20"),
        ("GM0=12000,7.5,20,,", "GM0=12000,7.5,20"),
        ("GM1=3000,8.5,6,,", "GM1=3000,8.5,6")
    ],
    935,
    [("POM=0.5,100^,", 0)],
    [189]
);
case!(
    p936_signal_twice,
    BASE,
    [("GAS=0.004,0.002,,", "GAS=0.004,0.002,U220K0,U220K0")],
    936,
    [("GAS=0.004", 0)],
    []
);
case!(
    p938_interpolator_kind,
    BASE,
    [("TPA=41,", "TPA=2,"), ("SRV=.5,2,10", "SRV=,,")],
    938,
    [("NAS=X", 0)],
    []
);
case!(
    p940_handwheel_interpolated,
    BASE,
    [("GM0=10000", "HWC=Z,U140K0\nGM0=10000")],
    940,
    [("HWC", 0)],
    []
);
case!(
    p941_com_axis,
    BASE,
    [
        ("NBP=1,", "NBP=2,"),
        ("*2", "PRO=2\nCOM=1,Q\nIN2=1,A,,2,16\nCAS=1,A,2\n*2")
    ],
    941,
    [("Q", 0)],
    [169]
);
case!(
    p942_section1_twice,
    BASE,
    [("TIM=1,0,0,0,0", "TIM=1,0,0,0,0\nTIM=1,0,0,0,0")],
    942,
    [("TIM", 1)],
    []
);
#[test]
fn p944_file_ref() {
    let src = magazine("FTP=BAD\n");
    let (line, col) = at(&src, "BAD", 0);
    assert_eq!(diags(&src), [(944, line, col)]);
}

/// A PTP tool magazine T in process 2 for the side-file rules.
fn magazine(ftp: &str) -> String {
    edit(
        BASE,
        &[
            ("NBP=1,", "NBP=2,"),
            ("*2", "PRO=2\nIN2=1,T,,2,1\nCAS=1,T,2\n*2"),
            (
                "*3",
                &format!(
                    "PRO=2\nNAS=T\nTPA=2,\nNTC=5,5\nRAP=600,10\nGAS=,,,\nPAS=6000,4,1,0\nPOS=.1,10\nSRV=,,\nMAN=400,10\nGM0=600,7.5,7,,\n{ftp}*3"
                ),
            ),
        ],
    )
}

fn with_side(src: &str, side: &dyn Fn(&FileRef) -> Option<Vec<u8>>) -> Vec<(u32, u32, u32)> {
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    d.extend(axcfil::validate_with(&f, side, true).1);
    d.iter().map(|d| (d.code, d.line, d.column)).collect()
}

#[test]
fn e213_ftp_file_incorrect_and_fx39_side_file() {
    let src = magazine("FTP=TABTT1/MP0\n");
    let (line, col) = at(&src, "FTP", 0);
    let good = "0 0 pos 0\n1 1.5 pos 1\n2 2 pos 2\n3 3 pos 3\n";
    assert_eq!(
        with_side(&src, &|f: &FileRef| (f.file == "TABTT1" && f.mp == 0)
            .then(|| good.as_bytes().to_vec())),
        []
    );
    let three = "0 0\n1 1.5\n2 2\n";
    assert_eq!(
        with_side(&src, &|_: &FileRef| Some(three.as_bytes().to_vec())),
        [(213, line, col)]
    );
    let jump = "0 0\n1 1.5\n2 3.5\n3 3\n";
    assert_eq!(
        with_side(&src, &|_: &FileRef| Some(jump.as_bytes().to_vec())),
        [(213, line, col)]
    );
}

#[test]
fn e214_ftp_file_missing() {
    let src = magazine("FTP=TABTT1/MP0\n");
    let (line, col) = at(&src, "FTP", 0);
    assert_eq!(with_side(&src, &|_: &FileRef| None), [(214, line, col)]);
}

#[test]
fn e223_fopp_signal() {
    let src = magazine("FOPP=I0A0\n");
    let (line, col) = at(&src, "I0A0", 0);
    assert_eq!(diags(&src), [(223, line, col)]);
    assert_eq!(diags(&magazine("FOPP=I222K16\n")), []);
}

#[test]
fn p943_feg_file() {
    let src = edit(
        BASE,
        &[(
            "*3\n",
            "*3\nPRO=1\nNAS=Z\nPAS=50\nFEG=COMPZ/MP2\nNM0=E002\n",
        )],
    );
    let (line, col) = at(&src, "NAS=Z", 1);
    assert_eq!(with_side(&src, &|_: &FileRef| None), [(943, line, col)]);
    let ok = |f: &FileRef| {
        (f.file == "COMPZ" && f.mp == 2).then(|| b"E001 = 0.1\nE002 = 0.11\n".to_vec())
    };
    assert_eq!(with_side(&src, &ok), []);
    let bad = |_: &FileRef| Some(b"E001 = 0.1\nE001 = 0.11\n".to_vec());
    assert_eq!(with_side(&src, &bad), [(943, line, col), (177, line, col)]);
}

#[test]
fn e126_servo_ticks_differ() {
    let src = magazine("")
        .replace("CAS=1,T,2", "CAS=1,T,4")
        .replace("IN2=1,T,,2,1", "IN2=1,T,,4,1");
    let (line, col) = at(&src, "CAS=1,T", 0);
    assert_eq!(diags(&src), [(126, line, col)]);
}

#[test]
fn e207_cub_axes() {
    let axis = |n: char, k: u32| {
        format!(
            "NAS={n}\nTPA=1,\nNTC={k},{k}\nRAP=12000,800\nGAS=,,,\nPAS=5000,10,,\nPOS=.005,2\nSRV=.5,2,10\nMAN=2000,200\nGM0=12000,7.5,20,,\nCUB=1,-1,1\n"
        )
    };
    let src = edit(
        BASE,
        &[
            ("IN1=1,XZ,", "IN1=1,XZYW,"),
            ("CAS=1,XZS,2", "CAS=1,XZYWS,2"),
            ("GM0=10000,7.5,20,,\n", "GM0=10000,7.5,20,,\nCUB=1,-1,1\n"),
            ("GM0=12000,7.5,20,,\n", "GM0=12000,7.5,20,,\nCUB=1,-1,1\n"),
            ("NAS=S", &format!("{}{}NAS=S", axis('Y', 5), axis('W', 6))),
        ],
    );
    let (line, col) = at(&src, "CUB", 3);
    assert_eq!(diags(&src), [(207, line, col)]);
}

#[test]
fn slave_axis_example_is_valid() {
    assert_eq!(diags(&slave()), []);
}

/// Diagnostics about section-1 records found while checking an axis carry section 1.
#[test]
fn block_num_diagnostic_names_section_one() {
    let src = edit(BASE, &[("S,2,16", "S,2,1")]);
    let (f, _) = read("AXCFIL", src.as_bytes());
    let d = axcfil::validate(&f).1;
    assert_eq!(
        d.iter()
            .map(|d| (d.code, d.section, d.process))
            .collect::<Vec<_>>(),
        [(926, Some(1), Some(1))]
    );
}

case!(
    p945_slave_homing,
    &slave(),
    [("POS=.005,2", "MCZ=I0A7,0,300\nPOS=.005,2")],
    945,
    [("MCZ=I0A8", 0)],
    []
);
case!(
    p931_vgas_without_backlash,
    BASE,
    [("GAS=0.004,0.002,,", "GAS=,0.002,,\nVGAS=3,U180K0,U180K1")],
    931,
    [("VGAS", 0)],
    []
);
case!(
    p929_kkrm_hdbrp,
    BASE,
    [
        ("TPA=41,", "TPA=40041,"),
        ("POS=.005,2", "MCZ=,0,200,0,0.02\nPOS=.005,2")
    ],
    929,
    [("MCZ", 0)],
    []
);

#[test]
fn slave_with_the_masters_homing_is_valid() {
    let src = edit(&slave(), &[("POS=.005,2", "MCZ=I0A7,0,200\nPOS=.005,2")]);
    assert_eq!(diags(&src), []);
    let vgas = edit(BASE, &[("GM0=10000", "VGAS=3,U180K0,U180K1\nGM0=10000")]);
    assert_eq!(diags(&vgas), []);
}

/// Diagnostics carry the section and process they were found in.
#[test]
fn diagnostics_name_section_and_process() {
    let src = edit(
        BASE,
        &[
            ("MAN=2000,200", "MAN=20000,200"),
            ("TIM=1,", "TIM=64,"),
            ("*3\n", "*3\nPRO=1\nNAS=Z\nPAS=50\nE002=0\nE001=0\n"),
        ],
    );
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    d.extend(axcfil::validate(&f).1);
    let got: Vec<(u32, Option<u32>, Option<u32>)> =
        d.iter().map(|d| (d.code, d.section, d.process)).collect();
    assert_eq!(
        got,
        [
            (101, Some(1), None),
            (174, Some(3), Some(1)),
            (175, Some(3), Some(1)),
            (139, Some(2), Some(1))
        ]
    );
}

/// NBP=7 on a file that opens one process: one error, the real cause, with the likely intent in
/// its hint; no follow-on errors about processes 2..5 (issue 12: 25 errors and 8 warnings before).
#[test]
fn nbp_too_many_is_one_error_with_the_processes_of_the_file_as_hint() {
    let src = edit(BASE, &[("NBP=1,", "NBP=7,")]);
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    let (model, v) = axcfil::validate(&f);
    d.extend(v);
    let got: Vec<_> = d
        .iter()
        .map(|d| {
            (
                d.code,
                d.line,
                d.column,
                d.message.as_str(),
                d.hint.as_str(),
            )
        })
        .collect();
    assert_eq!(
        got,
        [(
            183,
            2,
            5,
            "NBP declares 7 processes",
            "at most 5 processes are allowed; section 1 opens processes up to PRO=1: write NBP=1"
        )]
    );
    assert_eq!(model.nbp, 1);
}

/// A misspelled instruction gets "did you mean" with the nearest instruction of its section (the
/// axis then lacks RAP: 137 is the consequence, reported at the axis).
#[test]
fn misspelled_instruction_suggests_the_nearest_name() {
    let src = edit(BASE, &[("RAP=10000,800", "RPA=10000,800")]);
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    d.extend(axcfil::validate(&f).1);
    let got: Vec<_> = d
        .iter()
        .map(|d| {
            (
                d.code,
                d.line,
                d.column,
                d.message.as_str(),
                d.hint.as_str(),
            )
        })
        .collect();
    assert_eq!(
        got,
        [
            (
                6,
                12,
                1,
                "instruction RPA is not allowed in AXCFIL section 2",
                "did you mean `RAP`? section 2 allows TPA NTC RAP GAS VGAS PAS SKW MCZ POS SRV MAN MSS GMxx FRC LOP LOx MFC AFC CUB SWx TSM ASM POM ADP ZNO FBF HWC ATR GRA FOPP FTP ADG LAS FQF"
            ),
            (
                137,
                9,
                1,
                "axis X has no RAP",
                "declare rapid speed and acceleration, e.g. `RAP=12000,800`"
            )
        ]
    );
}
