//! The Blender Principled BSDF / OpenPBR surface, mapped onto the lobes.

use super::bsdf::Bsdf;
use super::fresnel::{f0_from_ior, Fresnel};
use super::layer::{CoatAlbedoTable, CoatLayer, CoatedDiffuse};
use super::lobe::Lobe;
use super::subsurface::Subsurface;
use super::texture::{ColorParam, FloatParam, Texture};
use super::{coat_lobe, dielectric_lobe, reflection_lobe};
use crate::math::{Frame, Spectrum};
use crate::scene::desc::PrincipledDesc;
use glam::Vec2;

/// Largest coat reflectance at normal incidence (relative IOR about 37).
const MAX_COAT_F0: f32 = 0.9;

/// Blender Principled BSDF / OpenPBR Surface (the subset photonmap renders).
///
/// | parameter | meaning |
/// |---|---|
/// | `base_color` | colour (texturable): diffuse albedo, metal F0, glass tint |
/// | `metallic` | [0,1] (texturable): blend towards the metal |
/// | `roughness` | [0,1] perceptual (texturable); alpha = roughness^2, 0 = smooth (delta lobes) |
/// | `transmission` | [0,1]: blend of the dielectric base towards glass |
/// | `ior` | index of refraction of the dielectric base and of the glass |
/// | `specular` | OpenPBR `specular_weight` (Blender IOR Level x 2): scales the coat's F0 |
/// | `emission_color`, `emission_strength` | emitted radiance = colour x strength |
/// | `multiscatter` | reflection compensated for multiple scattering (Multiscatter GGX) |
/// | `coat_weight`, `coat_roughness`, `coat_ior`, `coat_tint` | a clear coat over it all ([`CoatLayer`]) |
/// | `subsurface` | subsurface scattering below the specular layer ([`Subsurface`]) |
///
/// Mapping onto the lobes (weights sum to one):
///
/// | lobe | weight | model |
/// |---|---|---|
/// | metal | m | GGX reflection (delta at roughness 0), Schlick Fresnel with F0 = base colour |
/// | glass | (1 - m) t | dielectric of IOR `ior`, rough or smooth, transmission tinted by base colour |
/// | specular | (1 - m)(1 - t) | GGX reflection (delta at roughness 0) with the dielectric Fresnel of IOR eta_s |
/// | base | (1 - m)(1 - t)(1 - s) | Lambert base colour x (1 - E(wo)) under the specular layer, as Cycles layers it |
/// | subsurface | (1 - m)(1 - t) s | the base's Lambert lobe of the subsurface colour, marked: a camera path walks below it, every other path reflects it |
/// | clear coat | `coat_weight` | over all of the above ([`CoatLayer`]): GGX with the dielectric Fresnel of `coat_ior` |
///
/// eta_s follows OpenPBR's specular weight: F0_s = clamp(specular x ((ior - 1)/(ior + 1))^2,
/// 0, 0.9) and eta_s = (1 + sqrt F0_s)/(1 - sqrt F0_s), so `specular` = 1 is the physical
/// interface and 0 removes the specular layer. E is its directional albedo (tabulated), so
/// the base receives exactly what it does not reflect and the two add up to at most one.
#[derive(Clone, Debug, PartialEq)]
pub struct Principled {
    pub name: String,
    pub base_color: ColorParam,
    pub metallic: FloatParam,
    pub roughness: FloatParam,
    pub transmission: f32,
    pub ior: f32,
    pub specular: f32,
    pub emission_color: ColorParam,
    pub emission_strength: f32,
    /// Reflection lobes compensated for multiple scattering (Cycles' Multiscatter GGX).
    pub multiscatter: bool,
    /// The clear coat over everything, if any (Coat Weight > 0).
    pub clearcoat: Option<CoatLayer>,
    /// Albedo table of the coat (its F0 is fixed by `ior` and `specular`).
    pub coat_table: &'static CoatAlbedoTable,
    /// The subsurface part (weight s above), if any.
    pub subsurface: Option<Subsurface>,
}

fn sane(v: f32, lo: f32, hi: f32, default: f32) -> f32 {
    if v.is_finite() {
        v.clamp(lo, hi)
    } else {
        default
    }
}

fn coat_f0(ior: f32, specular: f32) -> f32 {
    (specular * f0_from_ior(ior)).clamp(0.0, MAX_COAT_F0)
}

impl Principled {
    pub fn from_desc(d: &PrincipledDesc) -> Self {
        let ior = sane(d.ior, 1.0, 10.0, 1.5);
        let specular = sane(d.specular, 0.0, 10.0, 1.0);
        Principled {
            name: d.name.clone(),
            base_color: ColorParam::from_input(&d.base_color),
            metallic: FloatParam::from_input(&d.metallic),
            roughness: FloatParam::from_input(&d.roughness),
            transmission: sane(d.transmission, 0.0, 1.0, 0.0),
            ior,
            specular,
            emission_color: ColorParam::from_input(&d.emission_color),
            emission_strength: sane(d.emission_strength, 0.0, f32::MAX, 0.0),
            multiscatter: d.multiscatter,
            clearcoat: (d.coat_weight.is_finite() && d.coat_weight > 0.0).then(|| {
                let coat_ior = sane(d.coat_ior, 1.0, 10.0, 1.5);
                CoatLayer {
                    weight: d.coat_weight.min(1.0),
                    roughness: sane(d.coat_roughness, 0.0, 1.0, 0.03),
                    ior: coat_ior,
                    tint: Spectrum::from(d.coat_tint).clamp(Spectrum::ZERO, Spectrum::ONE),
                    table: CoatAlbedoTable::for_f0(f0_from_ior(coat_ior)),
                    multiscatter: d.multiscatter,
                }
            }),
            coat_table: CoatAlbedoTable::for_f0(coat_f0(ior, specular)),
            subsurface: d.subsurface.as_ref().and_then(|ss| {
                // The medium is one per material: a textured base colour gives its scale.
                let base = match ColorParam::from_input(&d.base_color) {
                    ColorParam::Const(c) => c,
                    ColorParam::Tex { scale, .. } => scale,
                };
                Subsurface::from_desc(ss, base, ior)
            }),
        }
    }

    /// Normal-incidence reflectance of the coat over the dielectric base.
    pub fn coat_f0(&self) -> f32 {
        coat_f0(self.ior, self.specular)
    }

    pub fn bsdf(&self, frame: Frame, uv: Vec2, textures: &[Texture]) -> Bsdf {
        let base = self.base_color.eval(uv, textures).max(Spectrum::ZERO);
        let m = sane(self.metallic.eval(uv, textures), 0.0, 1.0, 0.0);
        let r = sane(self.roughness.eval(uv, textures), 0.0, 1.0, 0.5);
        let t = self.transmission;
        let mut bsdf = Bsdf::new(frame);
        let ms = self.multiscatter;
        bsdf.add(m, reflection_lobe(r, Fresnel::Schlick { f0: base }, ms));
        bsdf.add((1.0 - m) * t, dielectric_lobe(self.ior, r, base, ms));
        let w_base = (1.0 - m) * (1.0 - t);
        if self.coat_f0() > 0.0 {
            bsdf.add(w_base, coat_lobe(r, self.coat_table, ms));
        }
        let diffuse =
            |albedo| Lobe::CoatedDiffuse(CoatedDiffuse::new(albedo, r, self.coat_table, ms));
        match self.subsurface {
            None => {
                bsdf.add(w_base, diffuse(base));
            }
            Some(ss) => {
                // The channels that do not walk stay with the diffuse base.
                let rest = base * (Spectrum::ONE - ss.weight * ss.walks);
                if rest.max_element() > 0.0 {
                    bsdf.add(w_base, diffuse(rest));
                }
                bsdf.add_subsurface(w_base * ss.weight, diffuse(ss.color));
            }
        }
        if let Some(c) = self.clearcoat {
            bsdf.coat_over(c);
            bsdf.add_coat_lobe(c.weight, coat_lobe(c.roughness, c.table, c.multiscatter));
        }
        bsdf
    }

    /// Whether a delta, near-specular or transmissive lobe can occur anywhere on the surface.
    pub fn has_specular(&self) -> bool {
        if self.transmission > 0.0 {
            return true;
        }
        let rough_zero = match self.roughness {
            FloatParam::Const(r) => r <= super::microfacet::NEAR_SPECULAR_ROUGHNESS,
            FloatParam::Tex { .. } => true,
        };
        let metal = match self.metallic {
            FloatParam::Const(v) => v > 0.0,
            FloatParam::Tex { scale, .. } => scale > 0.0,
        };
        let smooth_coat = self
            .clearcoat
            .is_some_and(|c| c.roughness <= super::microfacet::NEAR_SPECULAR_ROUGHNESS);
        smooth_coat || (rough_zero && (metal || self.coat_f0() > 0.0))
    }
}
