//! Surface materials: the scene IR's materials turned into BSDFs at shading points.
//!
//! - [`bsdf`]: the BSDF interface (lobe mixture, flags, samples, Russian roulette parts);
//! - lobes: [`diffuse`] (Lambert), [`conductor`] (delta reflection), [`glossy`] (GGX
//!   reflection), [`dielectric`] (smooth glass), [`rough_dielectric`] (GGX glass),
//!   [`layer`] (diffuse under a coat);
//! - [`fresnel`], [`microfacet`]: shared terms; [`texture`]: images and parameters;
//! - [`principled`]: the Principled BSDF mapping; [`subsurface`]: its subsurface part (Cycles'
//!   random walk below the diffuse base).

pub mod bsdf;
pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod fresnel;
pub mod glass_albedo;
pub mod glossy;
pub mod graph;
mod graph_constant;
pub mod layer;
pub mod lobe;
pub mod microfacet;
pub mod principled;
pub mod rough_dielectric;
pub mod subsurface;
pub mod texture;
pub mod translucent;

pub use bsdf::{Bsdf, BsdfSample, Component, LobeFlags, MAX_LOBES};
pub use lobe::Lobe;
pub use principled::Principled;
pub use texture::{ColorParam, FloatParam, Texture};

use crate::math::{Frame, Spectrum};
use crate::scene::desc::MaterialDesc;
use conductor::SpecularReflection;
use dielectric::SmoothDielectric;
use diffuse::Lambert;
use fresnel::Fresnel;
use glam::{Vec2, Vec3};
use glossy::MicrofacetReflection;
use microfacet::{alpha_from_roughness, Ggx};
use rough_dielectric::RoughDielectric;

/// Relative IORs closer to 1 than this are index-matched: the interface is treated as a
/// smooth dielectric whatever its roughness (a rough interface with eta -> 1 refracts into a
/// lobe of width ~ alpha |eta - 1|, numerically a delta).
pub const INDEX_MATCHED_EPS: f32 = 1e-3;

/// Reflection lobe of perceptual `roughness` (0 = delta) with the given Fresnel; with
/// `multiscatter`, compensated for multiple scattering between microfacets as Cycles'
/// Multiscatter GGX is.
pub fn reflection_lobe(roughness: f32, fresnel: Fresnel, multiscatter: bool) -> Lobe {
    if roughness > 0.0 {
        Lobe::MicrofacetReflection(MicrofacetReflection::new(
            roughness,
            fresnel,
            None,
            multiscatter,
        ))
    } else {
        Lobe::SpecularReflection(SpecularReflection { fresnel })
    }
}

/// The reflection of a dielectric coat whose albedo table is `table` (its F0 fixes the
/// Fresnel), of perceptual `roughness`.
pub fn coat_lobe(
    roughness: f32,
    table: &'static layer::CoatAlbedoTable,
    multiscatter: bool,
) -> Lobe {
    let fresnel = Fresnel::Dielectric {
        eta: fresnel::ior_from_f0(table.f0()),
    };
    if roughness > 0.0 {
        Lobe::MicrofacetReflection(MicrofacetReflection::new(
            roughness,
            fresnel,
            Some(table),
            multiscatter,
        ))
    } else {
        Lobe::SpecularReflection(SpecularReflection { fresnel })
    }
}

/// Dielectric interface of relative IOR `eta` (inside / outside), perceptual `roughness`
/// (0 = smooth) and transmission `tint`; with `multiscatter`, a rough one compensated for
/// multiple scattering between microfacets as Cycles' Multiscatter GGX glass is.
pub fn dielectric_lobe(eta: f32, roughness: f32, tint: Spectrum, multiscatter: bool) -> Lobe {
    interface_lobe(eta, roughness, tint, multiscatter, false)
}

/// Cycles' Refraction BSDF: the refraction of [`dielectric_lobe`] alone, not scaled by the
/// Fresnel transmittance (GGX without multiple-scattering compensation, as Cycles has it).
pub fn refraction_lobe(eta: f32, roughness: f32, tint: Spectrum) -> Lobe {
    interface_lobe(eta, roughness, tint, false, true)
}

fn interface_lobe(
    eta: f32,
    roughness: f32,
    tint: Spectrum,
    multiscatter: bool,
    refraction_only: bool,
) -> Lobe {
    let eta = if eta.is_finite() && eta > 0.0 {
        eta
    } else {
        1.5
    };
    if roughness > 0.0 && (eta - 1.0).abs() >= INDEX_MATCHED_EPS {
        Lobe::RoughDielectric(RoughDielectric {
            ggx: Ggx::new(alpha_from_roughness(roughness)),
            eta,
            tint,
            multiscatter,
            refraction_only,
        })
    } else {
        Lobe::SmoothDielectric(SmoothDielectric {
            eta,
            tint,
            refraction_only,
        })
    }
}

/// A surface material, built from [`MaterialDesc`]. Roughness is perceptual everywhere
/// (GGX alpha = roughness^2, clamped to 1e-4; roughness 0 is the smooth delta lobe).
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Invisible boundary of a participating medium: no lobes, rays continue unchanged.
    Null { name: String },
    /// Lambertian reflector.
    ///
    /// | parameter | meaning |
    /// |---|---|
    /// | `color` | albedo (texturable) |
    Diffuse { name: String, color: ColorParam },
    /// Perfect mirror.
    ///
    /// | parameter | meaning |
    /// |---|---|
    /// | `color` | reflectance at every angle |
    Mirror { name: String, color: Spectrum },
    /// Metal with exact conductor Fresnel; GGX when rough.
    ///
    /// | parameter | meaning |
    /// |---|---|
    /// | `eta`, `k` | complex IOR per channel |
    /// | `roughness` | perceptual roughness, 0 = smooth |
    Conductor {
        name: String,
        eta: Spectrum,
        k: Spectrum,
        roughness: f32,
    },
    /// Glass-like interface; GGX (Walter 2007) when rough.
    ///
    /// | parameter | meaning |
    /// |---|---|
    /// | `ior` | index of refraction inside (outside is 1) |
    /// | `roughness` | perceptual roughness, 0 = smooth |
    /// | `color` | transmission tint |
    /// | `multiscatter` | Cycles' multiple-scattering compensation (Multiscatter GGX) |
    Dielectric {
        name: String,
        ior: f32,
        roughness: f32,
        color: Spectrum,
        multiscatter: bool,
    },
    /// GGX reflection tinted by a colour, without Fresnel (Blender's Glossy BSDF).
    ///
    /// | parameter | meaning |
    /// |---|---|
    /// | `color` | reflectance tint |
    /// | `roughness` | perceptual roughness, 0 = smooth |
    /// | `multiscatter` | Cycles' multiple-scattering compensation (Multiscatter GGX) |
    Glossy {
        name: String,
        color: Spectrum,
        roughness: f32,
        multiscatter: bool,
    },
    /// Emitter that reflects nothing.
    ///
    /// | parameter | meaning |
    /// |---|---|
    /// | `color` | colour (texturable) |
    /// | `strength` | radiance = colour x strength |
    Emission {
        name: String,
        color: ColorParam,
        strength: f32,
    },
    /// Blender Principled BSDF / OpenPBR; see [`Principled`] for the mapping.
    Principled(Box<Principled>),
    /// A shading graph ([`graph::ShaderGraph`]): closures over node expressions.
    Graph(Box<graph::ShaderGraph>),
}

fn rgb(c: &[f32; 3]) -> Spectrum {
    let v = Vec3::from_array(*c);
    if v.is_finite() {
        v.max(Vec3::ZERO)
    } else {
        Vec3::ZERO
    }
}

fn unit(v: f32) -> f32 {
    if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

impl Material {
    /// Converts validated IR; out-of-range values are clamped, never a panic.
    pub fn from_desc(desc: &MaterialDesc) -> Material {
        match desc {
            MaterialDesc::Diffuse { name, color } => Material::Diffuse {
                name: name.clone(),
                color: ColorParam::from_input(color),
            },
            MaterialDesc::Mirror { name, color } => Material::Mirror {
                name: name.clone(),
                color: rgb(color),
            },
            MaterialDesc::Conductor {
                name,
                eta,
                k,
                roughness,
            } => Material::Conductor {
                name: name.clone(),
                eta: rgb(eta),
                k: rgb(k),
                roughness: unit(*roughness),
            },
            MaterialDesc::Dielectric {
                name,
                ior,
                roughness,
                color,
                multiscatter,
            } => Material::Dielectric {
                name: name.clone(),
                ior: if ior.is_finite() && *ior > 0.0 {
                    *ior
                } else {
                    1.5
                },
                roughness: unit(*roughness),
                color: rgb(color),
                multiscatter: *multiscatter,
            },
            MaterialDesc::Glossy {
                name,
                color,
                roughness,
                multiscatter,
            } => Material::Glossy {
                name: name.clone(),
                color: rgb(color),
                roughness: unit(*roughness),
                multiscatter: *multiscatter,
            },
            MaterialDesc::Emission {
                name,
                color,
                strength,
            } => Material::Emission {
                name: name.clone(),
                color: ColorParam::from_input(color),
                strength: if strength.is_finite() {
                    strength.max(0.0)
                } else {
                    0.0
                },
            },
            MaterialDesc::Null { name } => Material::Null { name: name.clone() },
            MaterialDesc::Principled(p) => Material::Principled(Box::new(Principled::from_desc(p))),
            MaterialDesc::Graph(g) => Material::from_graph(g, "", usize::MAX),
        }
    }

    /// The material of graph `g` (at JSON pointer `pointer`, in a scene of `n_textures`):
    /// one closure with constant inputs becomes the plain material it is; a graph that does
    /// not compile (validation reports it first) renders grey diffuse.
    pub fn from_graph(
        g: &crate::scene::graph_desc::GraphDesc,
        pointer: &str,
        n_textures: usize,
    ) -> Material {
        match graph::ShaderGraph::new(g, pointer, n_textures) {
            Ok(sg) => match sg
                .as_constant()
                .and_then(|(k, v)| graph_constant::plain(&g.name, k, &v))
            {
                Some(desc) => Material::from_desc(&desc),
                None => Material::Graph(Box::new(sg)),
            },
            Err(_) => Material::Diffuse {
                name: g.name.clone(),
                color: ColorParam::Const(Vec3::splat(0.8)),
            },
        }
    }

    /// An invisible surface (a medium boundary): rays and photons pass straight through.
    pub fn is_null(&self) -> bool {
        matches!(self, Material::Null { .. })
    }

    pub fn name(&self) -> &str {
        match self {
            Material::Diffuse { name, .. }
            | Material::Mirror { name, .. }
            | Material::Conductor { name, .. }
            | Material::Dielectric { name, .. }
            | Material::Glossy { name, .. }
            | Material::Emission { name, .. }
            | Material::Null { name } => name,
            Material::Principled(p) => &p.name,
            Material::Graph(g) => &g.name,
        }
    }

    /// The BSDF at a shading point with frame `frame` and texture coordinates `uv`.
    pub fn bsdf(&self, frame: Frame, uv: Vec2, textures: &[Texture]) -> Bsdf {
        let b = Bsdf::new(frame);
        match self {
            Material::Null { .. } => b,
            Material::Diffuse { color, .. } => b.with(
                1.0,
                Lobe::Lambert(Lambert {
                    albedo: color.eval(uv, textures).max(Vec3::ZERO),
                }),
            ),
            Material::Mirror { color, .. } => b.with(
                1.0,
                Lobe::SpecularReflection(SpecularReflection {
                    fresnel: Fresnel::Constant(*color),
                }),
            ),
            Material::Conductor {
                eta, k, roughness, ..
            } => b.with(
                1.0,
                reflection_lobe(*roughness, Fresnel::Conductor { eta: *eta, k: *k }, false),
            ),
            Material::Dielectric {
                ior,
                roughness,
                color,
                multiscatter,
                ..
            } => b.with(
                1.0,
                dielectric_lobe(*ior, *roughness, *color, *multiscatter),
            ),
            Material::Glossy {
                color,
                roughness,
                multiscatter,
                ..
            } => b.with(
                1.0,
                reflection_lobe(*roughness, Fresnel::Constant(*color), *multiscatter),
            ),
            Material::Emission { .. } => b,
            Material::Principled(p) => p.bsdf(frame, uv, textures),
            Material::Graph(g) => {
                let mut sp = graph::point::ShadingPoint::at(Vec3::ZERO, frame.n, uv);
                sp.dpdu = frame.s;
                g.shade(&sp, textures, graph::Want::All).bsdf
            }
        }
    }

    /// Emitted radiance at shading point `sp` (zero for non-emitters).
    pub fn emission_at(&self, sp: &graph::point::ShadingPoint, textures: &[Texture]) -> Spectrum {
        match self {
            Material::Graph(g) => g.shade(sp, textures, graph::Want::Light).emission,
            _ => self.emission(sp.uv, textures),
        }
    }

    /// Emitted radiance at `uv` (zero for non-emitters; a graph's is that of
    /// [`Material::emission_at`] at a point that knows only `uv`).
    pub fn emission(&self, uv: Vec2, textures: &[Texture]) -> Spectrum {
        match self {
            Material::Graph(g) => {
                let sp = graph::point::ShadingPoint::at(Vec3::ZERO, Vec3::Z, uv);
                g.shade(&sp, textures, graph::Want::Light).emission
            }
            Material::Emission {
                color, strength, ..
            } => color.eval(uv, textures).max(Vec3::ZERO) * *strength,
            Material::Principled(p) if p.emission_strength > 0.0 => {
                p.emission_color.eval(uv, textures).max(Vec3::ZERO) * p.emission_strength
            }
            _ => Vec3::ZERO,
        }
    }

    /// The material's subsurface part, if it has one.
    pub fn subsurface(&self) -> Option<&subsurface::Subsurface> {
        match self {
            Material::Principled(p) => p.subsurface.as_ref(),
            _ => None,
        }
    }

    /// Whether the material can emit anywhere.
    pub fn is_emissive(&self) -> bool {
        match self {
            Material::Emission {
                color, strength, ..
            } => *strength > 0.0 && !color.is_black(),
            Material::Principled(p) => p.emission_strength > 0.0 && !p.emission_color.is_black(),
            Material::Graph(g) => g.is_emissive(),
            _ => false,
        }
    }

    /// Whether light reaching the surface can leave it other than straight through, reflected
    /// or transmitted by a lobe. Where no surface of a scene can, photons are never stored.
    pub fn scatters(&self) -> bool {
        match self {
            Material::Emission { .. } | Material::Null { .. } => false,
            Material::Graph(g) => g.scatters(),
            _ => true,
        }
    }

    /// Whether a delta, near-specular or transmissive lobe is possible (the scene then needs a
    /// caustic map).
    pub fn has_specular(&self) -> bool {
        match self {
            Material::Diffuse { .. } | Material::Emission { .. } | Material::Null { .. } => false,
            Material::Mirror { .. } | Material::Dielectric { .. } => true,
            Material::Conductor { roughness, .. } | Material::Glossy { roughness, .. } => {
                *roughness <= microfacet::NEAR_SPECULAR_ROUGHNESS
            }
            Material::Principled(p) => p.has_specular(),
            Material::Graph(g) => g.has_specular(),
        }
    }
}
