//! Surface materials in the IR: the plain materials, the Principled BSDF and its
//! subsurface part, and shading graphs.

use super::{one, white, yes, ColorInput, FloatInput, Rgb};
use serde::{Deserialize, Serialize};

fn default_ior() -> f32 {
    1.5
}
fn default_roughness() -> f32 {
    0.5
}
fn default_base_color() -> ColorInput {
    ColorInput::Value([0.8, 0.8, 0.8])
}
fn default_specular() -> f32 {
    1.0
}
/// Surface materials. Roughness is perceptual (GGX alpha = roughness^2, as Blender).
///
/// | type | parameters |
/// |---|---|
/// | `diffuse` | `color` (Lambert albedo) |
/// | `mirror` | `color` (reflectance of a perfect mirror) |
/// | `conductor` | `eta`, `k` (complex IOR per channel), `roughness` (0 = smooth) |
/// | `dielectric` | `ior`, `roughness` (0 = smooth), `color` (transmission tint) |
/// | `glossy` | `color` (normal-incidence reflectance, Schlick), `roughness` |
/// | `emission` | `color`, `strength`: radiance = color x strength; reflects nothing |
/// | `null` | an invisible surface: the boundary of a medium (Blender's volume-only material) |
/// | `principled` | Blender Principled BSDF / OpenPBR: `base_color`, `metallic`, `roughness`, `transmission`, `ior`, `specular`, `emission_color`, `emission_strength` |
/// | `graph` | a shading graph: `nodes` and the `surface` closure ([`crate::scene::graph_desc::GraphDesc`]) |
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum MaterialDesc {
    Diffuse {
        #[serde(default)]
        name: String,
        #[serde(default = "default_base_color")]
        color: ColorInput,
    },
    Mirror {
        #[serde(default)]
        name: String,
        #[serde(default = "white")]
        color: Rgb,
    },
    Conductor {
        #[serde(default)]
        name: String,
        eta: Rgb,
        k: Rgb,
        #[serde(default)]
        roughness: f32,
    },
    Dielectric {
        #[serde(default)]
        name: String,
        #[serde(default = "default_ior")]
        ior: f32,
        #[serde(default)]
        roughness: f32,
        #[serde(default = "white")]
        color: Rgb,
        /// A rough interface compensated for multiple scattering between microfacets
        /// (Blender's Multiscatter GGX, the default); false is plain GGX.
        #[serde(default = "yes")]
        multiscatter: bool,
    },
    Glossy {
        #[serde(default)]
        name: String,
        #[serde(default = "white")]
        color: Rgb,
        #[serde(default = "default_roughness")]
        roughness: f32,
        /// Compensated for multiple scattering between microfacets (Blender's Multiscatter
        /// GGX, the default); false is plain GGX.
        #[serde(default = "yes")]
        multiscatter: bool,
    },
    Emission {
        #[serde(default)]
        name: String,
        #[serde(default = "white_color")]
        color: ColorInput,
        #[serde(default = "one")]
        strength: f32,
    },
    Null {
        #[serde(default)]
        name: String,
    },
    Principled(Box<PrincipledDesc>),
    /// A shading graph (`graph_desc::GraphDesc`): closures combined by Mix and Add over
    /// node expressions.
    Graph(Box<crate::scene::graph_desc::GraphDesc>),
}

/// Blender Principled BSDF / OpenPBR parameters.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PrincipledDesc {
    #[serde(default)]
    pub name: String,
    #[serde(default = "default_base_color")]
    pub base_color: ColorInput,
    #[serde(default = "zero_float")]
    pub metallic: FloatInput,
    #[serde(default = "half_float")]
    pub roughness: FloatInput,
    #[serde(default)]
    pub transmission: f32,
    #[serde(default = "default_ior")]
    pub ior: f32,
    /// Specular weight (OpenPBR `specular_weight`, Blender "IOR Level" x 2): scales the
    /// dielectric reflection; 1 is physical.
    #[serde(default = "default_specular")]
    pub specular: f32,
    #[serde(default = "black_color")]
    pub emission_color: ColorInput,
    #[serde(default)]
    pub emission_strength: f32,
    /// Reflection compensated for multiple scattering between microfacets (Blender's
    /// Multiscatter GGX, the Principled BSDF's default); false is plain GGX.
    #[serde(default = "yes")]
    pub multiscatter: bool,
    /// Clear coat over everything (Blender's Coat, OpenPBR `coat_*`): weight in [0, 1]
    /// (0 = none), perceptual roughness, IOR and tint.
    #[serde(default)]
    pub coat_weight: f32,
    #[serde(default = "default_coat_roughness")]
    pub coat_roughness: f32,
    #[serde(default = "default_ior")]
    pub coat_ior: f32,
    #[serde(default = "white")]
    pub coat_tint: Rgb,
    /// Subsurface scattering below the surface (Blender's Subsurface Weight with the Random
    /// Walk method, OpenPBR `subsurface_*`); absent or weight 0: none. See [`SubsurfaceDesc`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub subsurface: Option<SubsurfaceDesc>,
}

/// The subsurface part of a Principled material, walked as Cycles' Random Walk
/// (`materials::subsurface`).
///
/// | field | meaning |
/// |---|---|
/// | `weight` | [0, 1]: share of the diffuse base that scatters below the surface (Blender Subsurface Weight, OpenPBR `subsurface_weight`) |
/// | `radius` | RGB mean free path in scene units (Blender Radius x Scale, OpenPBR `subsurface_radius` x `subsurface_radius_scale`); a channel of 0 renders as the diffuse base |
/// | `color` | the albedo seen on the surface (default: the base colour; OpenPBR `subsurface_color`) |
/// | `ior` | index of refraction of the entry (default: the material's `ior`; Blender's Subsurface IOR with `skin`) |
/// | `anisotropy` | Henyey-Greenstein g inside, clamped to [0, 0.9] as Cycles does |
/// | `method` | `random_walk` (default) or `skin` (Blender's Random Walk (Skin)) |
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SubsurfaceDesc {
    #[serde(default = "one")]
    pub weight: f32,
    pub radius: Rgb,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgb>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ior: Option<f32>,
    #[serde(default)]
    pub anisotropy: f32,
    #[serde(default)]
    pub method: SubsurfaceMethod,
}

/// How a camera path enters a subsurface material (Blender's Subsurface Method).
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SubsurfaceMethod {
    /// Through a GGX interface of the surface's roughness and the material's IOR.
    #[default]
    RandomWalk,
    /// Half diffusely, half through a GGX interface of roughness 1 and the Subsurface IOR.
    Skin,
}
fn default_coat_roughness() -> f32 {
    0.03
}
fn white_color() -> ColorInput {
    ColorInput::Value(white())
}
fn zero_float() -> FloatInput {
    FloatInput::Value(0.0)
}
fn half_float() -> FloatInput {
    FloatInput::Value(0.5)
}
fn black_color() -> ColorInput {
    ColorInput::Value([0.0; 3])
}
impl Default for PrincipledDesc {
    fn default() -> Self {
        PrincipledDesc {
            name: String::new(),
            base_color: default_base_color(),
            metallic: zero_float(),
            roughness: half_float(),
            transmission: 0.0,
            ior: default_ior(),
            specular: 1.0,
            emission_color: black_color(),
            emission_strength: 0.0,
            multiscatter: true,
            coat_weight: 0.0,
            coat_roughness: default_coat_roughness(),
            coat_ior: default_ior(),
            coat_tint: white(),
            subsurface: None,
        }
    }
}

impl MaterialDesc {
    pub fn name(&self) -> &str {
        match self {
            MaterialDesc::Diffuse { name, .. }
            | MaterialDesc::Mirror { name, .. }
            | MaterialDesc::Conductor { name, .. }
            | MaterialDesc::Dielectric { name, .. }
            | MaterialDesc::Glossy { name, .. }
            | MaterialDesc::Emission { name, .. }
            | MaterialDesc::Null { name } => name,
            MaterialDesc::Principled(p) => &p.name,
            MaterialDesc::Graph(g) => &g.name,
        }
    }
}
