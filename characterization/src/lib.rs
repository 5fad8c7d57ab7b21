//! Reads and validates the NC-xxx characterization files FCRSYS, AXCFIL, PGCFIL and IOCFIL.

pub mod pgcfil;
pub mod reader;
