//! Reads and validates the NC-xxx characterization files FCRSYS, AXCFIL, PGCFIL and IOCFIL.
