//! Arbitrary bytes as scene JSON: parse and validate, then build and render 8x8 at 1 spp
//! with ~100 photons per map. Errors are expected; a panic is a bug, and so is a non-finite
//! or negative pixel in any AOV.
#![no_main]

use libfuzzer_sys::fuzz_target;
use photonmap::io::scene_json;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(desc) = scene_json::from_str(text) {
        photonmap_fuzz::tiny_render(&desc);
    }
});
