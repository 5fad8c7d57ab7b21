//! The modal record of canonical blocks ([`partprogram::BlockModal`]): the distance and feed mode,
//! work offset, cutter compensation with D and tool length with H each block ran under, per
//! dialect, derived by hand from the programs' text; and its `nc plan` JSON and text forms.

use crate::common;

use common::*;
use partprogram::{Canon, Dialect, MachineSpec, PlanOptions};

fn codes(blocks: &[Canon]) -> Vec<(Option<u32>, String)> {
    blocks
        .iter()
        .map(|b| (b.n, b.modal.codes().join(" ")))
        .collect()
}

#[test]
fn mefi_blocks_carry_distance_feed_mode_zero_offset_and_compensation() {
    let p = run(
        &mill(),
        "%1\nN10 G92 D1 R0=5.\nN20 G54 G91 G0 X-10 Y-10\nN30 G90 G1 G41 D1 X0 Y0 F100\nN40 X10\n\
         N50 G40 X20\nN60 G95 S100 X30 F0.5\nN70 G53 G94 G0 X0\nN80 M30\n",
        PlanOptions::default(),
    );
    // N10 sets D1's radius (no block); D stays 1 after G40; G53 is MEFI's zero offset row 0.
    let want = [
        (20, "G91 G94 G54 G40 D1"),
        (30, "G90 G94 G54 G41 D1"),
        (40, "G90 G94 G54 G41 D1"),
        (50, "G90 G94 G54 G40 D1"),
        (60, "G90 G95 G54 G40 D1"),
        (70, "G90 G94 G53 G40 D1"),
        (80, "G90 G94 G53 G40 D1"),
    ];
    assert_eq!(codes(&p.blocks), expected(&want));
    // nc plan: the record is the last field of the JSON line and of the text line.
    assert!(
        p.blocks[4]
            .to_json_line()
            .ends_with(r#","modal":["G90","G95","G54","G40","D1"]}"#),
        "{}",
        p.blocks[4].to_json_line()
    );
    assert!(
        p.blocks[4]
            .to_text_line()
            .ends_with(" modal G90,G95,G54,G40,D1"),
        "{}",
        p.blocks[4].to_text_line()
    );
}

fn expected(want: &[(u32, &str)]) -> Vec<(Option<u32>, String)> {
    want.iter()
        .map(|(n, c)| (Some(*n), c.to_string()))
        .collect()
}

#[test]
fn fanuc_blocks_carry_distance_work_offset_compensation_and_tool_length() {
    let haas = MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z']);
    let p = run(
        &haas,
        "O1\nN1 G10 L12 P2 R1.\nN2 G90 G54 G00 X0 Y0 Z10.\nN3 G43 H1 Z5.\nN4 G91 G01 X10. F100.\n\
         N5 G90 G55 G41 D2 X20. Y0\nN6 X30.\nN7 G40 G49 G00 X40.\nN8 G154 P3 X0\nN9 M30\n",
        PlanOptions::default(),
    );
    // N1 writes register 2's radius (no block); H shows under G43 only, D stays 2 after G40;
    // work offsets past G59 are G154 P1–P99.
    let want = [
        (2, "G90 G94 G54 G40 G49"),
        (3, "G90 G94 G54 G40 G43 H1"),
        (4, "G91 G94 G54 G40 G43 H1"),
        (5, "G90 G94 G55 G41 D2 G43 H1"),
        (6, "G90 G94 G55 G41 D2 G43 H1"),
        (7, "G90 G94 G55 G40 D2 G49"),
        (8, "G90 G94 G154 P3 G40 D2 G49"),
        (9, "G90 G94 G154 P3 G40 D2 G49"),
    ];
    assert_eq!(codes(&p.blocks), expected(&want));
}
