//! Procedural textures, as Cycles evaluates them.
