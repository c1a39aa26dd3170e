//! The scene IR: plain serde data, owned by the core and shared by every front end
//! (JSON files, the USD importer, the Blender exporter).
//!
//! Conventions:
//! - Right-handed world, any up axis. Lengths in scene units.
//! - Matrices are 4x4, written as four rows, column-vector convention (`p' = M p`,
//!   translation in the last column).
//! - Colours are linear Rec.709 RGB.
//! - Light units follow Blender/Cycles: point, spot and area lights have a `power` in watts;
//!   distant lights an `irradiance` in W/m^2; emissive surfaces and the environment a radiance.
//!   An area light of power P and area A emits radiance P/(pi A); a point or spot light of power
//!   P has intensity P/(4 pi); a sphere light of power P and radius r emits P/(4 pi^2 r^2).

use serde::{Deserialize, Serialize};

pub type Rgb = [f32; 3];
pub type Matrix = [[f32; 4]; 4];

pub const IDENTITY: Matrix = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

fn identity() -> Matrix {
    IDENTITY
}
fn one() -> f32 {
    1.0
}
fn white() -> Rgb {
    [1.0, 1.0, 1.0]
}
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

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    pub camera: CameraDesc,
    #[serde(default)]
    pub film: FilmDesc,
    #[serde(default)]
    pub meshes: Vec<MeshDesc>,
    /// Extra placements of meshes; a mesh that any instance names is a prototype and is only
    /// drawn through its instances.
    #[serde(default)]
    pub instances: Vec<InstanceDesc>,
    #[serde(default)]
    pub materials: Vec<MaterialDesc>,
    #[serde(default)]
    pub textures: Vec<TextureDesc>,
    #[serde(default)]
    pub lights: Vec<LightDesc>,
    /// Light arriving from infinity; absent means black.
    #[serde(default)]
    pub environment: Option<EnvironmentDesc>,
    /// Participating media, referenced by meshes (`interior_medium`) and by `world_medium`.
    #[serde(default)]
    pub media: Vec<MediumDesc>,
    /// Medium filling all space outside mesh media (world fog); the camera starts in it.
    #[serde(default)]
    pub world_medium: Option<u32>,
    /// Light groups: the render writes one image per group (`lightgroup.<name>`), the light
    /// of its members alone; the groups sum to the beauty. Emitters in no group form the
    /// group `default` (when any group is given).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lightgroups: Vec<LightGroupDesc>,
}

/// A light group: the emitters whose light its image holds.
///
/// | field | meaning |
/// |---|---|
/// | `name` | letters, digits, `_` and `-` (it names an EXR layer and a Blender pass) |
/// | `lights` | indices into `lights` |
/// | `meshes` | indices into `meshes`: their emissive triangles (every placement of a prototype not named by its instances) |
/// | `instances` | indices into `instances`: an instance's emissive triangles |
/// | `environment` | the environment (and distant lights, which are `lights`) |
///
/// An emitter belongs to one group at most.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LightGroupDesc {
    pub name: String,
    #[serde(default)]
    pub lights: Vec<u32>,
    #[serde(default)]
    pub meshes: Vec<u32>,
    #[serde(default)]
    pub instances: Vec<u32>,
    #[serde(default)]
    pub environment: bool,
}

/// A participating medium (coefficients per unit length of scene units), homogeneous or
/// scaled by a density grid.
///
/// | field | meaning |
/// |---|---|
/// | `sigma_a` | absorption coefficient, RGB |
/// | `sigma_s` | scattering coefficient, RGB |
/// | `g` | Henyey-Greenstein anisotropy in (-1, 1): < 0 back-scattering, > 0 forward |
///
/// Media fill the inside of closed meshes (`MeshDesc::interior_medium`) or the whole world
/// (`SceneDesc::world_medium`). Along a ray the medium is that of the most recently entered
/// mesh not yet exited, else the world medium: nested meshes work as expected, and where
/// two mesh media overlap, the one entered last wins.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MediumDesc {
    #[serde(default)]
    pub name: String,
    pub sigma_a: Rgb,
    pub sigma_s: Rgb,
    #[serde(default)]
    pub g: f32,
    /// Heterogeneous medium: the coefficients are multiplied by this density grid (zero
    /// outside it). Its extinction `sigma_a + sigma_s` must be grey (the same in R, G, B);
    /// the albedo may be coloured.
    #[serde(default)]
    pub density: Option<DensityGridDesc>,
}

/// A dense 3D grid of densities over the unit cube [0,1]^3 of its `transform`
/// (grid-to-world), looked up trilinearly between voxel centres.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DensityGridDesc {
    /// Voxels along x, y, z.
    pub resolution: [u32; 3],
    /// `x * y * z` non-negative densities, x varying fastest, then y, then z.
    pub data: Vec<f32>,
    #[serde(default = "identity")]
    pub transform: Matrix,
}

/// Output image size in pixels.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FilmDesc {
    pub width: u32,
    pub height: u32,
}
impl Default for FilmDesc {
    fn default() -> Self {
        FilmDesc {
            width: 256,
            height: 256,
        }
    }
}

/// Perspective camera looking down its local -Z with +Y up (as Blender and USD cameras).
///
/// | field | meaning |
/// |---|---|
/// | `transform` | camera-to-world |
/// | `fov` | field of view in radians across the sensor-fit axis; overrides the lens |
/// | `focal_length`, `sensor_width`, `sensor_height` | lens in mm (any unit, same for all three) |
/// | `sensor_fit` | `auto` (larger image side), `horizontal`, `vertical` |
/// | `shift` | lens shift in units of the sensor-fit side |
/// | `near`, `far` | clipping distances |
/// | `fstop`, `focus_distance` | thin-lens depth of field; `fstop` absent or 0 = pinhole |
/// | `units_per_mm` | scene units per millimetre, turning the aperture into scene units |
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    #[serde(default = "identity")]
    pub transform: Matrix,
    #[serde(default)]
    pub fov: Option<f32>,
    #[serde(default = "default_focal")]
    pub focal_length: f32,
    #[serde(default = "default_sensor")]
    pub sensor_width: f32,
    #[serde(default)]
    pub sensor_height: Option<f32>,
    #[serde(default)]
    pub sensor_fit: SensorFit,
    #[serde(default)]
    pub shift: [f32; 2],
    #[serde(default = "default_near")]
    pub near: f32,
    #[serde(default = "default_far")]
    pub far: f32,
    #[serde(default)]
    pub fstop: Option<f32>,
    #[serde(default)]
    pub focus_distance: Option<f32>,
    #[serde(default = "default_units_per_mm")]
    pub units_per_mm: f32,
}
fn default_focal() -> f32 {
    50.0
}
fn default_sensor() -> f32 {
    36.0
}
fn default_near() -> f32 {
    1e-3
}
fn default_far() -> f32 {
    1e30
}
fn default_units_per_mm() -> f32 {
    1e-3
}
impl Default for CameraDesc {
    fn default() -> Self {
        CameraDesc {
            transform: IDENTITY,
            fov: None,
            focal_length: default_focal(),
            sensor_width: default_sensor(),
            sensor_height: None,
            sensor_fit: SensorFit::Auto,
            shift: [0.0, 0.0],
            near: default_near(),
            far: default_far(),
            fstop: None,
            focus_distance: None,
            units_per_mm: default_units_per_mm(),
        }
    }
}

#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum SensorFit {
    #[default]
    Auto,
    Horizontal,
    Vertical,
}

/// Triangle mesh.
///
/// | field | meaning |
/// |---|---|
/// | `positions` | vertex positions, object space |
/// | `indices` | triangles, three vertex indices each |
/// | `normals` | optional per-vertex shading normals |
/// | `uvs` | optional per-vertex texture coordinates |
/// | `attributes` | optional named per-vertex attributes (colour attributes, Blender's named attributes, USD primvars) as linear RGBA, read by the Attribute node; `.tangent` (object-space tangent, bitangent sign in `w`) replaces the tangents a tangent-space Normal Map would otherwise get at build |
/// | `material` | material of every triangle (index into `materials`) |
/// | `material_indices` | optional per-triangle material, overrides `material` |
/// | `transform` | object-to-world |
/// | `object` | optional object name for Cryptomatte (default `name`) |
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MeshDesc {
    #[serde(default)]
    pub name: String,
    pub positions: Vec<[f32; 3]>,
    pub indices: Vec<[u32; 3]>,
    #[serde(default)]
    pub normals: Option<Vec<[f32; 3]>>,
    #[serde(default)]
    pub uvs: Option<Vec<[f32; 2]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attributes: Option<std::collections::BTreeMap<String, Vec<[f32; 4]>>>,
    #[serde(default)]
    pub material: u32,
    #[serde(default)]
    pub material_indices: Option<Vec<u32>>,
    #[serde(default = "identity")]
    pub transform: Matrix,
    /// Medium inside this closed mesh (index into `media`); the mesh's normals (from the
    /// triangle winding) must point outwards.
    #[serde(default)]
    pub interior_medium: Option<u32>,
    /// The object's name where compositing names it (Cryptomatte object mattes); default
    /// `name`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object: Option<String>,
}

impl Default for MeshDesc {
    fn default() -> Self {
        MeshDesc {
            name: String::new(),
            positions: Vec::new(),
            indices: Vec::new(),
            normals: None,
            uvs: None,
            attributes: None,
            material: 0,
            material_indices: None,
            transform: IDENTITY,
            interior_medium: None,
            object: None,
        }
    }
}

/// Another placement of a mesh: world = `transform` x mesh.transform.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InstanceDesc {
    #[serde(default)]
    pub name: String,
    pub mesh: u32,
    #[serde(default = "identity")]
    pub transform: Matrix,
    /// The object's name where compositing names it (Cryptomatte object mattes); default
    /// `name`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub object: Option<String>,
}

impl Default for InstanceDesc {
    fn default() -> Self {
        InstanceDesc {
            name: String::new(),
            mesh: 0,
            transform: IDENTITY,
            object: None,
        }
    }
}

/// Float RGB(A) image, rows from top to bottom, looked up bilinearly by UV
/// (u right, v up: v = 0 is the bottom row, as in Blender and USD).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TextureDesc {
    #[serde(default)]
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// 1 (grey), 3 (RGB) or 4 (RGBA).
    pub channels: u32,
    /// `width * height * channels` floats, linear or as `encoding` says.
    pub data: Vec<f32>,
    #[serde(default)]
    pub wrap: WrapMode,
    /// How `data` encodes the colour channels (alpha is always linear).
    #[serde(default)]
    pub encoding: TextureEncoding,
}

/// `linear`: the values are linear. `srgb`: the colour channels hold sRGB-encoded values in
/// [0, 1] (an 8-bit image's bytes / 255), interpolated as stored and decoded to linear after
/// the bilinear lookup, as Cycles looks up 8-bit sRGB images.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum TextureEncoding {
    #[default]
    Linear,
    Srgb,
}

#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum WrapMode {
    #[default]
    Repeat,
    Clamp,
    Mirror,
    /// Outside [0,1) is black.
    Black,
}

/// A colour: a constant, or a texture times a scale.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum ColorInput {
    Value(Rgb),
    Texture {
        texture: u32,
        #[serde(default = "white")]
        scale: Rgb,
    },
}

/// A scalar: a constant, or one channel of a texture times a scale.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum FloatInput {
    Value(f32),
    Texture {
        texture: u32,
        #[serde(default)]
        channel: u32,
        #[serde(default = "one")]
        scale: f32,
    },
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
/// | `graph` | a shading graph: `nodes` and the `surface` closure ([`super::graph_desc::GraphDesc`]) |
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
    Graph(Box<super::graph_desc::GraphDesc>),
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
fn yes() -> bool {
    true
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

/// Lights. `color` tints the power; every light has `name` for messages.
///
/// | type | parameters |
/// |---|---|
/// | `point` | `position`, `power` W, `radius` (0 = a true point; > 0 a sphere light), `soft_falloff` (Blender's Soft Falloff: a disk of `radius` facing the shading point instead of a sphere; default false) |
/// | `spot` | `position`, `direction`, `power` W (as the unshaded point light), `cone_angle` (full angle, rad), `blend` in [0,1], `radius`, `soft_falloff` |
/// | `rect` | `transform` (light emits along local -Z), `width`, `height`, `power` W, `two_sided`, `spread` (full emission angle, rad, (0, pi]; default pi) |
/// | `disk` | `transform`, `radius`, `radius_y` (an ellipse's second radius; default `radius`), `power` W, `two_sided`, `spread` |
/// | `sphere` | `position`, `radius` > 0, `power` W |
///
/// Every light but `distant` also takes `camera_visible` (default true): false hides the
/// emitter from camera rays, as Blender's Ray Visibility > Camera, while it still lights the
/// scene and shows in mirrors and glass.
/// | `distant` | `direction` (travel direction of the light), `irradiance` W/m^2, `angle` (angular diameter, rad) |
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum LightDesc {
    Point {
        #[serde(default)]
        name: String,
        position: [f32; 3],
        power: f32,
        #[serde(default = "white")]
        color: Rgb,
        #[serde(default)]
        radius: f32,
        #[serde(default)]
        soft_falloff: bool,
        /// Seen by camera rays (Blender's Ray Visibility > Camera); it lights the scene
        /// either way.
        #[serde(default = "yes")]
        camera_visible: bool,
    },
    Spot {
        #[serde(default)]
        name: String,
        position: [f32; 3],
        direction: [f32; 3],
        power: f32,
        #[serde(default = "white")]
        color: Rgb,
        cone_angle: f32,
        #[serde(default)]
        blend: f32,
        #[serde(default)]
        radius: f32,
        #[serde(default)]
        soft_falloff: bool,
        /// Seen by camera rays (Blender's Ray Visibility > Camera); it lights the scene
        /// either way.
        #[serde(default = "yes")]
        camera_visible: bool,
    },
    Rect {
        #[serde(default)]
        name: String,
        #[serde(default = "identity")]
        transform: Matrix,
        width: f32,
        height: f32,
        power: f32,
        #[serde(default = "white")]
        color: Rgb,
        #[serde(default)]
        two_sided: bool,
        #[serde(default = "full_spread")]
        spread: f32,
        /// Seen by camera rays (Blender's Ray Visibility > Camera); it lights the scene
        /// either way.
        #[serde(default = "yes")]
        camera_visible: bool,
    },
    Disk {
        #[serde(default)]
        name: String,
        #[serde(default = "identity")]
        transform: Matrix,
        radius: f32,
        #[serde(default)]
        radius_y: Option<f32>,
        power: f32,
        #[serde(default = "white")]
        color: Rgb,
        #[serde(default)]
        two_sided: bool,
        #[serde(default = "full_spread")]
        spread: f32,
        /// Seen by camera rays (Blender's Ray Visibility > Camera); it lights the scene
        /// either way.
        #[serde(default = "yes")]
        camera_visible: bool,
    },
    Sphere {
        #[serde(default)]
        name: String,
        position: [f32; 3],
        radius: f32,
        power: f32,
        #[serde(default = "white")]
        color: Rgb,
        /// Seen by camera rays (Blender's Ray Visibility > Camera); it lights the scene
        /// either way.
        #[serde(default = "yes")]
        camera_visible: bool,
    },
    Distant {
        #[serde(default)]
        name: String,
        direction: [f32; 3],
        irradiance: f32,
        #[serde(default = "white")]
        color: Rgb,
        #[serde(default)]
        angle: f32,
    },
}

fn full_spread() -> f32 {
    std::f32::consts::PI
}

impl LightDesc {
    /// Whether camera rays see the emitter (lights at infinity: always).
    pub fn camera_visible(&self) -> bool {
        match self {
            LightDesc::Point { camera_visible, .. }
            | LightDesc::Spot { camera_visible, .. }
            | LightDesc::Rect { camera_visible, .. }
            | LightDesc::Disk { camera_visible, .. }
            | LightDesc::Sphere { camera_visible, .. } => *camera_visible,
            LightDesc::Distant { .. } => true,
        }
    }

    pub fn name(&self) -> &str {
        match self {
            LightDesc::Point { name, .. }
            | LightDesc::Spot { name, .. }
            | LightDesc::Rect { name, .. }
            | LightDesc::Disk { name, .. }
            | LightDesc::Sphere { name, .. }
            | LightDesc::Distant { name, .. } => name,
        }
    }
}

/// Light from infinity: radiance = `color` x `strength` (x the texture, when given).
///
/// The lat-long `texture` maps direction d (in the environment's local frame, +Z up, as
/// Blender's Environment Texture) to u = 0.5 - atan2(d.y, d.x) / 2pi, v = 0.5 + asin(d.z) / pi.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentDesc {
    #[serde(default = "white")]
    pub color: Rgb,
    #[serde(default = "one")]
    pub strength: f32,
    #[serde(default)]
    pub texture: Option<u32>,
    /// Environment-to-world.
    #[serde(default = "identity")]
    pub transform: Matrix,
}
