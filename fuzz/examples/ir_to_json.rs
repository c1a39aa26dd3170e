//! Prints the scene IR JSON that an `ir_builder` input generates, to store it under
//! `tests/data/fuzz/` for `tests/fuzz_regressions.rs`:
//!
//! ```sh
//! cargo run --manifest-path fuzz/Cargo.toml --example ir_to_json -- fuzz/artifacts/ir_builder/crash-...
//! ```

use arbitrary::{Arbitrary, Unstructured};
use photonmap::io::scene_json;
use photonmap_fuzz::FuzzScene;

fn main() {
    let path = std::env::args().nth(1).expect("usage: ir_to_json INPUT");
    let bytes = std::fs::read(&path).expect("readable input");
    let scene = FuzzScene::arbitrary_take_rest(Unstructured::new(&bytes)).expect("an input");
    println!("{}", scene_json::to_string(&scene.desc()));
}
