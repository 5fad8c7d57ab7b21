//! The manual's PGCFIL example (§1.11, NC-110) and fragments of chapter 5: each loads, or fails
//! with exactly the errors the manual implies.

use characterization::pgcfil::{self, LoadMode, NewName, Units};
use characterization::reader::{Grammar, read_with};

/// (code, line, column) of every diagnostic of reading + decoding `src` as PGCFIL.
fn run(src: &str) -> (pgcfil::Pgcfil, Vec<(u32, u32, u32)>) {
    let (file, mut diags) = read_with("PGCFIL", src.as_bytes(), Grammar::PGCFIL);
    let (pg, more) = pgcfil::parse(&file);
    diags.extend(more);
    (
        pg,
        diags.iter().map(|d| (d.code, d.line, d.column)).collect(),
    )
}

#[test]
fn nc110_example_normalized_loads() {
    let (pg, d) = run(include_str!("../fixtures/pgcfil_nc110.txt"));
    assert_eq!(d, []);
    assert_eq!(pg.load_mode, LoadMode::New);
    assert!(!pg.retains());
    assert_eq!(
        pg.processes.iter().map(|p| p.number).collect::<Vec<_>>(),
        [1, 2]
    );
    let p1 = &pg.processes[0];
    assert_eq!(p1.sim.len(), 2);
    assert_eq!(
        (p1.sim[0].var_name.as_str(), p1.sim[0].max_num),
        ("E", Some(60))
    );
    assert_eq!(
        (p1.sim[1].var_name.as_str(), p1.sim[1].max_num),
        ("p", Some(100))
    );
    assert_eq!(p1.assigned("USO"), Some(1.0));
    assert_eq!(p1.npl.and_then(|n| n.prog_num), Some(20));
    assert_eq!(p1.ndd, Some(1));
    let fil = p1.fil.as_ref().map(|f| {
        (
            f.origins.as_ref().map(|r| (r.name.as_str(), r.device)),
            f.tool_life.is_none(),
        )
    });
    assert_eq!(fil, Some((Some(("FILEOR", 0)), true)));
    assert_eq!(p1.nip, Some('1'));
    assert_eq!(p1.tof.map(|t| (t.base(), t.is_lathe())), Some((6, true)));
    assert_eq!(p1.nam, Some('Z'));
    assert_eq!(p1.npd, Some(('Z', 'X')));
    assert_eq!(p1.mas, ['X', 'Z']);
    assert_eq!(p1.initial_g(), [0, 27, 90, 70, 95, 96]);
    let p2 = &pg.processes[1];
    assert_eq!(
        (p2.nip, p2.npd, p2.mas.clone()),
        (Some('3'), Some(('Z', 'Z')), vec!['Z'])
    );
    assert!(p2.sim.is_empty());
    assert_eq!(p2.g70.unwrap_or(Units::Millimetres), Units::Millimetres);
}

#[test]
fn nc110_example_verbatim_breaks_on_the_escaped_section_marker() {
    // The spec reproduces the example as the source prints it: a leading empty line, trailing
    // blanks and `\*6` (a Markdown escape) instead of `*6`. `\` cannot start a line (error 2), so
    // section 6 never opens: its PRO lines repeat processes of section 5 (184) and MAS is not an
    // instruction of section 5 (6).
    let src = include_str!("../fixtures/pgcfil_nc110_verbatim.txt");
    let (_, d) = run(src);
    assert_eq!(
        d,
        [
            (2, 33, 1),
            (184, 34, 5),
            (6, 35, 1),
            (184, 36, 5),
            (6, 37, 1)
        ]
    );
}

/// Wraps section bodies into an otherwise valid one-process PGCFIL.
fn wrap(s1: &str, s2: &str, s3: &str, s4: &str, s5: &str, s6: &str) -> String {
    format!(
        "NEW\n*1\n{s1}*2\n{s2}*3\n{s3}*4\nPRO=1\n{s4}*5\nPRO=1\nNIP=1\nTOF=2\nNAM=Z\nNPD=Z,X\n{s5}*6\n{s6}"
    )
}

#[test]
fn tri_examples() {
    let (pg, d) = run(&wrap(
        "TRI = CLS,D,\nTRI = DIS, VIS,\nTRI=EXE,RUN,\n",
        "",
        "",
        "",
        "",
        "",
    ));
    assert_eq!(d, []);
    let names: Vec<(&str, NewName, Option<u8>)> = pg
        .tri
        .iter()
        .map(|t| (t.old_name.as_str(), t.new_name.clone(), t.synchro))
        .collect();
    assert_eq!(
        names,
        [
            ("CLS", NewName::Delete, None),
            ("DIS", NewName::Rename("VIS".into()), None),
            ("EXE", NewName::Rename("RUN".into()), None)
        ]
    );
}

#[test]
fn jcl_examples() {
    // The manual prints `JCL = CAO,D` followed by a comma that is the empty third parameter.
    let (pg, d) = run(&wrap("", "", "JCL = CAO,D,\nJCL = VTU,UTV,\n", "", "", ""));
    assert_eq!(d, []);
    assert_eq!(pg.jcl.len(), 2);
    // Without that comma the instruction has two of its three parameters: error 10 at its end.
    let (_, d) = run(&wrap("", "", "JCL = CAO,D\n", "", "", ""));
    assert_eq!(d, [(10, 5, 12)]);
}

#[test]
fn sim_example_changes_the_number_of_e_variables() {
    let (pg, d) = run(&wrap("", "SIM = E,,200,,,\n", "", "", "", ""));
    assert_eq!(d, []);
    assert_eq!(pg.processes[0].sim[0].max_num, Some(200));
}

#[test]
fn ass_examples_each_load() {
    for (line, var, value) in [
        ("ASS=MCD,1", "MCD", 1.0),
        ("ASS=RMS,110", "RMS", 110.0),
        ("ASS=RMS,10", "RMS", 10.0),
        ("ASS=SRT,10", "SRT", 10.0),
        ("ASS=VRT,0.2", "VRT", 0.2),
        ("ASS=PRT,2", "PRT", 2.0),
        ("ASS=SK1023,255", "SK1023", 255.0),
    ] {
        let (pg, d) = run(&wrap("", "", "", &format!("{line}\n"), "", ""));
        assert_eq!(d, [], "{line}");
        assert_eq!(pg.processes[0].assigned(var), Some(value), "{line}");
    }
}

#[test]
fn nip_example_with_its_sentence_dot() {
    // `NIP=3 .` keeps the manual's sentence punctuation: "3 ." is not a one-character name (113).
    let src = "NEW\n*1\n*2\n*3\n*4\nPRO=1\n*5\nPRO=1\nNIP=3 .\nTOF=2\nNAM=Z\nNPD=Z,X\n";
    assert_eq!(run(src).1, [(113, 9, 5)]);
    let (pg, d) = run(&src.replace("3 .", "3"));
    assert_eq!(d, []);
    assert_eq!(pg.processes[0].nip, Some('3'));
}

#[test]
fn section5_examples() {
    let (pg, d) = run(&wrap("", "", "", "", "GXX=00,27,,70,94,\nCWP=C000,0\n", ""));
    assert_eq!(d, []);
    let p = &pg.processes[0];
    assert_eq!(
        p.gxx,
        Some([Some(0), Some(27), None, Some(70), Some(94), None])
    );
    assert_eq!(p.initial_g(), [0, 27, 90, 70, 94, 96]);
    assert_eq!(p.cwp.and_then(|c| c.cw_console), Some(0xC000));
    let (pg, d) = run(
        &wrap("", "", "", "", "GXX=01,,,70,95,97\nCWP=C200,0\n", "").replace("TOF=2", "TOF=12")
    );
    assert_eq!(d, []);
    let p = &pg.processes[0];
    assert_eq!(
        p.tof
            .map(|t| (t.base(), t.diameter_offsets(), t.inverted_ordinate())),
        Some((2, true, false))
    );
    assert_eq!(p.initial_g(), [1, 27, 90, 70, 95, 97]);
}

#[test]
fn mas_example_and_default_tables() {
    let (pg, d) = run(&wrap("", "", "", "", "", "PRO=1\nMAS = XYZ\n"));
    assert_eq!(d, []);
    let p = &pg.processes[0];
    assert_eq!(p.mas, ['X', 'Y', 'Z']);
    assert_eq!(p.fro_table()[11], 1.25);
    assert_eq!(p.fmo_table()[0], -1.0);
}

#[test]
fn invalid_plc_identifiers_of_table_7_1() {
    // Error 19 points at the wrong packet letter, 17 and 18 at the whole identifier.
    for (sig, code, col) in [
        ("U256K20", 18, 5),
        ("U200K32", 18, 5),
        ("I32A1", 18, 5),
        ("I32A32", 18, 5),
        ("X1K1", 17, 5),
        ("U1Q1", 19, 7),
    ] {
        let (_, d) = run(&wrap("", "", "", "", &format!("INU={sig},1\n"), ""));
        assert_eq!(d, [(code, 13, col)], "{sig}");
    }
}
