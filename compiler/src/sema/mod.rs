//! Semantic analysis: names, signals against the machine, types, stateful elements, warnings.

pub mod codes;
