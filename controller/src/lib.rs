//! The ncplc controller, assembled in one place: [`Controller::builder`] takes a machine directory
//! and typed steps (engine, I/O, CNC part, recording, servers, clock), [`Builder::build`] validates
//! every choice first and reports every error at once, then opens, compiles and wires; the returned
//! [`Controller`] has the one run loop ([`Controller::run`] / [`Controller::step`]).
//! [`Builder::replayer`] assembles the same machine for a trace replay.
//!
//! | module | concept |
//! |---|---|
//! | [`builder`] | the builder's steps and `build()`: validation, then assembly |
//! | [`control`] | the running [`Controller`]: the order of one tick, the end of a run |
//! | [`settings`] | the typed choices a builder collects (engine, I/O, part, recording, servers, clock) |
//! | [`servers`] | the web HMI and the [`servers::Server`] extension point (an OPC UA server, …) |
//! | [`retained`] | PGCFIL OLD: restore at start, the writer thread, the final save |
//! | [`replayer`] | a trace replay assembled from the machine (with the CNC kernel for part traces) |
//! | [`machine`] | opening a machine directory: configuration, PLC source, sim script, interface map |
//! | [`drive_io`] | a part run on CiA 402 drives: the CANopen master and the kernel behind one I/O |
//! | [`io`] | the `--io` dispatch: sim, Modbus TCP, CANopen (drives on the fieldbus plug in here) |
//! | [`part_run`] | the CNC kernel behind the simulated I/O and the operator of a part run |
//! | [`part_replay`] | the part run's kernel, plant and operator driven by a replay |
//! | [`plc_messages`] | the PLC's messages: raised from the request bits, acknowledged to the logic |
//! | [`hmi_link`] | a running scheduler connected to the `hmi` server (frames, requests, render thread) |
//!
//! **Invariants:** the only loop that runs a controller is [`Controller::run`] (with
//! [`Controller::step`] for one tick); no assembly function is longer than about 80 lines; this crate
//! sits below the `ncplc` binary and never parses arguments or picks exit codes — it reports
//! through return values (and a few operational notes on stderr, as the moved code did).

pub mod builder;
pub mod control;
pub mod drive_io;
pub mod hmi_link;
pub mod io;
pub mod machine;
pub mod part_replay;
pub mod part_run;
pub mod plc_messages;
pub mod replayer;
pub mod retained;
pub mod servers;
pub mod settings;

pub use builder::{BuildError, Builder, WrapIo};
pub use control::{Controller, Ending, Observer, Quiet};
