//! Structured scenes (meshes, instances, materials, textures, lights, environment, media,
//! camera) with NaN, infinite, huge, tiny and negative values: validate, build and render
//! 8x8. Invalid scenes must be rejected by `validate` with an error, never a panic; scenes it
//! accepts must build and render with every AOV pixel finite and >= 0.
#![no_main]

use libfuzzer_sys::fuzz_target;
use photonmap::scene::validate;
use photonmap_fuzz::FuzzScene;

fuzz_target!(|input: FuzzScene| {
    let desc = input.desc();
    if validate(&desc).is_ok() {
        photonmap_fuzz::tiny_render(&desc);
    }
});
