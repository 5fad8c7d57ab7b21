//! Reads and validates the NC-xxx characterization files FCRSYS, AXCFIL, PGCFIL and IOCFIL.
//!
//! * [`reader`]: the common file grammar (sections, records, parameters with spans, comments,
//!   CP866/CP1251 bytes) and the Table 7.1 grammar errors.
//! * [`values`]: typed parameter parsers (integer, word, real, hexadecimal, boolean, ASCII string,
//!   PLC variable) and [`values::Ctx`], which builds located diagnostics.
//! * [`fcrsys`]: the system file and the resolution of logical names into the machine directory.
//! * [`axcfil`]: the axis file, its typed model and the rules of the manual's Table 7.2.
//! * [`pgcfil`], [`iocfil`]: the process and logic files (chapters 5 and 6), project codes 950–999.
//! * [`machine`]: [`load_machine`] reads a whole machine directory in one run.
//! * [`messages`]: the PLC message files (FCRSYS FILMS5, PGCFIL FLC).
//! * [`codes`]: every diagnostic number used, with the project's own 900–949 range documented
//!   (PGCFIL/IOCFIL use 950–999).
//!
//! Broken input never panics: every function returns its result together with diagnostics.
//! `ERRORS.md` in the crate directory lists every chapter-7 number with the test that produces it.

pub mod axcfil;
pub mod codes;
pub mod decode;
pub mod fcrsys;
pub mod iocfil;
pub mod machine;
pub mod messages;
pub mod pgcfil;
pub mod reader;
pub mod values;

pub use machine::{Machine, MachineLoad, MachinePaths, load_machine, load_machine_capped};
