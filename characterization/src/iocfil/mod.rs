//! IOCFIL, the logic characterization file (manual chapter 6).
//!
//! [`parse`] decodes a file read by [`crate::reader::read`] into the typed [`Iocfil`] and reports
//! every rule that needs no other file; [`check_against`] applies the rules that need AXCFIL
//! (CLO against TIM, process numbers against NBP, axis names and kinds, TAx positions against
//! PAS). Error numbers are those of Table 7.4 (and Table 7.1 for syntax); rules the manual states
//! without a number use the project numbers listed in `characterization/ERRORS.md`.
//!
//! Project codes raised for IOCFIL:
//!
//! | code | rule |
//! |---|---|
//! | 961 | TAx phase offset not less than the mechanical step of PAS |
//! | 962 | Mxx with m_request 10 or 20 lacks the calculation-block bit 04 |
//! | 963 | warning: UCDA lists 4 axes (chapter 6.3.5 allows 3) |
//! | 964 | warning: a process of NBP has no block in section 2 or 3 |

mod check;
mod equipment;
mod model;
mod parse;

pub use check::{check_against, check_against_into};
pub use model::*;
pub use parse::{INPUT_CONNECTORS, OUTPUT_CONNECTORS, parse, parse_into};
