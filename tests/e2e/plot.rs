//! End-to-end tests of `ncplc plot trace` and `ncplc nc plot`: the SVGs equal the committed
//! goldens in `tests/golden/plot/` (`BLESS=1` rewrites them after a deliberate change; look at
//! them before committing), PNGs are real PNGs of the chart's size, bad input is refused.

use std::path::Path;

use crate::e2e_common::{ncplc_at_root as ncplc, root};

fn golden(out: &Path, name: &str) {
    let got = std::fs::read_to_string(out).expect("svg written");
    let path = root().join("tests/golden/plot").join(name);
    if std::env::var_os("BLESS").is_some() {
        std::fs::write(&path, &got).expect("bless");
        return;
    }
    let want = std::fs::read_to_string(&path).expect("golden exists (BLESS=1 to create)");
    assert!(
        got == want,
        "{name} differs from its golden (BLESS=1 after checking it)"
    );
}

#[test]
fn the_timing_diagram_of_the_lathe_trace_matches_its_golden_svg() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("basic.svg");
    let o = ncplc(&[
        "plot",
        "trace",
        "plc-programs/lathe/traces/basic.jsonl",
        "--signals",
        "START_PB,SPINDLE_CW,COOLANT,FOV,MSTB",
        "--machine",
        "plc-programs/lathe",
        "--to",
        "7s",
        "-o",
        out.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).ends_with("basic.svg: 5 signals, ticks 0..=700\n"));
    golden(&out, "lathe-basic-timing.svg");
    let text = std::fs::read_to_string(&out).expect("svg");
    for label in [
        "START_PB I0A3",
        "SPINDLE_CW U4A0",
        "COOLANT U4A2",
        "FOV W14K0",
        "MSTB I1K0",
    ] {
        assert!(text.contains(label), "lane {label}");
    }
}

#[test]
fn the_mill_contour_matches_its_golden_svg_and_png_is_a_real_png() {
    let dir = tempfile::tempdir().expect("tempdir");
    let svg = dir.path().join("contour.svg");
    let o = ncplc(&[
        "nc",
        "plot",
        "plc-programs/mill",
        "CONTOUR",
        "-o",
        svg.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    golden(&svg, "mill-contour-xy.svg");
    let png = dir.path().join("thread.png");
    let o = ncplc(&[
        "nc",
        "plot",
        "plc-programs/lathe",
        "G84THREAD",
        "--view",
        "zx",
        "-o",
        png.to_str().expect("utf8"),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(&png).expect("png");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width and height, big-endian, at bytes 16..24.
    assert_eq!(&bytes[16..24], &[0, 0, 3, 32, 0, 0, 2, 88]); // 800 x 600
    // Both were drawn beside their names and renamed over them: no temporary file is left.
    let left: Vec<String> = std::fs::read_dir(dir.path())
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".ncplc-"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn plots_refuse_bad_input_with_a_reason() {
    for (args, want) in [
        (
            vec![
                "plot",
                "trace",
                "plc-programs/lathe/traces/basic.jsonl",
                "--signals",
                "I0A3",
                "-o",
                "x.pdf",
            ],
            "error: x.pdf: the output must end in .svg or .png\n",
        ),
        (
            vec![
                "plot",
                "trace",
                "plc-programs/lathe/traces/basic.jsonl",
                "--signals",
                "START_PB",
                "-o",
                "x.svg",
            ],
            "error: --signals: `START_PB` is not a signal address (give --machine to use names)\n",
        ),
        (
            vec![
                "plot",
                "trace",
                "plc-programs/lathe/traces/basic.jsonl",
                "--signals",
                "I0A3",
                "--from",
                "9",
                "--to",
                "2",
                "-o",
                "x.svg",
            ],
            "error: --from 9 is after --to 2\n",
        ),
        (
            vec![
                "plot",
                "trace",
                "plc-programs/lathe/traces/basic.jsonl",
                "--signals",
                "I0A3",
                "--from",
                "abc",
                "-o",
                "x.svg",
            ],
            "error: --from: `abc` is not a tick number or a time such as 1.5s or 300ms\n",
        ),
    ] {
        let o = ncplc(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert_eq!(String::from_utf8_lossy(&o.stderr), want, "{args:?}");
    }
}
