//! The compositing AOVs beside the terms (`aov::AovRequest::aovs`): what one camera sample
//! records for them, how a pixel accumulates its samples, and how it resolves into the film.
//!
//! - **Denoising guides** (`albedo`, `normal`): at the first non-specular surface an eye
//!   path reaches, followed through perfect mirrors and glass (Open Image Denoise's guides,
//!   as Cycles writes its `Denoising Albedo` and `Denoising Normal`): the surface's
//!   directional albedo times the tint of the specular bounces before it, and its shading
//!   normal facing the camera, in camera space. Paths that escape add zeros. Each is the mean
//!   over the pixel's samples, like the terms.
//! - **Cryptomatte** (`render::cryptomatte`): the object and the material of the first
//!   surface a camera ray hits, ranked per pixel by coverage.
//! - **Noisy terms** (`<term>_noisy`): the terms as rendered, kept when the terms are denoised.
//!
//! Nothing is recorded or allocated for an AOV that was not asked for.

use super::aov::{
    AovKind, AovSpec, Term, CRYPTO_MATERIAL, CRYPTO_OBJECT, LIGHTGROUP_PREFIX, NOISY_SUFFIX,
};
use super::cryptomatte::{self, Coverage};
use super::film::AovImage;
use super::film::TermRadiance;
use super::settings::RenderSettings;
use crate::math::Spectrum;
use crate::scene::Scene;
use glam::{Mat3, Vec3};
use std::collections::BTreeMap;

/// The denoising guides of one camera sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Guides {
    pub albedo: Spectrum,
    /// World space, facing the camera.
    pub normal: Vec3,
}

/// What one camera sample records for the compositing AOVs (reset before each sample).
#[derive(Clone, Debug, Default)]
pub struct SampleAovs {
    /// Record the guides and the first hit at all (the integrator skips the work otherwise).
    pub want_guides: bool,
    pub want_first_hit: bool,
    /// The guides where the path reached a non-specular surface.
    pub guides: Option<Guides>,
    /// The first surface the camera ray hit: (instance of the acceleration structure,
    /// material).
    pub first_hit: Option<(u32, u32)>,
    /// With light groups, each group's share of the sample's radiance (one entry per group;
    /// empty without groups).
    pub groups: Vec<Spectrum>,
    /// How much of the sample sees a transparent background or a Holdout (always recorded;
    /// the film's alpha is one minus its mean, see `accumulate::Accumulator`).
    pub transparent: f32,
}

impl SampleAovs {
    fn clear(&mut self) {
        self.guides = None;
        self.first_hit = None;
        self.groups.iter_mut().for_each(|g| *g = Spectrum::ZERO);
        self.transparent = 0.0;
    }
}

/// A pixel's running sums of its samples' compositing AOVs: one pointer, allocated at the
/// pixel's first sample that records something.
#[derive(Clone, Debug, Default)]
pub struct PixelAovs(Option<Box<PixelSums>>);

#[derive(Clone, Debug, Default)]
struct PixelSums {
    /// Sums of albedo (0..3) and world normal (3..6).
    guides: [f32; 6],
    objects: Coverage,
    materials: Coverage,
    /// Sums of each light group's share.
    groups: Vec<Spectrum>,
}

/// The layout of a render without compositing AOVs.
pub static NO_AOVS: AovLayout = AovLayout::none();

/// One Cryptomatte type of a render: the float id of each index (instance or material), the
/// names in the manifest, and the index of its first layer among the film's AOVs.
struct CryptoType {
    type_name: &'static str,
    ids: Vec<f32>,
    names: Vec<String>,
    first_image: usize,
}

/// What the compositing AOVs of one render are, and where each goes in the film.
pub struct AovLayout {
    /// The optional AOVs of the film, in output order (the list of `AovRequest::aovs`
    /// without `error`, which the film keeps apart).
    specs: Vec<AovSpec>,
    /// World to camera space (x right, y up, z away from the camera), for the normals; set
    /// when the guides are asked for, with the index of `albedo` among the film's AOVs.
    guides: Option<(Mat3, usize)>,
    /// The index of `direct_noisy` and the following noisy terms, when kept.
    noisy: Option<usize>,
    /// The index of the first light group's image, and the number of groups (0: none).
    groups: (usize, usize),
    crypto: Vec<CryptoType>,
    levels: usize,
}

impl AovLayout {
    /// The layout of a render of `scene` with `settings`; `light_groups` are the scene's.
    pub fn new(scene: &Scene, settings: &RenderSettings, light_groups: &[String]) -> AovLayout {
        let req = &settings.aovs();
        let specs: Vec<AovSpec> = req.aovs(light_groups).into_iter().skip(1).collect();
        let index = |name: &str| specs.iter().position(|a| a.name == name);
        let guides = index(super::aov::ALBEDO_AOV).map(|i| (scene.camera.world_to_camera(), i));
        let noisy = index(&format!("{}{NOISY_SUFFIX}", Term::Direct.name()));
        let groups = match light_groups.first() {
            Some(g) => (
                index(&format!("{LIGHTGROUP_PREFIX}{g}")).unwrap_or(specs.len()),
                light_groups.len(),
            ),
            None => (0, 0),
        };
        let mut crypto = Vec::new();
        for (on, type_name, names) in [
            (
                req.cryptomatte.object(),
                CRYPTO_OBJECT,
                &scene.instance_names,
            ),
            (
                req.cryptomatte.material(),
                CRYPTO_MATERIAL,
                &scene.material_names,
            ),
        ] {
            if !on {
                continue;
            }
            let first_image = index(&format!("{type_name}00")).unwrap_or(specs.len());
            crypto.push(CryptoType {
                type_name,
                ids: names.iter().map(|n| cryptomatte::name_id(n)).collect(),
                names: names.clone(),
                first_image,
            });
        }
        AovLayout {
            specs,
            guides,
            noisy,
            groups,
            crypto,
            levels: req.crypto_layers() * 2,
        }
    }

    /// No compositing AOVs: nothing recorded, nothing allocated.
    pub const fn none() -> AovLayout {
        AovLayout {
            specs: Vec::new(),
            guides: None,
            noisy: None,
            groups: (0, 0),
            crypto: Vec::new(),
            levels: 0,
        }
    }

    /// The sample record of this layout's render.
    pub fn sample(&self) -> SampleAovs {
        SampleAovs {
            want_guides: self.guides.is_some(),
            want_first_hit: !self.crypto.is_empty(),
            groups: vec![Spectrum::ZERO; self.groups.1],
            ..SampleAovs::default()
        }
    }

    /// Adds a sample's record to its pixel's sums, and clears the record.
    pub fn add(&self, px: &mut PixelAovs, s: &mut SampleAovs) {
        if s.guides.is_none() && s.first_hit.is_none() && s.groups.is_empty() {
            return;
        }
        let px = px.0.get_or_insert_with(Default::default);
        if !s.groups.is_empty() {
            px.groups.resize(s.groups.len(), Spectrum::ZERO);
            for (sum, g) in px.groups.iter_mut().zip(&s.groups) {
                if g.is_finite() {
                    *sum += *g;
                }
            }
        }
        if let Some(g) = s.guides {
            if g.albedo.is_finite() && g.normal.is_finite() {
                for c in 0..3 {
                    px.guides[c] += g.albedo[c];
                    px.guides[3 + c] += g.normal[c];
                }
            }
        }
        if let Some((instance, material)) = s.first_hit {
            for t in &self.crypto {
                match t.type_name {
                    CRYPTO_OBJECT => px.objects.add(instance),
                    _ => px.materials.add(material),
                }
            }
        }
        s.clear();
    }

    /// The film's AOV images (without `error`), all zero.
    pub fn images(&self, width: usize, height: usize) -> Vec<AovImage> {
        self.specs
            .iter()
            .map(|spec| AovImage {
                spec: spec.clone(),
                data: vec![0.0; width * height * spec.channels().len()],
            })
            .collect()
    }

    /// Writes pixel `i`'s AOVs after `samples` samples; `terms` is its resolved terms, and
    /// `extra_groups` adds to its light groups' means what the integrator keeps apart (the
    /// progressive mode's photon flux).
    pub fn resolve(
        &self,
        px: &PixelAovs,
        samples: u32,
        terms: &TermRadiance,
        images: &mut [AovImage],
        i: usize,
        extra_groups: impl FnOnce(&mut [Spectrum]),
    ) {
        let (first_group, n_groups) = self.groups;
        if n_groups > 0 {
            let inv = 1.0 / samples.max(1) as f32;
            let mut g: Vec<Spectrum> = match px.0.as_deref() {
                Some(p) if !p.groups.is_empty() => p.groups.iter().map(|v| *v * inv).collect(),
                _ => vec![Spectrum::ZERO; n_groups],
            };
            extra_groups(&mut g);
            for (k, v) in g.iter().enumerate() {
                images[first_group + k].data[3 * i..3 * i + 3].copy_from_slice(&v.to_array());
            }
        }
        if let Some(k) = self.noisy {
            for (j, t) in super::aov::DENOISED_TERMS.iter().enumerate() {
                let v = terms.0[t.index()].to_array();
                images[k + j].data[3 * i..3 * i + 3].copy_from_slice(&v);
            }
        }
        let Some(px) = px.0.as_deref() else {
            return;
        };
        let inv = 1.0 / samples.max(1) as f32;
        if let Some((to_camera, k)) = self.guides {
            let a = &px.guides;
            images[k].data[3 * i..3 * i + 3].copy_from_slice(&[a[0] * inv, a[1] * inv, a[2] * inv]);
            let n = to_camera * (Vec3::new(a[3], a[4], a[5]) * inv);
            images[k + 1].data[3 * i..3 * i + 3].copy_from_slice(&n.to_array());
        }
        for t in &self.crypto {
            let cov = match t.type_name {
                CRYPTO_OBJECT => &px.objects,
                _ => &px.materials,
            };
            let ranks = cov.ranked(&t.ids, samples, self.levels);
            for (r, pair) in ranks.chunks(2).enumerate() {
                let img = &mut images[t.first_image + r];
                let dst = &mut img.data[4 * i..4 * i + 4];
                dst[0] = pair[0].0;
                dst[1] = pair[0].1;
                if let Some(p) = pair.get(1) {
                    dst[2] = p.0;
                    dst[3] = p.1;
                }
            }
        }
    }

    /// Bytes the compositing AOVs of a `width` x `height` render take: the film's images and
    /// each pixel's sums (the Cryptomatte coverage lists counted at `levels` entries).
    pub fn memory_bytes(&self, width: usize, height: usize) -> u64 {
        if self.specs.is_empty() {
            return 0;
        }
        let channels: usize = self.specs.iter().map(|s| s.channels().len()).sum();
        let sums = std::mem::size_of::<PixelSums>()
            + self.crypto.len() * self.levels * 8
            + self.groups.1 * std::mem::size_of::<Spectrum>();
        ((width * height) * (channels * 4 + sums)) as u64
    }

    /// Each Cryptomatte type's manifest: type name -> the names of its ids.
    pub fn manifests(&self) -> BTreeMap<String, Vec<String>> {
        self.crypto
            .iter()
            .map(|t| {
                let mut names = t.names.clone();
                names.sort();
                names.dedup();
                (t.type_name.to_string(), names)
            })
            .collect()
    }
}

/// The EXR header attributes of a film's Cryptomatte types, each layer named
/// `<prefix><type>` (Blender puts the view layer's name and a dot before it).
pub fn cryptomatte_header(
    manifests: &BTreeMap<String, Vec<String>>,
    prefix: &str,
) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for (type_name, names) in manifests {
        out.extend(cryptomatte::header(&format!("{prefix}{type_name}"), names));
    }
    out
}

/// An AOV kind's channel count.
pub fn channel_count(kind: AovKind) -> usize {
    kind.channels().len()
}

/// An error when a render made of separate pieces (`what`: pppm's blocks of passes, Jensen's
/// tiles) is asked for compositing AOVs, which those pieces do not carry; it names the
/// setting (or the scene's light groups).
pub fn require_none(scene: &Scene, s: &RenderSettings, what: &str) -> crate::error::Result<()> {
    let asked = if s.aovs().denoise {
        Some("denoise")
    } else if s.aovs().denoising_data {
        Some("denoising_data")
    } else if s.aovs().cryptomatte != super::aov::Cryptomatte::Off {
        Some("cryptomatte")
    } else if !scene.light_groups.is_empty() {
        Some("lightgroups")
    } else {
        None
    };
    match asked {
        Some(setting) => Err(crate::error::Error::InvalidSetting {
            setting: setting.into(),
            message: format!(
                "{what} carry no compositing AOVs (denoising data, Cryptomatte, light groups): \
                 render the frame whole in the jensen or sppm mode"
            ),
        }),
        None => Ok(()),
    }
}
