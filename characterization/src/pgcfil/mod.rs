//! PGCFIL, the technological-process characterization file (manual chapter 5).
//!
//! [`parse`] decodes a file read by [`crate::reader::read`] into the typed [`Pgcfil`] and reports
//! every rule that needs no other file; [`check_against`] applies the rules that need AXCFIL
//! (process numbers against NBP, interpolator and axis names, axis kinds, ECDF-only
//! instructions). Error numbers are those of Table 7.3 (and Table 7.1 for syntax); rules the manual
//! states without a number use the project numbers listed in `characterization/ERRORS.md`.

pub(crate) mod axes;
mod check;
pub(crate) mod fields;
pub(crate) mod locate;
mod model;
mod parse;
mod sections56;
pub(crate) mod structure;
pub mod tables;

pub use check::check_against;
pub use model::*;
pub use parse::parse;
