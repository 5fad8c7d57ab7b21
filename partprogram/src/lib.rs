//! Partprograms: MEFI CNC8x6 and Fanuc/HAAS dialects, parameter macros compiled with cranelift, canonical block plans.
