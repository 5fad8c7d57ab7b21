//! Every row of `docs/fanuc-conformance.md` behaves as the table says: implemented and differing codes
//! plan without error, refused ones fail with a diagnostic that names the code (no silent word).

use partprogram::{Dialect, MachineSpec, PlanOptions, compile, plan};

fn table() -> String {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/fanuc-conformance.md");
    std::fs::read_to_string(path).expect("docs/fanuc-conformance.md")
}

/// (code, status, probe) of every table row with a probe in backticks.
fn rows(text: &str) -> Vec<(String, String, String)> {
    text.lines()
        .filter_map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            if cells.len() < 5 {
                return None;
            }
            let probe = cells[3].strip_prefix('`')?.strip_suffix('`')?;
            Some((
                cells[1].to_string(),
                cells[2].to_string(),
                probe.to_string(),
            ))
        })
        .collect()
}

/// Compiles and plans `O1; probe; M30` on a HAAS mill: Ok, or the first error message.
fn outcome(probe: &str) -> Result<(), String> {
    let m = MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z']);
    let src = format!("O1\n{}\nM30\n", probe.replace(';', "\n"));
    let (prog, diags) = compile(&m, "probe", &src);
    if let Some(d) = diags.iter().find(|d| d.severity == diag::Severity::Error) {
        return Err(d.message.clone());
    }
    let prog = prog.ok_or("no program")?;
    plan(&prog, PlanOptions::default())
        .map(|_| ())
        .map_err(|(_, d)| d.message)
}

#[test]
fn every_code_of_the_conformance_table_behaves_as_the_table_says() {
    let text = table();
    let rows = rows(&text);
    assert!(rows.len() > 120, "only {} rows read", rows.len());
    let mut wrong = Vec::new();
    for (code, status, probe) in &rows {
        match (status.as_str(), outcome(probe)) {
            ("implemented" | "differs", Ok(())) => {}
            ("refused", Err(msg)) if msg.contains(code.as_str()) => {}
            (s, got) => wrong.push(format!("{code} ({s}) `{probe}`: {got:?}")),
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn every_g_and_m_code_of_the_haas_tables_is_in_the_conformance_table() {
    let text = table();
    let codes: Vec<String> = rows(&text).into_iter().map(|r| r.0).collect();
    let mut missing = Vec::new();
    let g = [
        0, 1, 2, 3, 4, 9, 10, 12, 13, 17, 18, 19, 20, 21, 28, 29, 31, 35, 36, 37, 40, 41, 42, 43,
        44, 47, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60, 61, 64, 65, 68, 69, 70, 71, 72, 73,
        74, 76, 77, 80, 81, 82, 83, 84, 85, 86, 87, 88, 89, 90, 91, 92, 93, 94, 98, 99, 100, 101,
        102, 103, 107, 110, 129, 136, 141, 143, 150, 153, 154, 155, 161, 169, 174, 184, 187, 188,
    ];
    for n in g {
        let c = format!("G{n:02}");
        if !codes.contains(&c) {
            missing.push(c);
        }
    }
    for n in [
        0, 1, 2, 3, 4, 5, 6, 8, 9, 10, 16, 19, 21, 30, 31, 59, 96, 97, 98, 99,
    ] {
        let c = format!("M{n:02}");
        if !codes.contains(&c) {
            missing.push(c);
        }
    }
    for l in "DEFGHIJKLMNOPQRSTUVWXYZ".chars() {
        if !codes.contains(&l.to_string()) {
            missing.push(l.to_string());
        }
    }
    assert!(missing.is_empty(), "missing rows: {missing:?}");
}
