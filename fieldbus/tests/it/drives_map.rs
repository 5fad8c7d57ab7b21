//! `[[canopen.drive]]` in io.toml: valid entries parse as written; every documented drive error
//! is reported with its code, line and column; the example lathe's map with drives for X, Z and S
//! validates against the lathe's own AXCFIL.

use std::path::Path;
use std::time::Duration;

use fieldbus::map::{CanDrive, DriveMode, SdoWrite};
use fieldbus::{DeclaredAxis, DeclaredConnectors, codes, parse_map_with_axes};

/// The lathe's axes: X (TPA 41: coordinate, diameter), Z (1), S (820: spindle with encoder,
/// controlled acceleration); plus test axes of forbidden types in process 2.
fn axes() -> Vec<DeclaredAxis> {
    // Every axis homes (MCZ) but Z of process 1, an absolute encoder.
    let a = |process, name, tpa| DeclaredAxis {
        process,
        name,
        tpa,
        homes: !(process == 1 && name == 'Z'),
    };
    vec![
        a(1, 'X', 0x41),
        a(1, 'Z', 0x1),
        a(1, 'S', 0x820),
        a(2, 'A', 0x201),
        a(2, 'V', 0x101),
        a(2, 'W', 0x1_0009),
    ]
}

/// (code, line, column, message) of every error.
fn errors(text: &str) -> Vec<(u32, u32, u32, String)> {
    let (map, diags) = parse_map_with_axes(
        text,
        "io.toml",
        &DeclaredConnectors::default(),
        Some(&axes()),
    );
    assert_eq!(map.is_some(), !diag::has_errors(&diags));
    diags
        .iter()
        .filter(|d| d.is_error())
        .map(|d| (d.code, d.line, d.column, d.message.clone()))
        .collect()
}

const HEAD: &str =
    "[canopen]\ntransport = \"virtual\"\n[[canopen.node]]\nname = \"dio1\"\nnode_id = 2\n";

fn entry(fields: &str) -> String {
    format!("[[canopen.drive]]\n{fields}\n")
}

#[test]
fn valid_drive_entries_parse_as_written() {
    let text = format!(
        "{HEAD}{}{}{}",
        entry(
            "axis = \"X\"\nnode_id = 3\ncounts_per_unit = 10000\nmode = \"csp\"\nheartbeat_ms = 50"
        ),
        entry(
            "axis = \"Z\"\nnode_id = 4\ncounts_per_unit = 2500.5\nmode = \"csp\"\nsdo = [{ index = 0x6065, subindex = 0, value = 100000, size = 4 }]"
        ),
        entry("axis = \"S\"\nprocess = 1\nnode_id = 5\ncounts_per_unit = 4096\nmode = \"csv\""),
    );
    let (map, diags) = parse_map_with_axes(
        &text,
        "io.toml",
        &DeclaredConnectors::default(),
        Some(&axes()),
    );
    assert!(diags.iter().all(|d| !d.is_error()), "{diags:?}");
    let drives = map.expect("valid").canopen.expect("canopen").drives;
    // Each entry remembers where its node id is written (for start-up errors, 3077); X homes on
    // its csp drive (MCZ), Z has an absolute encoder and S is a csv spindle: no homing PDOs.
    let span = |n: &str| {
        let i = text.find(&format!("node_id = {n}\n")).expect("entry") + "node_id = ".len();
        i..i + n.len()
    };
    assert_eq!(
        drives,
        vec![
            CanDrive {
                process: 1,
                axis: 'X',
                node_id: 3,
                counts_per_unit: 10000.0,
                mode: DriveMode::Csp,
                heartbeat: Duration::from_millis(50),
                sdo: vec![],
                simulate: Default::default(),
                span: span("3"),
                homing: true,
            },
            CanDrive {
                process: 1,
                axis: 'Z',
                node_id: 4,
                counts_per_unit: 2500.5,
                mode: DriveMode::Csp,
                heartbeat: Duration::from_millis(100),
                sdo: vec![SdoWrite {
                    index: 0x6065,
                    subindex: 0,
                    value: 100_000,
                    size: 4
                }],
                simulate: Default::default(),
                span: span("4"),
                homing: false,
            },
            CanDrive {
                process: 1,
                axis: 'S',
                node_id: 5,
                counts_per_unit: 4096.0,
                mode: DriveMode::Csv,
                heartbeat: Duration::from_millis(100),
                sdo: vec![],
                simulate: Default::default(),
                span: span("5"),
                homing: false,
            },
        ]
    );
}

#[test]
fn every_drive_error_is_located() {
    let line = |fields: &str| format!("{HEAD}{}", entry(fields));
    // HEAD is 5 lines, `[[canopen.drive]]` line 6, the fields from line 7.
    type Expected<'a> = Vec<(u32, u32, u32, &'a str)>;
    let cases: Vec<(String, Expected)> = vec![
        (
            line("axis = \"Y\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\""),
            vec![(
                codes::DRIVE_AXIS,
                7,
                8,
                "AXCFIL declares no axis Y in process 1",
            )],
        ),
        (
            line("axis = \"X\"\nprocess = 3\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\""),
            vec![(
                codes::DRIVE_AXIS,
                7,
                8,
                "AXCFIL declares no axis X in process 3",
            )],
        ),
        (
            line("axis = \"XZ\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\""),
            vec![(codes::DRIVE_AXIS, 7, 8, "`XZ` is not an axis name")],
        ),
        (
            line("axis = \"X\"\nnode_id = 2\ncounts_per_unit = 1\nmode = \"csp\""),
            vec![(codes::DRIVE_NODE, 8, 11, "node id 2 is already an I/O node")],
        ),
        (
            line("axis = \"X\"\nnode_id = 128\ncounts_per_unit = 1\nmode = \"csp\""),
            vec![(codes::VALUE, 8, 11, "node id 128 is out of range")],
        ),
        (
            line("axis = \"X\"\nnode_id = 3\ncounts_per_unit = 0\nmode = \"csp\""),
            vec![(
                codes::DRIVE_SCALE,
                9,
                19,
                "counts_per_unit 0 is not a positive finite number",
            )],
        ),
        (
            line("axis = \"X\"\nnode_id = 3\ncounts_per_unit = -2.5\nmode = \"csp\""),
            vec![(
                codes::DRIVE_SCALE,
                9,
                19,
                "counts_per_unit -2.5 is not a positive finite number",
            )],
        ),
        (
            line("axis = \"X\"\nnode_id = 3\ncounts_per_unit = nan\nmode = \"csp\""),
            vec![(
                codes::DRIVE_SCALE,
                9,
                19,
                "counts_per_unit NaN is not a positive finite number",
            )],
        ),
        (
            line("axis = \"X\"\nnode_id = 3\ncounts_per_unit = inf\nmode = \"csp\""),
            vec![(
                codes::DRIVE_SCALE,
                9,
                19,
                "counts_per_unit inf is not a positive finite number",
            )],
        ),
        (
            line("axis = \"S\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\""),
            vec![(
                codes::DRIVE_MODE,
                10,
                8,
                "mode \"csp\" does not fit axis S (TPA=820), a spindle",
            )],
        ),
        (
            line("axis = \"Z\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csv\""),
            vec![(
                codes::DRIVE_MODE,
                10,
                8,
                "mode \"csv\" does not fit axis Z (TPA=1), a positioned axis",
            )],
        ),
        (
            line("axis = \"Z\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"pp\""),
            vec![(
                codes::DRIVE_MODE_NOT_YET,
                10,
                8,
                "mode \"pp\" (profile position) is not supported yet",
            )],
        ),
        (
            line("axis = \"Z\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"cst\""),
            vec![(codes::DRIVE_MODE, 10, 8, "unknown drive mode `cst`")],
        ),
        (
            line("axis = \"A\"\nprocess = 2\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\""),
            vec![(
                codes::DRIVE_AXIS_TYPE,
                7,
                8,
                "axis A has TPA=201, which includes 200 (absolute axis): not allowed for an axis driven over CANopen",
            )],
        ),
        (
            line("axis = \"W\"\nprocess = 2\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\""),
            vec![(
                codes::DRIVE_AXIS_TYPE,
                7,
                8,
                "axis W has TPA=10009, which includes 8 (switched axis), 10000 (encoder without reference mark): not allowed for an axis driven over CANopen",
            )],
        ),
        (
            line("axis = \"V\"\nprocess = 2\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\""),
            vec![(
                codes::DRIVE_AXIS_TYPE,
                7,
                8,
                "axis V is a virtual axis (TPA=101): it has no drive",
            )],
        ),
        (
            line(
                "axis = \"Z\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\"\nsdo = [{ index = 0x6065, value = 300, size = 1 }]",
            ),
            vec![(codes::VALUE, 11, 8, "SDO value 300 does not fit size 1")],
        ),
        (
            line("axis = \"Z\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\"\ngain = 3"),
            vec![(
                codes::SYNTAX,
                11,
                1,
                "unknown field `gain`, expected one of `axis`, `process`, `node_id`, `counts_per_unit`, `mode`, `heartbeat_ms`, `sdo`, `simulate`",
            )],
        ),
    ];
    for (text, want) in cases {
        let got = errors(&text);
        let want: Vec<(u32, u32, u32, String)> = want
            .into_iter()
            .map(|(c, l, col, m)| (c, l, col, m.to_string()))
            .collect();
        assert_eq!(got, want, "{text}");
    }
}

#[test]
fn an_axis_on_two_drives_and_a_node_of_two_drives_are_errors_naming_the_first() {
    let text = format!(
        "{HEAD}{}{}",
        entry("axis = \"Z\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\""),
        entry("axis = \"Z\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\""),
    );
    let (_, diags) = parse_map_with_axes(
        &text,
        "io.toml",
        &DeclaredConnectors::default(),
        Some(&axes()),
    );
    let got: Vec<_> = diags
        .iter()
        .map(|d| (d.code, d.line, d.message.clone(), d.hint.clone()))
        .collect();
    assert_eq!(
        got,
        vec![
            (
                codes::DRIVE_AXIS_TWICE,
                12,
                "axis Z of process 1 is on two drives".to_string(),
                "its first drive entry is on line 7; an axis has one drive".to_string()
            ),
            (
                codes::DRIVE_NODE,
                13,
                "node id 3 is already a drive".to_string(),
                "the drive entry on line 8 uses it; one drive per node".to_string()
            ),
        ]
    );
}

#[test]
fn without_the_axes_only_the_axis_checks_are_skipped() {
    let text = format!(
        "{HEAD}{}",
        entry("axis = \"Q\"\nnode_id = 2\ncounts_per_unit = 0\nmode = \"csv\"")
    );
    let (_, diags) = fieldbus::parse_map(&text, "io.toml", &DeclaredConnectors::default());
    let codes_seen: Vec<u32> = diags.iter().map(|d| d.code).collect();
    assert_eq!(codes_seen, vec![codes::DRIVE_NODE, codes::DRIVE_SCALE]);
}

#[test]
fn the_lathe_map_with_drives_for_x_z_and_s_validates_against_its_axcfil() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../plc-programs/lathe");
    let load = characterization::load_machine(&dir);
    let machine = load.machine.expect("the lathe loads");
    let axes: Vec<DeclaredAxis> = machine
        .axcfil
        .processes
        .iter()
        .flat_map(|p| {
            p.axes.iter().map(|a| DeclaredAxis {
                process: p.number,
                name: a.name,
                tpa: a.tpa.as_ref().map_or(0, |t| t.axis_type.raw),
                homes: a.mcz.is_some(),
            })
        })
        .collect();
    assert_eq!(
        axes.iter().map(|a| (a.name, a.tpa)).collect::<Vec<_>>(),
        vec![('X', 0x41), ('Z', 0x1), ('S', 0x820)]
    );
    // The bundled io.toml carries the drives of X, Z and the spindle.
    let text = std::fs::read_to_string(dir.join("io.toml")).expect("io.toml");
    let declared = DeclaredConnectors {
        inputs: vec![0, 1],
        outputs: vec![4, 5],
    };
    let (map, diags) = parse_map_with_axes(&text, "io.toml", &declared, Some(&axes));
    assert!(diags.is_empty(), "{diags:?}");
    let drives = map.expect("valid").canopen.expect("canopen").drives;
    assert_eq!(
        drives
            .iter()
            .map(|d| (d.axis, d.node_id))
            .collect::<Vec<_>>(),
        [('X', 3), ('Z', 4), ('S', 5)]
    );
}

#[test]
fn a_plain_run_starts_the_drives_beside_the_io_nodes_and_keeps_them_disabled() {
    let text = format!(
        "{HEAD}{}",
        entry("axis = \"Z\"\nnode_id = 3\ncounts_per_unit = 1\nmode = \"csp\"")
    );
    let (map, _) = parse_map_with_axes(
        &text,
        "io.toml",
        &DeclaredConnectors::default(),
        Some(&axes()),
    );
    let cfg = map.expect("valid").canopen.expect("canopen");
    let mut io = fieldbus::start_canopen(&cfg, &[], None).expect("the simulated drive starts");
    let drives = io.drives().expect("the drive is started");
    assert_eq!(drives.drives().len(), 1);
    // Nothing orders it: after a tick it answers with its power stage off (Shutdown: Ready to
    // switch on, statusword 0x0221).
    let mut packets = vec![0u8; packets::PACKETS_LEN];
    packets::PacketIo::publish_outputs(&mut io, 0, &packets);
    std::thread::sleep(std::time::Duration::from_millis(50));
    packets::PacketIo::latch_inputs(&mut io, 1, &mut packets);
    let a = io.drives().expect("drives").answers().clone();
    assert_eq!(a.seq, 1);
    assert_eq!(a.drives[0].values, [Some(0.0)]);
    assert_eq!(a.drives[0].statusword & 0x6F, 0x21);
    assert_eq!(a.drives[0].fault, None);
}
