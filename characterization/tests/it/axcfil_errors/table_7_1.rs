//! Table 7.1 of the manual: grammar and value types (codes 1–24).

use super::*;

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
