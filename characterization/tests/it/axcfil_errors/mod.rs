//! One test per diagnostic number an AXCFIL can trigger (Table 7.1, Table 7.2 and the project's
//! 917–944): a minimal edit of a valid file, the exact set of codes it yields, and the line and
//! column of the diagnostic under test.

use characterization::axcfil::{self, FileRef};
use characterization::reader::read;

/// A valid one-process lathe: X (diameter), Z, spindle S with encoder.
const BASE: &str = "\
*1
NBP=1,ECDF
TIM=1,0,0,0,0
PRO=1
IN1=1,XZ,S,2,16
CAS=1,XZS,2
*2
PRO=1
NAS=X
TPA=41,
NTC=1,1
RAP=10000,800
GAS=0.004,0.002,,
PAS=5000,5,,
POS=.005,2
SRV=.5,2,10
MAN=2000,200
GM0=10000,7.5,20,,
NAS=Z
TPA=1,
NTC=2,2
RAP=12000,800
GAS=0.006,0.002,,
PAS=5000,10,,
POS=.005,2
SRV=.5,2,10
MAN=2000,200
GM0=12000,7.5,20,,
NAS=S
TPA=820,
NTC=3,3
PAS=4096,1,,
GAS=,,,
POS=0.05,
SRV=,,
GM1=3000,8.5,6,,
TSM=4,17
POM=0.5,100,0.1,U230K1
*3
";

/// A slave parallel axis Q of master X, appended to BASE.
const SLAVE: &str = "NAS=Q\nTPA=1001,\nNTC=4,4\nGAS=,,,\nPAS=5000,-5,,\nMCZ=I0A8,0,200\nMFC=I0A9,I0A10\nSKW=X,1,0,0\n";

/// Applies `(find, replace)` edits in order, each to the first occurrence; panics if absent.
fn edit(base: &str, edits: &[(&str, &str)]) -> String {
    let mut s = base.to_string();
    for (find, replace) in edits {
        assert!(s.contains(find), "`{find}` not in\n{s}");
        s = s.replacen(find, replace, 1);
    }
    s
}

/// All diagnostics of reading and validating `src` as (code, line, column).
fn diags(src: &str) -> Vec<(u32, u32, u32)> {
    let (f, mut d) = read("AXCFIL", src.as_bytes());
    d.extend(axcfil::validate(&f).1);
    for x in &d {
        assert!(
            !x.hint.is_empty() && !x.message.is_empty(),
            "diagnostic without message or hint: {x:?}"
        );
        assert_eq!(x.file, "AXCFIL");
    }
    d.iter().map(|d| (d.code, d.line, d.column)).collect()
}

/// 1-based line and column of `needle` in `src` (nth occurrence, 0-based); a `^` in the needle
/// marks the position, otherwise its first character. An empty needle means the end of the text.
fn at(src: &str, needle: &str, nth: usize) -> (u32, u32) {
    if needle.is_empty() {
        return diag::line_column(src, src.len());
    }
    let offset = needle.find('^').unwrap_or(0);
    let plain = needle.replace('^', "");
    let start = src
        .match_indices(&plain)
        .nth(nth)
        .map(|(i, _)| i)
        .unwrap_or_else(|| panic!("`{plain}` #{nth} not in\n{src}"));
    diag::line_column(src, start + offset)
}

/// Checks that `code` is reported exactly at `needles`, and that the set of codes is `codes`.
fn check(src: &str, code: u32, needles: &[(&str, usize)], codes: &[u32]) {
    let d = diags(src);
    let got: Vec<(u32, u32)> = d
        .iter()
        .filter(|x| x.0 == code)
        .map(|x| (x.1, x.2))
        .collect();
    let want: Vec<(u32, u32)> = needles.iter().map(|(n, k)| at(src, n, *k)).collect();
    assert_eq!(got, want, "positions of {code} in {d:?}\n{src}");
    let mut set: Vec<u32> = d.iter().map(|x| x.0).collect();
    set.sort_unstable();
    set.dedup();
    let mut expected = codes.to_vec();
    expected.push(code);
    expected.sort_unstable();
    expected.dedup();
    assert_eq!(set, expected, "codes of {d:?}\n{src}");
}

macro_rules! case {
    ($name:ident, $base:expr, [$(($f:expr, $r:expr)),* $(,)?], $code:expr, [$(($n:expr, $k:expr)),* $(,)?], [$($o:expr),*]) => {
        #[test]
        fn $name() {
            let src = edit($base, &[$(($f, $r)),*]);
            check(&src, $code, &[$(($n, $k)),*], &[$($o),*]);
        }
    };
}

#[test]
fn base_files_are_valid() {
    assert_eq!(diags(BASE), []);
    assert_eq!(diags(&slave()), []);
}

fn slave() -> String {
    edit(
        BASE,
        &[
            ("CAS=1,XZS,2", "CAS=1,XZSQ,2"),
            ("*3\n", &format!("{SLAVE}*3\n")),
        ],
    )
}

mod project;
mod table_7_1;
mod table_7_2;
