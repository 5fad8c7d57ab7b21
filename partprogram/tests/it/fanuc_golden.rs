//! The Fanuc compile pinned to a golden file: the repository's Fanuc programs and 320 generated
//! variants, 80 of them valid (bad words, duplicate `N` and `O`, `M97 P`/`M98 P`/`GOTO`/`G65 P` to
//! present and missing targets, recursion through the macro folder, balanced and unbalanced
//! `WHILE … DO`/`END`, several `O` programs in one file), are compiled with every diagnostic kept
//! and with a cap of 2; each diagnostic (every field), the counts the cap hid and, for a program
//! that compiles, its units, block numbers and `DO`/`END`/`GOTO` links are written out and compared
//! with `golden/fanuc_compile.txt`.
//!
//! The golden file was recorded with the compile that parsed the whole file before building its
//! units (64b104a, before issue 23's streaming Fanuc units); the streaming compile gives the same
//! text but for the order of the hidden counts of a capped compile when several files overflow
//! (15 lines: now the main file first, then by name). `UPDATE_GOLDEN=1 cargo test -p partprogram
//! --test it fanuc_golden::` rewrites it; `FANUC_VARIANTS_DIR=<dir>` also writes the variants there
//! as files, to compare the `ncplc nc check` output of two builds.

use std::fmt::Write as _;
use std::path::PathBuf;

use partprogram::{Dialect, MachineSpec, compile_capped};

use crate::common::machines;

fn fixtures() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

/// A Fanuc mill whose macro folder holds the valid programs O2000 and O2006.
fn mill() -> MachineSpec {
    let mut m = MachineSpec::new(Dialect::Fanuc, &['X', 'Y', 'Z']);
    m.macro_dir = fixtures().join("fanuc_macros");
    m
}

/// A Fanuc mill whose macro folder has errors: O2001 ↔ O2002 and O2005 recurse, O2003 has errors
/// and a second program O2004 and repeats O2000.
fn mill_bad() -> MachineSpec {
    let mut m = mill();
    m.macro_dir = fixtures().join("fanuc_macros_bad");
    m
}

/// A Fanuc lathe (H and U/W are addresses of the C and X/Z axes) with the valid macro folder.
fn lathe() -> MachineSpec {
    let mut m = MachineSpec::new(Dialect::Fanuc, &['X', 'Z', 'C']);
    m.diameter_x = true;
    m.macro_dir = fixtures().join("fanuc_macros");
    m
}

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }

    fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[self.below(xs.len() as u64) as usize]
    }
}

/// One generated program: `O<main>`, then blocks of every kind, numbered mostly in rising order
/// with repeats and gaps, and targets drawn from the numbers used, nearby and missing.
fn variant(seed: u64) -> String {
    let mut r = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let main = ["1", "23", "2000", "2001", "0"][r.below(5) as usize];
    let mut s = String::new();
    if r.below(8) != 0 {
        let _ = writeln!(s, "O{main}");
    }
    let lines = 3 + r.below(22);
    let mut n = 0u64;
    let plain = [
        "G00 X0 Y0 Z5.",
        "G01 X10. F100.",
        "G02 X20. Y0 R10.",
        "M03 S1000",
        "G43 H01 Z2.",
        "G43 Z2.",
        "G01 X1. E1.",
        "G01 Q1. V2.",
        "G01 X1. X2.",
        "G00 G01 X1.",
        "G7 X1.",
        "M300",
        "M96",
        "M03 M04",
        "H150",
        "D300",
        "T-1",
        "G02 G41 X1. Y1. R1.",
        "U1. W2.",
        "X1 2",
        "G01 X1.@",
        "#1 = #1 + 1",
        "#1 = [",
        "M97",
        "M99",
        "M30",
        "G65 P2000 A1.",
        "G65 P9999",
        "WHILE [#1 LT 3] DO 4",
        "DO 1",
        "(comment) G01 X1. ; G00 Y1.",
        "G01 X1. E1. ; G01 Y1. E2.",
    ];
    for _ in 0..lines {
        let target = match r.below(4) {
            0 => n.saturating_sub(r.below(4)),
            1 => n + 1 + r.below(3),
            2 => r.below(40),
            _ => 9999,
        };
        let body = match r.below(16) {
            0 => format!("M97 P{target}"),
            1 => format!(
                "M98 P{}",
                ["2000", "2001", "2002", "2004", "2005", "2006", "7777", main][r.below(8) as usize]
            ),
            2 => format!("GOTO {target}"),
            3 => format!("IF [#1 GT 2] GOTO {target}"),
            4 => ["GOTO 1.5", "GOTO -3", "GOTO #5", "M99 P3"][r.below(4) as usize].to_string(),
            5 => format!("WHILE [#1 LT 3] DO {}", 1 + r.below(3)),
            6 | 7 => format!("END {}", 1 + r.below(3)),
            8 if r.below(3) == 0 => {
                let o = ["3000", "3001", "2000", "2004", main][r.below(5) as usize];
                let _ = writeln!(s, "O{o}");
                continue;
            }
            _ => r.pick(&plain).to_string(),
        };
        let skip = if r.below(12) == 0 { "/" } else { "" };
        match r.below(10) {
            0..=5 => {
                n += 1 + r.below(3);
                let _ = writeln!(s, "{skip}N{n} {body}");
            }
            6 => {
                let _ = writeln!(s, "{skip}N{} {body}", n.saturating_sub(r.below(3)));
            }
            _ => {
                let _ = writeln!(s, "{skip}{body}");
            }
        }
    }
    if r.below(3) != 0 {
        s.push_str("M30\n");
    }
    s
}

/// A generated program that compiles: every block numbered (a few numbers repeated: a warning, the
/// later block is the target), `GOTO`/`M97 P` to numbers of the program, loops balanced, `M98 P`
/// and `G65 P` to the valid macro folder's programs, sometimes a second program `O3000`.
fn clean_variant(seed: u64) -> String {
    let mut r = Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1);
    let lines = 4 + r.below(30);
    let mut s = String::from("O0042\n");
    let mut open: Vec<u64> = Vec::new();
    let mut n = 0;
    let valid = [
        "G00 X0 Y0 Z5.",
        "G01 X10. F100.",
        "G02 X20. Y0 R10.",
        "M03 S1000",
        "G43 H01 Z2.",
        "#1 = #1 + 1",
        "G65 P2006 A1.",
        "M98 P2000",
        "M98 P2006 L2",
        "(comment) G01 X1. ; G00 Y1.",
    ];
    for _ in 0..lines {
        // Numbers repeat at most a tenth of the time: the first two thirds are all written.
        let target = 1 + r.below(lines * 2 / 3);
        let body = match r.below(8) {
            0 => format!("GOTO {target}"),
            1 => format!("IF [#1 GT 2] GOTO {target}"),
            2 => format!("M97 P{target}"),
            3 if open.len() < 3 => {
                let free: Vec<u64> = (1..=3).filter(|m| !open.contains(m)).collect();
                let m = free[r.below(free.len() as u64) as usize];
                open.push(m);
                format!("WHILE [#1 LT 3] DO {m}")
            }
            4 if !open.is_empty() => format!("END {}", open.pop().unwrap_or(1)),
            _ => r.pick(&valid).to_string(),
        };
        n = if n > 0 && r.below(10) == 0 { n } else { n + 1 };
        let skip = if r.below(12) == 0 { "/" } else { "" };
        let _ = writeln!(s, "{skip}N{n} {body}");
    }
    while let Some(m) = open.pop() {
        n += 1;
        let _ = writeln!(s, "N{n} END {m}");
    }
    s.push_str("M30\n");
    if r.below(4) == 0 {
        s.push_str("O3000\nN1 G01 X1.\nN2 WHILE [#2 LT 1] DO 1\nN3 GOTO 2\nN4 END 1\nM99\n");
    }
    s
}

/// Every diagnostic of `src` compiled on `m` with the caps 0 and 2, and the compiled program.
fn report(out: &mut String, title: &str, m: &MachineSpec, src: &str) {
    for max in [0, 2] {
        let (prog, diags, hidden) = compile_capped(m, "P.nc", src, max);
        let _ = writeln!(out, "== {title} (max {max})");
        for d in &diags {
            let _ = writeln!(
                out,
                "{}:{}:{} [{}..{}] {} {:?} {} | {}",
                d.file,
                d.line,
                d.column,
                d.span.start,
                d.span.end,
                d.code,
                d.severity,
                d.message,
                d.hint
            );
        }
        for h in &hidden {
            let _ = writeln!(
                out,
                "hidden {}: {} errors, {} warnings",
                h.file, h.errors, h.warnings
            );
        }
        let Some(p) = prog else {
            let _ = writeln!(out, "rejected");
            continue;
        };
        if max != 0 {
            continue;
        }
        let _ = writeln!(out, "program O{:?}, {} blocks", p.number, p.blocks.len());
        for (i, u) in p.units.iter().enumerate() {
            let index: Vec<String> = u.index.iter().map(|(n, b)| format!("{n}>{b}")).collect();
            let _ = writeln!(
                out,
                "unit {i} {:?} O{} file {} blocks {}..{} index {}",
                u.kind,
                u.l,
                u.file,
                u.start,
                u.end,
                index.join(",")
            );
        }
        let mut lib: Vec<_> = p.library.iter().collect();
        lib.sort();
        let _ = writeln!(out, "library {lib:?}");
        for (i, b) in p.blocks.iter().enumerate() {
            let _ = writeln!(
                out,
                "block {i} N{:?} unit {} file {} {:?} words {} mac {} jump {:?}",
                b.n,
                b.unit,
                b.file,
                b.span,
                b.words.len(),
                b.mac.is_some(),
                b.jump
            );
        }
    }
}

/// Writes the generated variants as files `V<seed>.nc` / `C<seed>.nc` into `dir` (to compare the
/// `ncplc nc check` output of two builds).
fn dump_variants(dir: &std::path::Path) {
    for seed in 0..240u64 {
        std::fs::write(dir.join(format!("V{seed}.nc")), variant(seed)).expect("written");
    }
    for seed in 0..80u64 {
        std::fs::write(dir.join(format!("C{seed}.nc")), clean_variant(seed)).expect("written");
    }
}

fn golden_text() -> String {
    if let Some(dir) = std::env::var_os("FANUC_VARIANTS_DIR") {
        dump_variants(std::path::Path::new(&dir));
    }
    let mut out = String::new();
    let root = machines();
    let mut repo: Vec<PathBuf> = ["mill/nc", "lathe/nc"]
        .iter()
        .flat_map(|d| std::fs::read_dir(root.join(d)).expect("nc folder"))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "nc"))
        .collect();
    repo.push(fixtures().join("O1000-cylinder.nc"));
    for dir in ["fanuc_macros", "fanuc_macros_bad"] {
        repo.extend(
            std::fs::read_dir(fixtures().join(dir))
                .expect("macro folder")
                .filter_map(|e| e.ok().map(|e| e.path())),
        );
    }
    repo.sort();
    for p in &repo {
        let src = std::fs::read_to_string(p).expect("program");
        let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
        report(
            &mut out,
            &format!("file {}", name.unwrap_or_default()),
            &mill(),
            &src,
        );
    }
    for seed in 0..240u64 {
        let m = match seed % 5 {
            4 => lathe(),
            3 => mill_bad(),
            _ => mill(),
        };
        report(&mut out, &format!("variant {seed}"), &m, &variant(seed));
    }
    for seed in 0..80u64 {
        let m = mill();
        report(
            &mut out,
            &format!("clean variant {seed}"),
            &m,
            &clean_variant(seed),
        );
    }
    out
}

#[test]
fn fanuc_compiles_give_the_recorded_diagnostics_and_programs() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/it/golden/fanuc_compile.txt");
    let got = golden_text();
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(&path, &got).expect("golden written");
        return;
    }
    let want = std::fs::read_to_string(&path).expect("golden file");
    if got != want {
        if let Some(out) = std::env::var_os("GOLDEN_GOT") {
            std::fs::write(out, &got).expect("written");
        }
        let line = got
            .lines()
            .zip(want.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(got.lines().count().min(want.lines().count()));
        let show = |t: &str| {
            t.lines()
                .skip(line.saturating_sub(3))
                .take(8)
                .collect::<Vec<_>>()
                .join("\n")
        };
        panic!(
            "line {} differs\n-- got:\n{}\n-- recorded:\n{}",
            line + 1,
            show(&got),
            show(&want)
        );
    }
}

#[test]
fn the_variants_reach_every_check() {
    // The comparison is worth something only if the variants reach every phase of the compile.
    let text = golden_text();
    for what in [
        "address E",
        "unknown address",
        "block number N",
        "is loaded twice",
        "M97 P",
        "M97 needs P",
        "M98 P7777: program O7777 not found",
        "unbounded recursion",
        "no block N",
        "without END",
        "END 1 without WHILE",
        "inside an open DO",
        "loops overlap",
        "G65 P9999",
        "Some(",
    ] {
        assert!(text.contains(what), "no variant gives `{what}`");
    }
    let rejected = text.lines().filter(|l| *l == "rejected").count();
    let compiled = text.lines().filter(|l| l.starts_with("program O")).count();
    assert!(
        rejected > 100 && compiled > 30,
        "{rejected} rejected, {compiled} compiled"
    );
}
