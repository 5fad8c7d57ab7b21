//! IOCFIL, the logic characterization file (manual chapter 6).
//!
//! [`parse`] decodes a file read by [`crate::reader::read`] into the typed [`Iocfil`] and reports
//! every rule that needs no other file; [`check_against`] applies the rules that need AXCFIL
//! (CLO against TIM, process numbers against NBP, axis names and kinds, TAx positions against
//! PAS). Error numbers are those of Table 7.4 (and Table 7.1 for syntax); rules the manual states
//! without a number use the project numbers listed in `characterization/ERRORS.md`.

mod check;
mod equipment;
mod model;
mod parse;

pub use check::check_against;
pub use model::*;
pub use parse::{INPUT_CONNECTORS, OUTPUT_CONNECTORS, parse};
