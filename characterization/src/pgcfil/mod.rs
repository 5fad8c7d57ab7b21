//! PGCFIL, the technological-process characterization file (manual chapter 5).
//!
//! [`parse`] decodes a file read with [`crate::reader::read_with`] and `Grammar::PGCFIL` (so the
//! `NEW`/`OLD` header is kept) into the typed [`Pgcfil`] and reports
//! every rule that needs no other file; [`check_against`] applies the rules that need AXCFIL
//! (process numbers against NBP, interpolator and axis names, axis kinds, ECDF-only
//! instructions). Error numbers are those of Table 7.3 (and Table 7.1 for syntax); rules the manual
//! states without a number use the project numbers listed in `characterization/ERRORS.md`.
//!
//! Project codes raised for PGCFIL:
//!
//! | code | rule |
//! |---|---|
//! | 950 | NIP is not the first instruction after PRO in section 5 |
//! | 951 | a process of AXCFIL NBP has no block in the mandatory section 4 |
//! | 952 | JCL old name not in Table 5.6, or new name neither three capital letters nor `D` |
//! | 953 | warning: JCL synchronization code given (it cannot be changed) |
//! | 954 | NPL label_num above 255 |
//! | 955 | FLC parameter not `name/MPx` |
//! | 956 | CWP offset not 0 or 1 |
//! | 957 | G70 not 0 or 1 |
//! | 958 | MBR outside 1…255 |
//! | 959 | TAS measuring input equals the probe safety input |
//! | 960 | FRO/SSO/FMO: the last two positions differ |

pub(crate) mod axes;
mod check;
pub(crate) mod fields;
pub(crate) mod locate;
mod model;
mod parse;
mod sections56;
pub(crate) mod structure;
pub mod tables;

pub use check::{check_against, check_against_into};
pub use model::*;
pub use parse::{parse, parse_into};
