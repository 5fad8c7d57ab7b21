//! The I/O map: the example machines' maps validate cleanly, every documented error is reported with
//! its code, line and column, and no text makes the parser panic.

use std::path::Path;
use std::time::Duration;

use fieldbus::map::{ByteRange, ModbusArea, TransportConfig};
use fieldbus::{DeclaredConnectors, codes, load_map, parse_map};

fn lathe() -> DeclaredConnectors {
    DeclaredConnectors {
        inputs: vec![0, 1],
        outputs: vec![4, 5],
    }
}

fn machine(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("plc-programs")
        .join(name)
}

/// (code, line, column) of every error.
fn located(text: &str, declared: &DeclaredConnectors) -> Vec<(u32, u32, u32)> {
    let (map, diags) = parse_map(text, "io.toml", declared);
    assert_eq!(map.is_some(), !diag::has_errors(&diags));
    diags
        .iter()
        .filter(|d| d.is_error())
        .map(|d| (d.code, d.line, d.column))
        .collect()
}

const DEVICE: &str = "[[modbus.device]]\nname = \"rio1\"\naddress = \"127.0.0.1:5020\"\n";

#[test]
fn lathe_map_is_valid_and_parsed_as_written() {
    let (map, diags) = load_map(&machine("lathe"), &lathe());
    assert!(diags.is_empty(), "{diags:?}");
    let map = map.expect("valid");
    let hmi = map.hmi.expect("hmi");
    assert_eq!(hmi.bind.to_string(), "127.0.0.1:1502");
    assert_eq!((hmi.holding[0].start, hmi.holding[0].len), (128 + 800, 16));
    let rio = &map.modbus[0];
    assert_eq!(
        (rio.name.as_str(), rio.unit, rio.timeout, rio.alarm_ticks),
        ("rio1", 1, Duration::from_millis(20), 5)
    );
    assert_eq!(rio.healthy.map(|s| s.to_string()), Some("I100K0".into()));
    assert!(rio.write_connection, "a write connection by default");
    assert_eq!(
        rio.inputs
            .iter()
            .map(|m| (m.range, m.area, m.address))
            .collect::<Vec<_>>(),
        [
            (
                ByteRange { start: 0, len: 4 },
                ModbusArea::DiscreteInputs,
                0
            ),
            (
                ByteRange { start: 4, len: 4 },
                ModbusArea::DiscreteInputs,
                32
            ),
        ]
    );
    assert_eq!(
        rio.outputs
            .iter()
            .map(|m| (m.range.start, m.address))
            .collect::<Vec<_>>(),
        [(16, 0), (20, 32)]
    );
    let can = map.canopen.expect("canopen");
    assert_eq!(can.transport, TransportConfig::Virtual);
    assert_eq!(can.nodes[0].heartbeat, Duration::from_millis(100));
    assert_eq!(
        can.nodes[0]
            .inputs
            .iter()
            .map(|m| (m.range.start, m.pdo, m.offset))
            .collect::<Vec<_>>(),
        [(0, 1, 0), (4, 1, 4)]
    );
    assert_eq!(can.nodes[0].sdo[0].index, 0x1017);
}

#[test]
fn write_connection_can_be_turned_off_and_must_be_a_boolean() {
    let none = DeclaredConnectors::default();
    let (map, diags) = parse_map(
        &format!("{DEVICE}write_connection = false\n"),
        "io.toml",
        &none,
    );
    assert!(diags.is_empty(), "{diags:?}");
    assert!(!map.expect("valid").modbus[0].write_connection);
    assert_eq!(
        located(&format!("{DEVICE}write_connection = 1\n"), &none),
        [(codes::SYNTAX, 4, 20)]
    );
}

#[test]
fn direct_write_is_on_by_default_and_can_be_turned_off() {
    let none = DeclaredConnectors::default();
    let (map, diags) = parse_map(DEVICE, "io.toml", &none);
    assert!(diags.is_empty(), "{diags:?}");
    assert!(map.expect("valid").modbus[0].direct_write);
    let (map, diags) = parse_map(&format!("{DEVICE}direct_write = false\n"), "io.toml", &none);
    assert!(diags.is_empty(), "{diags:?}");
    assert!(!map.expect("valid").modbus[0].direct_write);
    assert_eq!(
        located(&format!("{DEVICE}direct_write = \"yes\"\n"), &none),
        [(codes::SYNTAX, 4, 16)]
    );
}

#[test]
fn io_cpus_are_parsed_and_checked_against_the_machine() {
    let (map, diags) = parse_map("[affinity]\nio_cpus = [0]\n", "io.toml", &lathe());
    assert!(diags.is_empty(), "{diags:?}");
    assert_eq!(map.expect("valid").io_cpus, vec![0]);
    let (map, _) = parse_map("", "io.toml", &lathe());
    assert_eq!(map.expect("valid").io_cpus, Vec::<usize>::new());
    // No machine has a million CPUs; the error points at the index.
    assert_eq!(
        located("[affinity]\nio_cpus = [0, 1000000]\n", &lathe()),
        [(codes::CPU, 2, 15)]
    );
    assert_eq!(
        located("[affinity]\nio_cpus = []\n", &lathe()),
        [(codes::CPU, 2, 11)]
    );
    assert_eq!(
        located("[affinity]\nio_cpus = [0, 0]\n", &lathe()),
        [(codes::CPU, 2, 15)]
    );
    assert_eq!(
        located("[affinity]\nio_cpus = [-1]\n", &lathe())[0].0,
        codes::SYNTAX
    );
    assert_eq!(
        located("[affinity]\nscan_cpu = 0\n", &lathe())[0].0,
        codes::SYNTAX
    );
}

#[test]
fn mill_map_is_valid() {
    let declared = DeclaredConnectors {
        inputs: vec![0, 1, 2],
        outputs: vec![4, 5, 6],
    };
    let (map, diags) = load_map(&machine("mill"), &declared);
    assert!(diags.is_empty(), "{diags:?}");
    let map = map.expect("valid");
    assert_eq!(map.modbus.len(), 2);
    assert_eq!(map.modbus[1].inputs[0].area, ModbusArea::InputRegisters);
    assert_eq!(map.canopen.expect("canopen").nodes.len(), 2);
}

#[test]
fn syntax_and_unknown_fields_are_located() {
    assert_eq!(
        located("[[modbus.device]\n", &lathe()),
        [(codes::SYNTAX, 1, 17)]
    );
    assert_eq!(
        located("[hmi]\nbindd = \"x\"\n", &lathe()),
        [(codes::SYNTAX, 2, 1)]
    );
}

#[test]
fn undeclared_connectors_direction_and_range_are_errors() {
    let text = format!("{DEVICE}[[input]]\ndevice = \"rio1\"\nconnector = 2\narea = \"coils\"\n");
    assert_eq!(located(&text, &lathe()), [(codes::UNDECLARED, 6, 13)]);
    let text = format!("{DEVICE}[[input]]\ndevice = \"rio1\"\nconnector = 4\narea = \"coils\"\n");
    assert_eq!(located(&text, &lathe()), [(codes::DIRECTION, 6, 13)]);
    let text = format!("{DEVICE}[[output]]\ndevice = \"rio1\"\nconnector = 0\narea = \"coils\"\n");
    assert_eq!(located(&text, &lathe()), [(codes::DIRECTION, 6, 13)]);
    let text = format!("{DEVICE}[[input]]\ndevice = \"rio1\"\nconnector = 32\narea = \"coils\"\n");
    assert_eq!(located(&text, &lathe()), [(codes::OUT_OF_RANGE, 6, 13)]);
    // Four bytes from W1A2 spill into connector 2, which is not declared.
    let text = format!(
        "{DEVICE}[[input]]\ndevice = \"rio1\"\nbyte = \"W1A2\"\nlen = 4\narea = \"coils\"\n"
    );
    assert_eq!(located(&text, &lathe()), [(codes::UNDECLARED, 6, 8)]);
    let text = format!("{DEVICE}[[input]]\ndevice = \"rio1\"\nbyte = \"W1K0\"\narea = \"coils\"\n");
    assert_eq!(located(&text, &lathe()), [(codes::NOT_PACKET_A, 6, 8)]);
    let text = format!("{DEVICE}[[input]]\ndevice = \"rio1\"\nbyte = \"I1A0\"\narea = \"coils\"\n");
    assert_eq!(located(&text, &lathe()), [(codes::BAD_SIGNAL, 6, 8)]);
}

#[test]
fn overlaps_unknown_devices_and_duplicates_are_errors() {
    let text = format!(
        "{DEVICE}[[input]]\ndevice = \"rio1\"\nconnector = 0\narea = \"coils\"\n[[input]]\ndevice = \"rio1\"\nbyte = \"W0A3\"\narea = \"coils\"\naddress = 100\n"
    );
    let (map, diags) = parse_map(&text, "io.toml", &lathe());
    assert!(map.is_none());
    let diags: Vec<_> = diags.into_iter().filter(|d| d.is_error()).collect();
    assert_eq!(diags.len(), 1);
    assert_eq!((diags[0].code, diags[0].line), (codes::OVERLAP, 8));
    assert_eq!(diags[0].message, "byte W0A3 is already mapped");
    assert_eq!(diags[0].hint, "the first mapping of it is on line 4");

    let text = format!("{DEVICE}[[input]]\ndevice = \"rio2\"\nconnector = 0\narea = \"coils\"\n");
    let (_, diags) = parse_map(&text, "io.toml", &lathe());
    let diags: Vec<_> = diags.into_iter().filter(|d| d.is_error()).collect();
    assert_eq!(
        (diags[0].code, diags[0].line, diags[0].column),
        (codes::UNKNOWN_DEVICE, 5, 10)
    );
    assert_eq!(diags[0].hint, "known devices: rio1");

    let text = format!("{DEVICE}{DEVICE}");
    assert_eq!(located(&text, &lathe()), [(codes::DUPLICATE_DEVICE, 5, 8)]);
}

#[test]
fn bus_specific_fields_and_values_are_checked() {
    let can = "[canopen]\n[[canopen.node]]\nname = \"dio1\"\nnode_id = 2\n";
    let text =
        format!("{can}[[input]]\ndevice = \"dio1\"\nconnector = 0\narea = \"coils\"\npdo = 1\n");
    assert_eq!(located(&text, &lathe()), [(codes::FIELD, 8, 8)]);
    let text = format!("{can}[[input]]\ndevice = \"dio1\"\nconnector = 0\npdo = 5\n");
    assert_eq!(located(&text, &lathe()), [(codes::VALUE, 8, 7)]);
    let text = format!("{can}[[input]]\ndevice = \"dio1\"\nconnector = 0\npdo = 1\noffset = 6\n");
    assert_eq!(located(&text, &lathe()), [(codes::VALUE, 9, 10)]);
    let text = "[canopen]\n[[canopen.node]]\nname = \"dio1\"\nnode_id = 128\n";
    assert_eq!(located(text, &lathe()), [(codes::VALUE, 4, 11)]);
    let text = "[canopen]\ntransport = \"socketcan\"\n";
    assert_eq!(located(text, &lathe()), [(codes::TRANSPORT, 1, 1)]);
    let text = format!(
        "{DEVICE}[[output]]\ndevice = \"rio1\"\nconnector = 4\narea = \"input_registers\"\n"
    );
    assert_eq!(located(&text, &lathe()), [(codes::READ_ONLY_AREA, 7, 8)]);
    let text = format!("{DEVICE}[[input]]\ndevice = \"rio1\"\nconnector = 0\n");
    assert_eq!(located(&text, &lathe()), [(codes::FIELD, 4, 1)]);
    let text = format!(
        "{DEVICE}[[input]]\ndevice = \"rio1\"\nconnector = 0\nbyte = \"W0A0\"\narea = \"coils\"\n"
    );
    assert_eq!(located(&text, &lathe()), [(codes::WHERE, 4, 1)]);
    let text = "[[modbus.device]]\nname = \"x\"\naddress = \"localhost\"\n";
    assert_eq!(located(text, &lathe()), [(codes::SOCKET_ADDR, 3, 11)]);
    let text = format!(
        "{DEVICE}[[input]]\ndevice = \"rio1\"\nbyte = \"W0A0\"\nlen = 3\narea = \"input_registers\"\n"
    );
    assert_eq!(located(&text, &lathe()), [(codes::VALUE, 6, 8)]);
}

#[test]
fn healthy_bits_and_hmi_windows_are_checked() {
    let with = |h: &str| {
        format!(
            "[[modbus.device]]\nname = \"rio1\"\naddress = \"127.0.0.1:5020\"\nhealthy = \"{h}\"\n"
        )
    };
    assert_eq!(located(&with("I100K0"), &lathe()), []);
    assert_eq!(
        located(&with("W100K0"), &lathe()),
        [(codes::HEALTHY, 4, 11)]
    );
    assert_eq!(located(&with("U4A0"), &lathe()), [(codes::HEALTHY, 4, 11)]);
    assert_eq!(located(&with("I2A0"), &lathe()), [(codes::HEALTHY, 4, 11)]);
    assert_eq!(located(&with("I0T0"), &lathe()), [(codes::HEALTHY, 4, 11)]);
    let text = "[hmi]\nholding = [{ byte = \"W0A0\", len = 2 }]\n";
    assert_eq!(located(text, &lathe()), [(codes::HMI_WINDOW, 2, 21)]);
    let text = "[hmi]\nholding = [{ byte = \"W255K2\", len = 4 }]\n";
    assert_eq!(located(text, &lathe()), [(codes::HMI_WINDOW, 2, 37)]);
    let text = "[hmi]\nholding = [{ byte = \"W200K1\", len = 2 }]\n";
    assert_eq!(located(text, &lathe()), [(codes::HMI_WINDOW, 2, 12)]);
    let text = "[hmi]\nbind = \"0.0.0.0:502\"\n";
    let (map, _) = parse_map(text, "io.toml", &lathe());
    assert_eq!(
        map.and_then(|m| m.hmi).map(|h| h.bind.to_string()),
        Some("0.0.0.0:502".into())
    );
    let (map, _) = parse_map("[hmi]\n", "io.toml", &lathe());
    assert_eq!(
        map.and_then(|m| m.hmi).map(|h| h.bind.to_string()),
        Some("127.0.0.1:1502".into()),
        "binds to 127.0.0.1 by default"
    );
}

#[test]
fn declared_but_unmapped_connectors_are_warnings() {
    let text = format!("{DEVICE}[[input]]\ndevice = \"rio1\"\nconnector = 0\narea = \"coils\"\n");
    let (map, diags) = parse_map(
        &text,
        "io.toml",
        &DeclaredConnectors {
            inputs: vec![0, 1],
            outputs: vec![],
        },
    );
    assert!(map.is_some());
    assert_eq!(diags.len(), 1);
    assert_eq!(
        (diags[0].code, diags[0].is_error()),
        (codes::UNMAPPED, false)
    );
    assert_eq!(
        diags[0].message,
        "IOCFIL declares IN1 but no mapping uses it"
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(128))]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,200}") {
        let _ = parse_map(&text, "io.toml", &lathe());
    }

    #[test]
    fn mutated_example_never_panics(cut in 0usize..4000, insert in "[\\[\\]=\"a-z0-9 \\n._{},]{0,12}") {
        let base = std::fs::read_to_string(machine("lathe").join("io.toml")).expect("lathe map");
        let mut at = cut.min(base.len());
        while !base.is_char_boundary(at) {
            at -= 1;
        }
        let text = format!("{}{}{}", &base[..at], insert, &base[at..]);
        let (map, diags) = parse_map(&text, "io.toml", &lathe());
        proptest::prop_assert_eq!(map.is_some(), !diag::has_errors(&diags));
    }
}

#[test]
fn hmi_server_limits_have_defaults_ranges_and_no_unknown_key() {
    use fieldbus::map::HmiLimits;
    let limits = |text: &str| {
        let (map, diags) = parse_map(text, "io.toml", &lathe());
        assert!(diags.is_empty(), "{diags:?}");
        map.and_then(|m| m.hmi).map(|h| h.limits)
    };
    assert_eq!(
        limits("[hmi]\n"),
        Some(HmiLimits {
            unit: 1,
            max_connections: 8,
            max_requests_per_s: 100,
            idle_timeout: Duration::from_secs(60),
        })
    );
    assert_eq!(
        limits(
            "[hmi]\nunit = 255\nmax_connections = 2\nmax_requests_per_s = 20\nidle_timeout_ms = 500\n"
        ),
        Some(HmiLimits {
            unit: 255,
            max_connections: 2,
            max_requests_per_s: 20,
            idle_timeout: Duration::from_millis(500),
        })
    );
    assert_eq!(
        located("[hmi]\nunit = 256\n", &lathe()),
        [(codes::VALUE, 2, 8)]
    );
    assert_eq!(
        located("[hmi]\nmax_connections = 0\n", &lathe()),
        [(codes::VALUE, 2, 19)]
    );
    assert_eq!(
        located("[hmi]\nmax_requests_per_s = 0\n", &lathe()),
        [(codes::VALUE, 2, 22)]
    );
    assert_eq!(
        located("[hmi]\nidle_timeout_ms = 0\n", &lathe()),
        [(codes::VALUE, 2, 19)]
    );
    // A misspelt key is an error at the key, never ignored.
    assert_eq!(
        located("[hmi]\nmax_conections = 3\n", &lathe()),
        [(codes::SYNTAX, 2, 1)]
    );
}
