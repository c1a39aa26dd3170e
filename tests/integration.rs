//! The integration tests, as one test binary: each file of `tests/` is a module here (run one
//! with `cargo test --release --test integration sppm::`). One binary links once and runs its
//! tests side by side. `cancel` and `time_budget` time renders and stay binaries of their own.

mod common;

mod alpha;
mod bsdf_chi2;
mod bsdf_furnace;
mod bvh_robust;
mod command;
mod compositing;
mod emission_consistency;
mod extremes;
mod fuzz_regressions;
mod glass_transparency;
mod kdtree_props;
mod lightgroups;
mod lights;
mod media;
mod media_reference;
mod photon_map_file;
mod photon_power;
mod photon_terms;
mod pppm;
mod reference_mitsuba;
mod render_invariants;
mod sensitivity;
mod sppm;
mod subsurface;
mod subsurface_reference;
