//! Converter nodes, as Cycles evaluates them.
