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

mod light;
mod material;

pub use light::{EnvironmentDesc, LightDesc};
pub use material::{MaterialDesc, PrincipledDesc, SubsurfaceDesc, SubsurfaceMethod};

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
fn yes() -> bool {
    true
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

/// Output image size in pixels, and whether the background seen by the camera is
/// transparent.
///
/// | field | meaning |
/// |---|---|
/// | `width`, `height` | pixels |
/// | `transparent` | Blender's Film > Transparent: where a camera ray reaches the background straight through transparent surfaces and media, it adds no colour and the image's alpha is transparent (the world still lights the scene, and is still seen in mirrors and through glass) |
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FilmDesc {
    pub width: u32,
    pub height: u32,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub transparent: bool,
}
impl Default for FilmDesc {
    fn default() -> Self {
        FilmDesc {
            width: 256,
            height: 256,
            transparent: false,
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
/// | `holdout` | Blender's object Holdout: camera rays that reach it straight (through transparent surfaces only) see a hole in the image, transparent and black, where its surface is opaque; other rays see it as usual |
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
    /// Blender's object Holdout (see the table above).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub holdout: bool,
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
            holdout: false,
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
    /// The placement's object is a holdout (as `MeshDesc::holdout`; the mesh's own flag is
    /// for its own placement).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub holdout: bool,
}

impl Default for InstanceDesc {
    fn default() -> Self {
        InstanceDesc {
            name: String::new(),
            mesh: 0,
            transform: IDENTITY,
            object: None,
            holdout: false,
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
