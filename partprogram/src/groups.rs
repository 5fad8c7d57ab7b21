//! G and M function groups of the MEFI dialect (dictionary, structure spec §5–§6).

/// The G group (0..=11) of MEFI function `g`, or None for an unknown function.
pub fn mefi_g_group(g: u16) -> Option<u8> {
    Some(match g {
        0 | 1 | 2 | 3 | 30 | 33 => 0,
        14..=19 => 1,
        5 | 6 | 7 | 9 | 10 | 23 | 24 | 98 => 2,
        40..=42 => 3,
        26..=29 => 4,
        53..=59 => 5,
        94..=97 => 6,
        70..=73 | 78 | 79 => 7,
        80..=89 => 8,
        90 | 91 => 9,
        4 | 92 | 93 | 74 | 75 => 10,
        34..=37 => 11,
        _ => return None,
    })
}

/// The M group (1..=14) of MEFI function `m`; every M not listed in groups 1–9 is group 14.
pub fn mefi_m_group(m: u16) -> u8 {
    match m {
        0 | 1 | 2 | 30 => 1,
        3 | 4 | 5 | 19 => 2,
        40..=44 => 3,
        36 | 37 => 4,
        7 | 8 | 9 | 17 => 5,
        50..=53 => 6,
        10 | 11 => 7,
        48 | 49 => 8,
        6 | 60 => 9,
        _ => 14,
    }
}

/// The group of a Fanuc/HAAS M code whose members contradict each other in one block (spindle,
/// coolant, program stop, call/return), or None.
pub fn fanuc_m_group(m: i64) -> Option<u8> {
    match m {
        3 | 4 | 5 | 19 => Some(1),
        7..=9 => Some(2),
        0..=2 | 30 => Some(3),
        97..=99 => Some(4),
        _ => None,
    }
}

/// The G group of a Fanuc/HAAS G code (code × 10 + sub-code, so G7.1 is 71 and G1 is 10), or None.
pub fn fanuc_g_group(g10: u16) -> Option<u8> {
    // Sub-codes exist only for G7.1 and G5.1: every other code is a whole number.
    if !g10.is_multiple_of(10) && g10 != 71 && g10 != 51 {
        return None;
    }
    Some(match g10 {
        0 | 10 | 20 | 30 => 1,
        170 | 180 | 190 => 2,
        900 | 910 => 3,
        940 => 5,
        200 | 210 => 6,
        400 | 410 | 420 => 7,
        430 | 440 | 490 => 8,
        730 | 740 | 800..=860 | 890 => 9,
        980 | 990 => 10,
        540..=590 | 1100..=1290 | 1540 => 12,
        71 => 16,
        690 => 17,
        500 => 11,
        // G05.1 (AI contour control) and G08 (AI look-ahead): group 0, Q/P switch them.
        40 | 51 | 80 | 90 | 120 | 130 | 280 | 520 | 530 | 920 | 100 | 1000 => 0,
        610 | 640 => 15,
        960 | 970 => 13,
        _ => return None,
    })
}
