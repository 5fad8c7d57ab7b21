//! Kernel tests against a scripted PLC (FIN = strobe within the same scan, like the bundled
//! programs' S and T) and a test interpolator whose moves take one tick per millimetre.

mod exec;
mod fixture;
mod handwheel;
mod homing;
mod manual;
mod zones;
