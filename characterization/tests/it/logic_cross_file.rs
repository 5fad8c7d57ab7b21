//! Cross-file rules of PGCFIL and IOCFIL against AXCFIL: one test per error number, with line and
//! column, and the manual's own examples checked against each other.

use characterization::axcfil::{self, Axcfil};
use characterization::reader::{Grammar, read, read_with};
use characterization::{iocfil, pgcfil};

const AX_NC110: &str = include_str!("../fixtures/axcfil_nc110.txt");
const PG_NC110: &str = include_str!("../fixtures/pgcfil_nc110.txt");

fn axcfil(src: &str) -> Axcfil {
    let (f, d) = read("AXCFIL", src.as_bytes());
    let (ax, more) = axcfil::validate(&f);
    assert!(
        !diag::has_errors(&d) && !diag::has_errors(&more),
        "{d:?} {more:?}"
    );
    ax
}

/// Every diagnostic (code, line, column) of PGCFIL `src` against `ax`: decoding and cross-file.
fn pg(src: &str, ax: &Axcfil) -> Vec<(u32, u32, u32)> {
    let (f, mut d) = read_with("PGCFIL", src.as_bytes(), Grammar::PGCFIL);
    let (p, more) = pgcfil::parse(&f);
    d.extend(more);
    d.extend(pgcfil::check_against(&p, &f, ax));
    d.iter().map(|d| (d.code, d.line, d.column)).collect()
}

/// Every diagnostic of IOCFIL `src` against `ax`.
fn io(src: &str, ax: &Axcfil) -> Vec<(u32, u32, u32)> {
    let (f, mut d) = read("IOCFIL", src.as_bytes());
    let (i, more) = iocfil::parse(&f);
    d.extend(more);
    d.extend(iocfil::check_against(&i, &f, ax));
    d.iter().map(|d| (d.code, d.line, d.column)).collect()
}

/// Line and column of the `nth` occurrence of `needle` (a `^` marks the position inside it).
fn at(src: &str, needle: &str, nth: usize) -> (u32, u32) {
    let mark = needle.find('^').unwrap_or(0);
    let needle = needle.replace('^', "");
    let offset = mark
        + src
            .match_indices(&needle)
            .nth(nth)
            .map(|(i, _)| i)
            .unwrap_or_else(|| panic!("{needle} not in source"));
    let line = src[..offset].matches('\n').count() + 1;
    let col = offset - src[..offset].rfind('\n').map_or(0, |i| i + 1) + 1;
    (line as u32, col as u32)
}

fn expect(got: Vec<(u32, u32, u32)>, code: u32, src: &str, needle: &str, nth: usize) {
    let (l, c) = at(src, needle, nth);
    assert_eq!(got, [(code, l, c)], "source:\n{src}");
}

#[test]
fn nc110_pgcfil_example_fits_its_axcfil() {
    assert_eq!(pg(PG_NC110, &axcfil(AX_NC110)), []);
}

#[test]
fn nc110_pgcfil_against_the_full_axcfil_example_breaks_124() {
    // The manual's full AXCFIL example (003:3900-3963) gives process 2 the interpolator 3 with X
    // and Z, while its PGCFIL example treats process 2 as a one-axis process (`NPD=Z, Z`): against
    // each other they break rule 124 (the same axis twice in NPD).
    let ax = axcfil(include_str!("../fixtures/FX-46.txt"));
    expect(pg(PG_NC110, &ax), 124, PG_NC110, "NPD=Z, ^Z", 0);
}

#[test]
fn pgcfil_process_numbers_against_nbp() {
    let ax = axcfil(AX_NC110);
    let src = PG_NC110.replacen("PRO=2\nASS", "PRO=3\nASS", 1);
    // PRO=3 is above NBP=2 (184) and process 2 then has no section-4 block (951).
    let (l, c) = at(&src, "PRO=^3", 0);
    let (l4, c4) = at(&src, "*4", 0);
    assert_eq!(pg(&src, &ax), [(184, l, c), (951, l4, c4)]);
    let src = PG_NC110.replace("PRO=2\nNIP=3\nTOF=6\nNAM=Z\nNPD=Z, Z\n", "");
    let (l5, c5) = at(&src, "*5", 0);
    assert_eq!(pg(&src, &ax), [(118, l5, c5)]);
}

#[test]
fn pgcfil_114_116_117_nip_nam_npd() {
    let ax = axcfil(AX_NC110);
    let src = PG_NC110.replace("NIP=3", "NIP=2");
    expect(pg(&src, &ax), 114, &src, "NIP=^2", 0);
    let src = PG_NC110.replace("NPD=Z, X", "NPD=Z, Y");
    expect(pg(&src, &ax), 116, &src, "NPD=Z, ^Y", 0);
    let src = PG_NC110.replacen("NAM=Z", "NAM=S", 1);
    expect(pg(&src, &ax), 117, &src, "NAM=^S", 0);
}

#[test]
fn pgcfil_131_nip_on_a_ptp_interpolator() {
    let ax = axcfil(include_str!("../fixtures/FX-46.txt"));
    let src = PG_NC110
        .replace("NIP=1", "NIP=2")
        .replace("NPD=Z, Z", "NPD=Z, X");
    expect(pg(&src, &ax), 131, &src, "NIP=^2", 0);
}

#[test]
fn pgcfil_146_148_tga_and_132_mas_and_ecdf_cax() {
    let ax = axcfil(AX_NC110);
    let src = PG_NC110.replace("NPD=Z, X\n", "NPD=Z, X\nTGA=B,0\n");
    expect(pg(&src, &ax), 146, &src, "TGA=^B", 0);
    let src = PG_NC110.replace("NPD=Z, X\n", "NPD=Z, X\nTGA=X,0\n");
    expect(pg(&src, &ax), 148, &src, "TGA=^X", 0);
    let src = PG_NC110.replace("MAS=XZ", "MAS=XZY");
    expect(pg(&src, &ax), 132, &src, "MAS=XZ^Y", 0);
    let src = PG_NC110.replace("NPD=Z, X\n", "NPD=Z, X\nCAX=X,Z,Y\n");
    expect(pg(&src, &ax), 132, &src, "CAX=X,Z,^Y", 0);
    let mut no_ecdf = axcfil(AX_NC110);
    no_ecdf.extension.ecdf = false;
    let src = PG_NC110.replace("NPD=Z, X\n", "NPD=Z, X\nCAX=X,Z,X\n");
    expect(pg(&src, &no_ecdf), 6, &src, "CAX", 0);
}

const IO_BASE: &str = "*1\nIN0=0,1,,,,,,\nOU0=4,5,,,,,,\nCLO=10,2\n*2\nPRO=1\nM03=45,00,21\nPRO=2\nM03=45,00,21\n*3\nPRO=1\nASM=S\nPRO=2\nCWD=0001\n*4\n";

#[test]
fn iocfil_base_fits() {
    assert_eq!(io(IO_BASE, &axcfil(AX_NC110)), []);
}

#[test]
fn iocfil_964_process_without_blocks() {
    let ax = axcfil(AX_NC110);
    let src = IO_BASE.replace("PRO=2\nM03=45,00,21\n", "");
    let (l, c) = at(&src, "*2", 0);
    let got: Vec<(u32, u32, u32)> = io(&src, &ax);
    assert_eq!(got, [(964, l, c)]);
}

#[test]
fn iocfil_clo_against_tim_104_105_106() {
    let tim2 = axcfil(
        &AX_NC110
            .replace("TIM=1,0,0,0,0", "TIM=4,0,0,0,0")
            .replace("IN1=1,XZ,S,1,16", "IN1=1,XZ,S,4,16")
            .replace("IN3=1,Z,,1,16", "IN3=1,Z,,4,16")
            .replace("CAS=1,XZS,1", "CAS=1,XZS,4")
            .replace("CAS=1,Z,1", "CAS=1,Z,4"),
    );
    let src = IO_BASE.replace("CLO=10,2", "CLO=10,5");
    expect(io(&src, &tim2), 105, &src, "CLO=^10", 0);
    let src = IO_BASE.replace("CLO=10,2", "CLO=12,2");
    expect(io(&src, &tim2), 106, &src, "CLO=12,^2", 0);
    let mut zero = axcfil(AX_NC110);
    zero.tim = 0;
    expect(io(IO_BASE, &zero), 104, IO_BASE, "CLO", 0);
}

#[test]
fn iocfil_process_and_axes_184_117_118_127_131() {
    let ax = axcfil(AX_NC110);
    let src = IO_BASE.replace("*3\nPRO=1\n", "PRO=3\nM03=45,00,21\n*3\nPRO=1\n");
    expect(io(&src, &ax), 184, &src, "PRO=^3", 0);
    let src = IO_BASE.replace("ASM=S", "ASM=Q");
    expect(io(&src, &ax), 117, &src, "ASM=^Q", 0);
    let src = IO_BASE.replace("ASM=S", "ASM=X");
    expect(io(&src, &ax), 118, &src, "ASM=^X", 0);
    let src = IO_BASE.replace("ASM=S", "ASM=S\nTA1=X,01,0,36,,");
    expect(io(&src, &ax), 127, &src, "TA1=^X", 0);
    let fx = axcfil(include_str!("../fixtures/FX-46.txt"));
    let src = IO_BASE.replace("ASM=S", "ASM=S\nTA1=T,01,0,32,,");
    expect(io(&src, &fx), 131, &src, "0,^32", 0);
    let src = IO_BASE.replace("ASM=S", "ASM=S\nTA1=T,01,40,36,,");
    expect(io(&src, &fx), 961, &src, "01,^40", 0);
    let src = IO_BASE.replace("ASM=S", "ASM=S\nTA1=T,01,0,36,,\nUCDA=TQ\nADV=0,R");
    let (l1, c1) = at(&src, "UCDA=T^Q", 0);
    let (l2, c2) = at(&src, "ADV=0,^R", 0);
    assert_eq!(io(&src, &fx), [(117, l1, c1), (117, l2, c2)]);
}
