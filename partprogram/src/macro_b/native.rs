//! Native code for Macro B (filled below).
