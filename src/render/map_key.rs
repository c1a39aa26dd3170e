//! The keys of photon maps and of renders.
//!
//! **The key.** A set is keyed by a hash (64-bit FNV-1a, [`keys`]) of the geometry (meshes,
//! instances), materials and textures, lights and environment (and light groups), media, the
//! settings (every one but those of [`NOT_IN_IMAGE`] and [`NOT_IN_MAPS`]), the seed and the version of the renderer and of the file format. Not the
//! camera nor the film. Each part's own hash is stored too, so that a mismatch says what
//! differs. Using a set under another key is an error (`map_file::check_key`), never a silently wrong
//! image; `photon_maps_mismatch rebuild` builds the maps again instead.
//!
//! The render key (pppm's partial sums merge only under the same one) adds the view and every
//! setting that changes the image.

use super::settings::RenderSettings;

/// The version of the photon-map file format (`map_file::MAP_FILE`): in the key, so that a
/// file of another format is never read as this one.
pub const MAP_FILE_VERSION: u32 = 3;
use crate::io::container::Fnv64;
use crate::scene::SceneDesc;
use serde::Serialize;

/// The parts of a photon-map key, each hashed on its own (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KeyParts {
    pub version: u64,
    pub geometry: u64,
    pub materials: u64,
    pub lights: u64,
    pub media: u64,
    pub photon_settings: u64,
    pub seed: u64,
}

impl KeyParts {
    const NAMES: [&'static str; 7] = [
        "renderer version",
        "geometry",
        "materials",
        "lights",
        "media",
        "photon settings",
        "seed",
    ];

    pub(super) fn array(&self) -> [u64; 7] {
        [
            self.version,
            self.geometry,
            self.materials,
            self.lights,
            self.media,
            self.photon_settings,
            self.seed,
        ]
    }

    /// The key: a hash of the parts.
    pub fn key(&self) -> u64 {
        let mut h = Fnv64::default();
        for v in self.array() {
            h.u64(v);
        }
        h.finish()
    }

    /// The names of the parts that differ from `other`'s.
    pub fn differences(&self, other: &KeyParts) -> Vec<&'static str> {
        Self::NAMES
            .iter()
            .zip(self.array().iter().zip(other.array()))
            .filter(|(_, (a, b))| **a != *b)
            .map(|(n, _)| *n)
            .collect()
    }
}

/// Hashes `v` as JSON into `h`, then a separator.
fn json(h: &mut Fnv64, v: &impl Serialize) {
    // Writing into the hasher cannot fail; a value serde cannot write hashes what it wrote.
    let _ = serde_json::to_writer(&mut *h, v);
    h.write(b"\x1e");
}

fn floats<const N: usize>(h: &mut Fnv64, v: &[[f32; N]]) {
    h.u64(v.len() as u64);
    for a in v {
        for x in a {
            h.write(&x.to_le_bytes());
        }
    }
}

/// The parts of the photon-map key of `desc` rendered with `s`.
pub fn key_parts(desc: &SceneDesc, s: &RenderSettings) -> KeyParts {
    let part = |f: &dyn Fn(&mut Fnv64)| {
        let mut h = Fnv64::default();
        f(&mut h);
        h.finish()
    };
    KeyParts {
        version: part(&|h| {
            h.write(env!("CARGO_PKG_VERSION").as_bytes());
            h.u64(MAP_FILE_VERSION as u64);
        }),
        geometry: part(&|h| {
            h.u64(desc.meshes.len() as u64);
            for m in &desc.meshes {
                json(h, &(&m.name, m.material, &m.transform, m.interior_medium));
                floats(h, &m.positions);
                h.u64(m.indices.len() as u64);
                for t in &m.indices {
                    for i in t {
                        h.write(&i.to_le_bytes());
                    }
                }
                match &m.normals {
                    Some(n) => floats(h, n),
                    None => h.write(b"-"),
                }
                match &m.uvs {
                    Some(u) => floats(h, u),
                    None => h.write(b"-"),
                }
                match &m.material_indices {
                    Some(ids) => {
                        h.u64(ids.len() as u64);
                        for i in ids {
                            h.write(&i.to_le_bytes());
                        }
                    }
                    None => h.write(b"-"),
                }
            }
            json(h, &desc.instances);
        }),
        materials: part(&|h| {
            json(h, &desc.materials);
            h.u64(desc.textures.len() as u64);
            for t in &desc.textures {
                json(
                    h,
                    &(&t.name, t.width, t.height, t.channels, &t.wrap, &t.encoding),
                );
                h.u64(t.data.len() as u64);
                for x in &t.data {
                    h.write(&x.to_le_bytes());
                }
            }
        }),
        lights: part(&|h| {
            json(h, &desc.lights);
            json(h, &desc.environment);
            // Photons carry their light's group.
            json(h, &desc.lightgroups);
        }),
        media: part(&|h| {
            json(h, &desc.media);
            json(h, &desc.world_medium);
        }),
        photon_settings: part(&|h| json(h, &without(s, &[&NOT_IN_IMAGE, &NOT_IN_MAPS, &["seed"]]))),
        seed: part(&|h| h.u64(s.seed)),
    }
}

/// The settings that do not change the image, left out of the render key: the threads, the
/// memory limit, where photon maps are saved or loaded, which block of pppm passes a process
/// renders (blocks of one render differ in it, and merge), and the quality preset's name (its
/// values are the fields it set).
pub const NOT_IN_IMAGE: [&str; 7] = [
    "quality",
    "threads",
    "memory_limit",
    "save_photon_maps",
    "load_photon_maps",
    "photon_maps_mismatch",
    "pass_range",
];

/// The settings that change the camera pass only, left out of the photon-map key besides
/// [`NOT_IN_IMAGE`] (the seed has its own part): the photon maps and the irradiance cache of
/// one scene serve views rendered with other samples, filters, AOVs, and the progressive
/// modes' radii (which never read a map file). Every other setting, a new one too, is in
/// the key: a map file is never used under settings it was not built with.
pub const NOT_IN_MAPS: [&str; 14] = [
    "spp",
    "adaptive_sampling",
    "noise_threshold",
    "max_spp",
    "filter",
    "progressive",
    "gather_rays_per_sample",
    "alpha",
    "initial_photons",
    "initial_radius",
    "denoising_data",
    "denoise",
    "cryptomatte",
    "cryptomatte_levels",
];

/// The keys of a render of `desc` with `s` (see [`super::RenderKeys`]). The render key hashes
/// every setting but [`NOT_IN_IMAGE`], as the settings serialise: a new setting is in it.
pub fn keys(desc: &SceneDesc, s: &RenderSettings) -> super::RenderKeys {
    let maps = key_parts(desc, s).key();
    let mut v = Fnv64::default();
    json(&mut v, &(&desc.camera, &desc.film));
    let view = v.finish();
    let mut r = Fnv64::default();
    r.u64(maps);
    r.u64(view);
    json(&mut r, &without(s, &[&NOT_IN_IMAGE]));
    super::RenderKeys {
        maps,
        view,
        render: r.finish(),
    }
}

/// The settings as JSON without the names in `lists`.
fn without(s: &RenderSettings, lists: &[&[&str]]) -> serde_json::Value {
    let mut v = serde_json::to_value(s).unwrap_or_else(|e| unreachable!("settings serialise: {e}"));
    if let Some(map) = v.as_object_mut() {
        for k in lists.iter().flat_map(|l| l.iter()) {
            map.remove(*k);
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::aov::{Term, TermMask};

    /// The engine's own settings (no keyword sets them) are in both keys, the block of pppm
    /// passes in neither. The schema's settings are checked one by one in
    /// `settings::tests::every_setting_round_trips_and_is_in_the_keys`.
    #[test]
    fn the_internal_settings_are_in_the_keys() {
        let desc = crate::scene::default_scene();
        let base = RenderSettings::default();
        let k0 = keys(&desc, &base);
        let changed = [
            RenderSettings {
                volume_points: false,
                ..base.clone()
            },
            RenderSettings {
                max_bounces: 3,
                ..base.clone()
            },
            RenderSettings {
                max_emitted_factor: 2,
                ..base.clone()
            },
            RenderSettings {
                terms: TermMask::NONE.with(Term::Direct),
                ..base.clone()
            },
        ];
        for s in &changed {
            let k = keys(&desc, s);
            assert!(k.render != k0.render && k.maps != k0.maps, "{s:?}");
        }
        let block = RenderSettings {
            pass_range: Some((2, 5)),
            ..base.clone()
        };
        assert_eq!(keys(&desc, &block).render, k0.render);
    }
}
