//! Kernel tests against a scripted PLC (FIN = strobe within the same scan, like the bundled
//! programs' S and T) and a test interpolator whose moves take one tick per millimetre.

mod bus;
mod correction;
mod exec;
pub(crate) mod fixture;
mod handwheel;
mod homing;
mod limit_switch;
mod manual;
mod mdi;
mod servo;
mod spindle;
mod zones;
