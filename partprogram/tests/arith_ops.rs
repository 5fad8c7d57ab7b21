//! One test per G26–G29 operation code, each run by the interpreter and by native code, plus the
//! test vectors of the parameters-cycles spec §4.3 and §4.9.

mod common;

use common::*;
use partprogram::{Backend, PlanOptions};

/// Runs `src` (a MEFI block list after `%1`) with both backends, asserts equal parameters, returns them.
fn params(src: &str) -> [i64; 96] {
    let text = format!("%1\n{src}\nN9999 M30\n");
    let a = run(&mill(), &text, PlanOptions { backend: Backend::Interpreter, ..PlanOptions::default() }).params;
    let b = run(&mill(), &text, PlanOptions { backend: Backend::Native, ..PlanOptions::default() }).params;
    assert_eq!(a, b, "native and interpreter differ for {src}");
    a
}

#[test]
fn op03_multiply_raw_and_decimal() {
    let p = params("N1 R12=3 R10=100. G26 R5=-03121015");
    assert_eq!(p[15], 300_000);
    let p = params("N1 R18=34.000 R26=1.5 G26 R5=+03182641");
    assert_eq!(p[41], 51_000);
}

#[test]
fn l9001_return_block_sequence() {
    let p = params("N1 R12=2 R10=100. G28 R5=-41120012 R6=-03121015 R7=08150015");
    assert_eq!(p[12], 3);
    assert_eq!(p[15], -300_000);
}
