//! Shared by the part-run benchmarks: a controller built as `ncplc run <machine> --program NAME
//! --until-end --virtual-time --no-watch` builds it, through [`Controller::builder`].

use std::path::{Path, PathBuf};

use controller::settings::{Clock, Hmi, Part, PartSpec, Scan};
use controller::{Controller, WrapIo};

/// The session token of the HMI benches' server (a viewer: the benches only watch).
#[allow(dead_code)]
pub const BENCH_TOKEN: &str = "bench-token-0123456789";

/// A bundled machine's directory.
pub fn machine_dir(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../plc-programs")
        .join(name)
}

/// A copy of the bundled machine `name` in `into`, with `text` as its partprogram `program`.
#[allow(dead_code)] // only the part bench runs a program of its own
pub fn machine_with_program(name: &str, into: &Path, program: &str, text: &str) -> PathBuf {
    let dir = into.join(name);
    copy_dir(&machine_dir(name), &dir);
    std::fs::write(dir.join("nc").join(program), text).unwrap_or_else(|e| panic!("{e}"));
    dir
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap_or_else(|e| panic!("{}: {e}", to.display()));
    for entry in std::fs::read_dir(from).unwrap_or_else(|e| panic!("{}: {e}", from.display())) {
        let entry = entry.unwrap_or_else(|e| panic!("{e}"));
        let target = to.join(entry.file_name());
        if entry.path().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), &target).unwrap_or_else(|e| panic!("{e}"));
        }
    }
}

/// The web HMI of the benches: an ephemeral loopback port, one viewer token (from a file in `tmp`).
#[allow(dead_code)] // the part bench serves no HMI
pub fn bench_hmi(tmp: &Path) -> Hmi {
    let tokens = tmp.join("hmi-tokens");
    std::fs::write(&tokens, format!("viewer {BENCH_TOKEN}\n")).unwrap_or_else(|e| panic!("{e}"));
    Hmi {
        addr: "127.0.0.1:0".parse().unwrap_or_else(|e| panic!("{e}")),
        readonly: false,
        token_file: Some(tokens),
        allow_hosts: Vec::new(),
        allow_origins: Vec::new(),
        tls: None,
        limits: hmi::security::limits::Limits::default(),
    }
}

/// The controller of `ncplc run DIR --program PROGRAM --until-end --virtual-time --no-watch`
/// (JIT), with the web HMI `hmi` and `wrap` around its I/O.
pub fn part_controller(
    dir: &Path,
    program: &str,
    hmi: Option<Hmi>,
    wrap: Option<WrapIo>,
) -> Controller {
    let part = Part {
        spec: PartSpec {
            program: Some(PathBuf::from(program)),
            process: 1,
            ..PartSpec::default()
        },
        trajectory: None,
        until_end: true,
    };
    let mut builder = Controller::builder(dir)
        .part(Some(part))
        .hmi(hmi)
        .clock(Clock::Virtual)
        .scan(Scan {
            watch: false,
            ..Scan::default()
        });
    if let Some(wrap) = wrap {
        builder = builder.wrap_io(wrap);
    }
    builder.build().unwrap_or_else(|e| panic!("{e}"))
}

/// The mill's square 25 times: about 10 minutes of machining.
#[allow(dead_code)] // the HMI benches run the lathe's PART1
pub fn long_mill_program() -> String {
    let mut s =
        String::from("%3 \"Ten minutes of squares\nN10 T2 M06\nN20 G54 S2000 M03\nN30 M08\n");
    s.push_str("N40 G00 X-100 Y-100 Z-50\nN50 G01 Z-60 F300\n");
    let mut n = 60;
    for _ in 0..25 {
        for (x, y) in [(-160, -100), (-160, -160), (-100, -160), (-100, -100)] {
            s.push_str(&format!("N{n} X{x} Y{y} F600\n"));
            n += 10;
        }
    }
    s.push_str(&format!(
        "N{n} G00 Z-50\nN{} M09\nN{} M05\nN{} M30\n",
        n + 10,
        n + 20,
        n + 30
    ));
    s
}
