//! The keys of photon maps and of renders.
//!
//! **The key.** A set is keyed by a hash (64-bit FNV-1a, [`keys`]) of the geometry (meshes,
//! instances), materials and textures, lights and environment (and light groups), media, the photon settings
//! (counts, gather, radius, final gathering and cache, bounces, power encoding, mode, terms,
//! specular depth), the seed and the version of the renderer and of the file format. Not the
//! camera nor the film. Each part's own hash is stored too, so that a mismatch says what
//! differs. Using a set under another key is an error (`map_file::check_key`), never a silently wrong
//! image; `photon_maps_mismatch rebuild` builds the maps again instead.
//!
//! The render key (pppm's partial sums merge only under the same one) adds the view and every
//! setting that changes the image.

use super::settings::RenderSettings;
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
            h.u64(super::map_file::MAP_FILE.version as u64);
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
        photon_settings: part(&|h| {
            json(h, &s.photons);
            json(h, &(s.mode, s.terms, s.max_specular_depth));
        }),
        seed: part(&|h| h.u64(s.seed)),
    }
}

/// The settings that do not change the image, left out of the render key: the threads, the
/// memory limit, where photon maps are saved or loaded, and which block of pppm passes a
/// process renders (blocks of one render differ in it, and merge).
pub const NOT_IN_IMAGE: [&str; 4] = ["threads", "memory_limit", "photon_map_files", "pass_range"];

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
    json(&mut r, &image_settings(s));
    super::RenderKeys {
        maps,
        view,
        render: r.finish(),
    }
}

/// The settings as JSON without [`NOT_IN_IMAGE`].
fn image_settings(s: &RenderSettings) -> serde_json::Value {
    let mut v = serde_json::to_value(s).unwrap_or_else(|e| unreachable!("settings serialise: {e}"));
    if let Some(map) = v.as_object_mut() {
        for k in NOT_IN_IMAGE {
            map.remove(k);
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every setting that changes the image changes the render key; the threads, the memory
    /// limit, the map files and the block of passes do not.
    #[test]
    fn the_render_key_covers_every_setting_that_changes_the_image() {
        let desc = crate::scene::default_scene();
        let base = RenderSettings::default();
        let key = |s: &RenderSettings| keys(&desc, s).render;
        let k0 = key(&base);
        let all = serde_json::to_value(&base).unwrap();
        for k in NOT_IN_IMAGE {
            assert!(all.get(k).is_some(), "{k} is a setting");
        }
        let changed: Vec<(&str, RenderSettings)> = vec![
            (
                "spp",
                RenderSettings {
                    spp: 9,
                    ..base.clone()
                },
            ),
            (
                "noise_threshold",
                RenderSettings {
                    noise_threshold: 0.3,
                    ..base.clone()
                },
            ),
            (
                "initial_photons",
                RenderSettings {
                    initial_photons: 7,
                    ..base.clone()
                },
            ),
            (
                "initial_radius",
                RenderSettings {
                    initial_radius: Some(0.1),
                    ..base.clone()
                },
            ),
            (
                "gather_rays_per_sample",
                RenderSettings {
                    gather_rays_per_sample: Some(3),
                    ..base.clone()
                },
            ),
            (
                "progressive",
                RenderSettings {
                    progressive: true,
                    ..base.clone()
                },
            ),
        ];
        for (what, s) in &changed {
            assert_ne!(key(s), k0, "{what}");
        }
        let mut photons = base.clone();
        photons.photons.volume_points = false;
        assert_ne!(key(&photons), k0, "photons.volume_points");
        let same = RenderSettings {
            threads: 3,
            memory_limit: Some(1 << 30),
            pass_range: Some((2, 5)),
            ..base.clone()
        };
        assert_eq!(key(&same), k0);
    }
}
