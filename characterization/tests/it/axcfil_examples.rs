//! The manual's AXCFIL and FCRSYS examples (spec §16, fixtures extracted verbatim into
//! `tests/fixtures/FX-*.txt`): complete files load or fail with exactly the errors the manual's
//! own inconsistencies imply; fragments parse record by record with only the known errors.

use characterization::axcfil::{self, AxisType};
use characterization::fcrsys;
use characterization::reader::{Grammar, read, read_with};

fn fixture(name: &str) -> String {
    let path = format!("{}/tests/fixtures/{name}.txt", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn axcfil_codes(src: &str) -> Vec<(u32, u32, u32)> {
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    d.extend(axcfil::validate(&f).1);
    d.iter().map(|d| (d.code, d.line, d.column)).collect()
}

fn fcrsys_codes(src: &str) -> Vec<(u32, u32, u32)> {
    let (f, mut d) = read_with("FCRSYS", src.as_bytes(), Grammar::FCRSYS);
    d.extend(fcrsys::validate(&f).1);
    d.iter().map(|d| (d.code, d.line, d.column)).collect()
}

#[test]
fn fx46_two_processes_loads_with_its_model() {
    let src = fixture("FX-46");
    assert_eq!(axcfil_codes(&src), []);
    let (f, _) = read("AXCFIL", src.as_bytes());
    let (ax, _) = axcfil::validate(&f);
    assert_eq!((ax.nbp, ax.tim, ax.extension.ecdf), (2, 1, true));
    let p1 = &ax.processes[0];
    assert_eq!(
        p1.interpolators
            .iter()
            .map(|i| i.name.as_str())
            .collect::<Vec<_>>(),
        ["1", "2"]
    );
    assert_eq!(
        p1.cas.as_ref().map(|c| c.axes.clone()),
        Some(vec!['X', 'Z', 'T', 'S'])
    );
    let s = p1.axis('S').map(|a| a.axis_type());
    assert_eq!(s, Some(AxisType::decode(0x820)));
    assert!(
        s.is_some_and(|t| t.spindle_with_encoder && t.controlled_acceleration && !t.coordinate)
    );
    let t = p1.axis('T').and_then(|a| a.pas);
    assert_eq!(
        t.map(|p| (p.mec_pitch, p.rev_num_motor, p.start_point)),
        Some((36.0, Some(36.0), Some(1.0)))
    );
    assert!(p1.axis('X').is_some_and(|a| a.axis_type().diameter));
    let p2 = &ax.processes[1];
    assert_eq!(p2.common[0].axes, ['S']);
    assert_eq!(p2.axes.iter().map(|a| a.name).collect::<String>(), "XZ");
    assert_eq!(p1.compensation[0].points.len(), 8);
    assert_eq!(p1.compensation[0].reference, Some(30));
}

/// FX-47 declares `NBP=2,ECDF` but characterizes only process 1 (spec §17 item 23): error 922
/// at section 1, nothing else.
#[test]
fn fx47_breaks_the_process_count_rule() {
    assert_eq!(axcfil_codes(&fixture("FX-47")), [(922, 1, 1)]);
}

/// FX-15 is section 1 alone: only error 1 (sections 2 and 3 missing), reported at the end.
#[test]
fn fx15_section_one_of_a_two_process_lathe() {
    let src = fixture("FX-15");
    assert_eq!(axcfil_codes(&src), [(1, 12, 1)]);
}

/// Codes a single record can produce (grammar, value types, value ranges): what a fragment can
/// be judged by without the rest of its file.
const RECORD_CODES: [u32; 36] = [
    2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 160, 161, 163, 166,
    172, 180, 205, 210, 216, 217, 222, 900, 901, 929, 944,
];

/// Record-level diagnostics of a fragment: `.....`/`...` filler lines dropped; a fragment that
/// does not start at `*1` is put into a scaffold (section 1 with ECDF on, and `PRO=1` of its
/// section `section`).
fn fragment(name: &str, section: u32) -> Vec<(u32, String)> {
    let src = fixture(name);
    let body: String = src
        .lines()
        .filter(|l| !l.trim().chars().all(|c| c == '.') || l.trim().is_empty())
        .map(|l| format!("{l}\n"))
        .collect();
    let head = "*1\nNBP=1,ECDF\nTIM=1,0,0,0,0\nPRO=1\n";
    let text = if body.starts_with("*1\n") {
        if body.contains("NBP") {
            body
        } else {
            body.replacen("*1\n", head, 1)
        }
    } else if body.starts_with("*2\n") {
        format!("{head}{body}")
    } else if section == 3 {
        format!("{head}*2\n*3\nPRO=1\n{body}")
    } else {
        format!("{head}*2\nPRO=1\n{body}*3\n")
    };
    let (f, mut d) = read(name, text.as_bytes());
    d.extend(axcfil::validate(&f).1);
    d.iter()
        .filter(|d| RECORD_CODES.contains(&d.code))
        .map(|d| (d.code, text[d.span.clone()].to_string()))
        .collect()
}

#[test]
fn fragments_parse_record_by_record() {
    for name in [
        "FX-07", "FX-14", "FX-17.1", "FX-20", "FX-21", "FX-22", "FX-26", "FX-27", "FX-28", "FX-31",
        "FX-32.1", "FX-33b.1", "FX-39.1", "FX-40",
    ] {
        assert_eq!(fragment(name, 2), [], "{name}");
    }
    for name in ["FX-42", "FX-42.1", "FX-45"] {
        assert_eq!(fragment(name, 3), [], "{name}");
    }
}

/// The fragments as printed keep the manual's OCR damage, placeholders and slips; each gives
/// exactly the error the rule implies.
#[test]
fn fragments_with_the_manuals_slips() {
    let empty = || (10, String::new());
    // Latin `TRA` for TPA (§17.1): not an instruction.
    assert_eq!(fragment("FX-17", 2), [(6, "TRA".to_string())]);
    // `TPA = 820` without the comma the rule asks for (003:1462): too few parameters.
    assert_eq!(fragment("FX-19", 2), [empty()]);
    // `GM0 = ..., ..., ...` is the manual's placeholder for the values.
    assert_eq!(
        fragment("FX-24", 2),
        [
            (20, "...".to_string()),
            (20, "...".to_string()),
            (20, "...".to_string())
        ]
    );
    // `ZN0` with a digit zero (§17.1).
    assert_eq!(fragment("FX-33b", 2), [(6, "ZN0".to_string())]);
    // `SRV=,` / `SRV = ,` have two fields where SRV has three (003:3044, 003:3128, 003:3149).
    assert_eq!(fragment("FX-35", 2), [empty()]);
    assert_eq!(fragment("FX-36a", 2), [empty()]);
    assert_eq!(fragment("FX-36b", 2), [empty()]);
    // Cyrillic homoglyphs in `NAS = В` (reported by the reader and by the ASCII parameter),
    // `ТРА = 2,` and `FTP = ТАВТТ1/МР0` (§3.8); the normalised copy FX-39.1 is clean.
    let fx39: Vec<u32> = fragment("FX-39", 2).iter().map(|d| d.0).collect();
    assert_eq!(fx39, [900, 900, 900, 900]);
    // `E00n = …` stands for "the last point" in the two-table examples.
    for name in ["FX-43c", "FX-44"] {
        assert_eq!(
            fragment(name, 3),
            [(6, "E00n".to_string()), (6, "E00n".to_string())],
            "{name}"
        );
    }
    // `IN1=1,X...,...,...,...`: the placeholders stand where int_tick and block_num go.
    for name in ["FX-43a", "FX-43b"] {
        assert_eq!(
            fragment(name, 2),
            [(15, "...".to_string()), (15, "...".to_string())],
            "{name}"
        );
    }
}

#[test]
fn fcrsys_fx01_standard_file_loads() {
    assert_eq!(fcrsys_codes(&fixture("FX-01")), []);
}

/// FX-02 and FX-03 are single sections: the missing sections (1) and the missing closing `*` (913).
#[test]
fn fcrsys_section_examples_are_sections() {
    assert_eq!(fcrsys_codes(&fixture("FX-02")), [(1, 9, 1), (913, 9, 1)]);
    assert_eq!(fcrsys_codes(&fixture("FX-03")), [(1, 13, 1), (913, 13, 1)]);
}

/// FX-04 shows two alternative HDD records without their section marker: error 3 once.
#[test]
fn fcrsys_hdd_examples() {
    assert_eq!(
        fcrsys_codes(&fixture("FX-04")),
        [(3, 1, 1), (1, 3, 1), (913, 3, 1)]
    );
    for rec in ["HDD=C", "HDD=CDF"] {
        let src = format!(
            "*1\nMP0=C:\\CNC32\\MP0\nMP1=C:\\CNC32\\MP1\n*2\nAXCONF,AXCFIL/MP0\nPGCONF,PGCFIL/MP0\nIOCONF,IOCFIL/MP0\nFORMAT,FORMAT/MP0\n*3\n{rec}\n*\n"
        );
        assert_eq!(fcrsys_codes(&src), [], "{rec}");
    }
}

/// The section-4 records quoted in prose (spec FX-05): misspelled driver names are not errors,
/// `IDE` with a CD as Primary Master is.
#[test]
fn fcrsys_section4_records() {
    let base = "*1\nMP0=C:\\CNC32\\MP0\nMP1=C:\\CNC32\\MP1\n*2\nAXCONF,AXCFIL/MP0\nPGCONF,PGCFIL/MP0\nIOCONF,IOCFIL/MP0\nFORMAT,FORMAT/MP0\n*4\n";
    for rec in [
        "FLP=A,B",
        "FLP=,B",
        "FLP=B,",
        "FLP=,",
        "IDE=HDD,,,",
        "IDE=HDD,DD",
        "IDE=,HDD",
        "IDE=HDD,HDD,CD",
        "DOC=DOC",
        "DOC=DOS",
        "USB=",
        "USB=CD,CRD,FLOPY,FLASH",
        "USB=,HDD",
        "USB=CRD,CRD,,",
    ] {
        assert_eq!(fcrsys_codes(&format!("{base}{rec}\n*\n")), [], "{rec}");
    }
    assert_eq!(
        fcrsys_codes(&format!("{base}IDE=CD,HDD\n*\n")),
        [(911, 10, 5)]
    );
}
