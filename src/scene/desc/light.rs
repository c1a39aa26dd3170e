//! Lights in the IR: point, spot, area and distant lights, and the environment.

use super::{identity, one, white, yes, Matrix, Rgb};
use serde::{Deserialize, Serialize};

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
