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
    let (pg, d) = run(include_str!("fixtures/pgcfil_nc110.txt"));
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
