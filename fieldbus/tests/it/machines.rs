//! The example machines' `io.toml` agree with their IOCFIL: loading each machine with the
//! characterization crate and validating its map against the declared `INx` / `OUx` connectors gives
//! no diagnostic at all (this is the glue `ncplc run --io modbus|canopen` uses).

use std::path::Path;

use fieldbus::{DeclaredConnectors, load_map};

fn declared(machine: &str) -> (std::path::PathBuf, DeclaredConnectors) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("plc-programs")
        .join(machine);
    let load = characterization::load_machine(&dir);
    let iocfil = load
        .machine
        .and_then(|m| m.iocfil)
        .expect("the machine has an IOCFIL");
    (
        dir,
        DeclaredConnectors {
            inputs: iocfil.input_connectors(),
            outputs: iocfil.output_connectors(),
        },
    )
}

#[test]
fn lathe_io_toml_matches_its_iocfil() {
    let (dir, d) = declared("lathe");
    assert_eq!(
        d,
        DeclaredConnectors {
            inputs: vec![0, 1],
            outputs: vec![4, 5]
        }
    );
    let (map, diags) = load_map(&dir, &d);
    assert!(diags.is_empty(), "{diags:?}");
    assert!(map.is_some());
}

#[test]
fn mill_io_toml_matches_its_iocfil() {
    let (dir, d) = declared("mill");
    assert_eq!(
        d,
        DeclaredConnectors {
            inputs: vec![0, 1, 2],
            outputs: vec![4, 5, 6]
        }
    );
    let (map, diags) = load_map(&dir, &d);
    assert!(diags.is_empty(), "{diags:?}");
    assert!(map.is_some());
}
