//! Tests of the interface map: the default table, overrides, roles per process and every error code.

use super::*;

fn sig(s: &str) -> Signal {
    s.parse().expect("signal")
}

/// One `[[signal]]` table.
fn entry(fields: &str) -> String {
    format!("[[signal]]\n{fields}\n")
}

fn codes_of(text: &str) -> Vec<u32> {
    match InterfaceMap::parse_all("f", text) {
        Ok(_) => Vec::new(),
        Err(errors) => errors.iter().map(InterfaceMapError::code).collect(),
    }
}

#[test]
fn builtin_map_has_the_documented_entries() {
    let map = InterfaceMap::parse("default", DEFAULT_MAP_TOML).expect("the shipped map parses");
    // 49 of plc-interface-map.md §1, 20 request signals of the CNC kernel and 5 of the PLC
    // messages.
    assert_eq!(map.len(), 76);
    assert_eq!(map.signal("mstb"), Some(sig("I1K0")));
    assert_eq!(map.signal("MFIN"), Some(sig("U11K0")));
    assert_eq!(map.signal("RABI3"), Some(sig("U10K10")));
    let scode = map.get("SCODE").expect("SCODE");
    assert_eq!(
        (scode.width, scode.dir),
        (Width::Dword, Direction::CncToPlc)
    );
    assert_eq!(map.fault_flag(), Some(sig("U11K8")));
    // Every default entry is process 1's fixed signal of its own name.
    assert!(
        map.iter()
            .all(|s| s.process == 1 && s.role.as_deref() == Some(s.name.as_str()))
    );
    assert_eq!(map.role(1, "mcode").map(|s| s.signal), Some(sig("W3K0")));
    assert_eq!(map.role(2, "MCODE"), None);
}

#[test]
fn overrides_replace_and_extend() {
    let o = InterfaceMap::parse(
        "o",
        "[[signal]]\nname='mfin'\naddress='U12K0'\nwidth='bit'\ndir='out'\n\
         [[signal]]\nname='DOOR'\naddress='I0K5'\nwidth='bit'\ndir='in'\nmeaning='door closed'\n",
    )
    .expect("valid override");
    let map = InterfaceMap::builtin().with_overrides(o).expect("no clash");
    assert_eq!(map.len(), 77);
    assert_eq!(map.signal("MFIN"), Some(sig("U12K0")));
    assert_eq!(map.role(1, "MFIN").map(|s| s.signal), Some(sig("U12K0")));
    let door = map.get("door").expect("DOOR");
    assert_eq!(
        (door.meaning.as_str(), door.role.as_deref()),
        ("door closed", None)
    );
}

#[test]
fn a_role_renames_a_fixed_signal_and_process_two_gets_its_own() {
    let text = entry("name='MSTROBE'\nrole='MSTB'\naddress='I1K0'\nwidth='bit'\ndir='in'")
        + &entry("name='MSTB2'\nrole='mstb'\nprocess=2\naddress='I6K0'\nwidth='bit'\ndir='in'")
        + &entry("name='MCODE2'\nrole='MCODE'\nprocess=2\naddress='W7K0'\nwidth='byte'\ndir='in'")
        + &entry("name='MFIN2'\nrole='MFIN'\nprocess=2\naddress='U30K0'\nwidth='bit'\ndir='out'");
    let o = InterfaceMap::parse("o", &text).expect("valid");
    let map = InterfaceMap::builtin().with_overrides(o).expect("no clash");
    // MSTROBE replaced MSTB (same process and role): 76 - 1 + 4.
    assert_eq!(map.len(), 79);
    assert_eq!(map.get("MSTB"), None);
    assert_eq!(
        map.role(1, "MSTB").map(|s| s.name.as_str()),
        Some("MSTROBE")
    );
    let m2 = map.role(2, "MSTB").expect("process 2 strobe");
    assert_eq!(
        (m2.name.as_str(), m2.signal, m2.process),
        ("MSTB2", sig("I6K0"), 2)
    );
    assert_eq!(map.role(2, "MCODE").map(|s| s.signal), Some(sig("W7K0")));
    assert_eq!(
        map.missing_roles(2, &[ProcessNeeds::m_only(2)]),
        Vec::<MissingRole>::new()
    );
}

#[test]
fn bad_entries_are_rejected_with_the_reason() {
    let e = InterfaceMap::parse(
        "f",
        "[[signal]]\nname='X'\naddress='W0K2'\nwidth='dword'\ndir='in'\n",
    );
    assert!(
        matches!(e, Err(InterfaceMapError::Entry { ref name, .. }) if name == "X"),
        "{e:?}"
    );
    let e = InterfaceMap::parse(
        "f",
        "[[signal]]\nname='X'\naddress='I0K2'\nwidth='byte'\ndir='in'\n",
    );
    assert!(matches!(e, Err(InterfaceMapError::Entry { .. })), "{e:?}");
    let e = InterfaceMap::parse("f", "[[signal]]\nname='X'\naddress='I0K2'\n");
    assert!(matches!(e, Err(InterfaceMapError::Toml { .. })), "{e:?}");
}

#[test]
fn each_error_has_its_code() {
    // 1601: not the map's shape.
    assert_eq!(
        codes_of("[[signal]]\nname='X'\naddress='I0K2'\n"),
        vec![1601]
    );
    assert_eq!(
        codes_of(&entry(
            "name='X'\naddress='I0K5'\nwidth='bit'\ndir='in'\nprocesss=2"
        )),
        vec![1601]
    );
    // 1602: bad name, bad address, width past the connector, defined twice, width not the role's.
    let e = entry("name='1X'\naddress='I0K5'\nwidth='bit'\ndir='in'")
        + &entry("name='Y'\naddress='I0Q5'\nwidth='bit'\ndir='in'")
        + &entry("name='Z'\naddress='W0K3'\nwidth='word'\ndir='in'")
        + &entry("name='D'\naddress='I0K5'\nwidth='bit'\ndir='in'")
        + &entry("name='d'\naddress='I0K6'\nwidth='bit'\ndir='in'")
        + &entry("name='MC2'\nrole='MCODE'\nprocess=2\naddress='W7K0'\nwidth='word'\ndir='in'");
    assert_eq!(codes_of(&e), vec![1602; 5]);
    // 1604: unknown role, machine-wide role for process 2, process 2 without a role.
    let e = entry("name='A'\nrole='MSTROBE'\naddress='I0K5'\nwidth='bit'\ndir='in'")
        + &entry("name='R2'\nrole='RESET'\nprocess=2\naddress='I6K1'\nwidth='bit'\ndir='in'")
        + &entry("name='DOOR2'\nprocess=2\naddress='I6K2'\nwidth='bit'\ndir='in'");
    assert_eq!(codes_of(&e), vec![1604; 3]);
    // 1605: process outside 1..5.
    let e = entry("name='A'\nrole='MSTB'\nprocess=6\naddress='I6K0'\nwidth='bit'\ndir='in'")
        + &entry("name='B'\nrole='MSTB'\nprocess=0\naddress='I6K1'\nwidth='bit'\ndir='in'");
    assert_eq!(codes_of(&e), vec![1605, 1605]);
    // 1606: the same (process, role) twice in one file.
    let e = entry("name='A'\nrole='MSTB'\nprocess=2\naddress='I6K0'\nwidth='bit'\ndir='in'")
        + &entry("name='B'\nrole='MSTB'\nprocess=2\naddress='I6K1'\nwidth='bit'\ndir='in'");
    assert_eq!(codes_of(&e), vec![1606]);
    // 1607: overlapping bits; a bit inside a byte.
    let e = entry("name='A'\naddress='I0K5'\nwidth='bit'\ndir='in'")
        + &entry("name='B'\naddress='I0K5'\nwidth='bit'\ndir='in'")
        + &entry("name='C'\naddress='W0K0'\nwidth='byte'\ndir='in'");
    assert_eq!(codes_of(&e), vec![1607, 1607]);
    // 1608: connector convention both ways, the I/U prefix, the role's direction.
    let e = entry("name='A'\naddress='U12K0'\nwidth='bit'\ndir='in'")
        + &entry("name='B'\naddress='W5K0'\nwidth='byte'\ndir='out'")
        + &entry("name='C'\naddress='I150K0'\nwidth='bit'\ndir='out'")
        + &entry("name='MF2'\nrole='MFIN'\nprocess=2\naddress='I150K1'\nwidth='bit'\ndir='in'");
    assert_eq!(codes_of(&e), vec![1608; 4]);
    // Connectors 100..255 take either direction.
    let e = entry("name='A'\naddress='U150K0'\nwidth='bit'\ndir='out'")
        + &entry("name='B'\naddress='I150K1'\nwidth='bit'\ndir='in'")
        + &entry("name='C'\naddress='W151N0'\nwidth='dword'\ndir='out'");
    assert_eq!(codes_of(&e), Vec::<u32>::new());
}

#[test]
fn an_override_that_overlaps_a_default_entry_is_a_clash_in_the_override_file() {
    let text = entry("name='MSTB2'\nrole='MSTB'\nprocess=2\naddress='I1K0'\nwidth='bit'\ndir='in'");
    let o = InterfaceMap::parse("interface.toml", &text).expect("valid alone");
    let errors = InterfaceMap::builtin()
        .with_overrides(o)
        .expect_err("I1K0 is process 1's MSTB");
    assert_eq!(errors.len(), 1);
    assert_eq!(
        errors[0].to_string(),
        "interface.toml: entry `MSTB2`: address I1K0 overlaps entry `MSTB` (I1K0)"
    );
    let d = errors[0].to_diagnostic(Some(&text));
    assert_eq!((d.code, d.line, d.column), (1607, 5, 9));
    assert_eq!(&text[d.span.clone()], "'I1K0'");
}

#[test]
fn messages_name_the_process_and_the_role() {
    let text = entry("name='A'\nrole='MSTB'\nprocess=2\naddress='I6K0'\nwidth='bit'\ndir='in'")
        + &entry("name='B'\nrole='MSTB'\nprocess=2\naddress='I6K1'\nwidth='bit'\ndir='in'")
        + &entry("name='C'\nrole='MSTB'\nprocess=7\naddress='I6K2'\nwidth='bit'\ndir='in'");
    let errors = InterfaceMap::parse_all("m.toml", &text).expect_err("two errors");
    let got: Vec<String> = errors.iter().map(ToString::to_string).collect();
    assert_eq!(
        got,
        vec![
            "m.toml: entry `B`: process 2 already has its MSTB in entry `A`",
            "m.toml: entry `C`: process 7 is outside 1..5",
        ]
    );
    let d = errors[1].to_diagnostic(Some(&text));
    assert_eq!((d.line, d.column, &text[d.span.clone()]), (18, 9, "7"));
    assert_eq!(d.message, "entry `C`: process 7 is outside 1..5");
}

#[test]
fn an_unreadable_override_is_an_io_error() {
    let dir = std::env::temp_dir().join(format!("ncplc-map-io-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("interface.toml")).expect("a directory in its place");
    let e = InterfaceMap::load_for_machine(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    let e = e.expect_err("not a file");
    assert_eq!(e.code(), 1603);
    assert_eq!(e.span(), None);
}

#[test]
fn processes_two_to_nbp_must_have_their_handshake_roles() {
    let map = InterfaceMap::builtin();
    let needs = [
        ProcessNeeds::m_only(2),
        ProcessNeeds {
            process: 3,
            spindle: true,
            tools: true,
        },
    ];
    let missing = map.missing_roles(3, &needs);
    let got: Vec<(u8, &str)> = missing.iter().map(|m| (m.process, m.role)).collect();
    assert_eq!(
        got,
        vec![
            (2, "MSTB"),
            (2, "MFIN"),
            (2, "MCODE"),
            (3, "MSTB"),
            (3, "MFIN"),
            (3, "MCODE"),
            (3, "SSTB"),
            (3, "SFIN"),
            (3, "SCODE"),
            (3, "TSTB"),
            (3, "TFIN"),
            (3, "TCODE"),
        ]
    );
    assert_eq!(
        missing[0].to_string(),
        "process 2 has no MSTB in the interface map (AXCFIL NBP=3)"
    );
    assert_eq!(MissingRole::CODE, 1609);
    assert!(map.missing_roles(1, &needs).is_empty());
}

mod props {
    use super::*;
    use proptest::prelude::*;

    /// Pieces of map entries, valid and not, so that generated files reach every check.
    const FIELDS: &[&str] = &[
        "name='A'",
        "name='MSTB2'",
        "name='1X'",
        "role='MSTB'",
        "role='MFIN'",
        "role='RESET'",
        "role='NOPE'",
        "process=2",
        "process=6",
        "process=-1",
        "address='I6K0'",
        "address='I1K0'",
        "address='U30K0'",
        "address='W7K3'",
        "address='Q1'",
        "width='bit'",
        "width='byte'",
        "width='dword'",
        "dir='in'",
        "dir='out'",
        "meaning='m'",
        "[[signal]]",
        "x=1",
    ];

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]

        #[test]
        fn any_map_text_gives_a_map_or_located_errors(picks in proptest::collection::vec(0..FIELDS.len(), 0..40)) {
            let text: String = picks.iter().map(|&i| format!("{}\n", FIELDS[i])).collect();
            let checked = InterfaceMap::parse_all("f", &text)
                .and_then(|o| InterfaceMap::builtin().with_overrides(o));
            if let Err(errors) = checked {
                prop_assert!(!errors.is_empty());
                for e in &errors {
                    prop_assert!((1601..=1608).contains(&e.code()));
                    if let Some(span) = e.span() {
                        prop_assert!(span.end <= text.len());
                    }
                    let d = e.to_diagnostic(Some(&text));
                    prop_assert!(d.span.end <= text.len());
                }
            }
        }
    }
}
