//! A graph that is one closure with constant inputs, as the plain material it is.

use super::graph::closure::LeafKind;
use crate::scene::desc::{ColorInput, FloatInput, MaterialDesc, PrincipledDesc};
use glam::Vec3;

/// The plain IR material for closure `kind` with input values `v` (in the node's socket
/// order), if there is one that renders the same.
pub fn plain(name: &str, kind: LeafKind, v: &[Vec3]) -> Option<MaterialDesc> {
    let rgb = |c: Vec3| [c.x, c.y, c.z];
    let name = name.to_string();
    Some(match kind {
        LeafKind::Principled { multiscatter } => {
            // Alpha below 1, subsurface and sheen stay graphs (or are warned about there).
            if v[4].x < 1.0 || v[6].x != 0.0 || v[16].x != 0.0 {
                return None;
            }
            MaterialDesc::Principled(Box::new(PrincipledDesc {
                name,
                base_color: ColorInput::Value(rgb(v[0])),
                metallic: FloatInput::Value(v[1].x),
                roughness: FloatInput::Value(v[2].x),
                ior: v[3].x,
                specular: 2.0 * v[7].x,
                transmission: v[8].x,
                coat_weight: v[9].x.clamp(0.0, 1.0),
                coat_roughness: v[10].x,
                coat_ior: v[11].x.max(1.0),
                coat_tint: rgb(v[12]),
                emission_color: ColorInput::Value(rgb(v[14])),
                emission_strength: v[15].x.max(0.0),
                multiscatter,
                subsurface: None,
            }))
        }
        LeafKind::Diffuse => MaterialDesc::Diffuse {
            name,
            color: ColorInput::Value(rgb(v[0])),
        },
        LeafKind::Glossy { multiscatter } => MaterialDesc::Glossy {
            name,
            color: rgb(v[0]),
            roughness: v[1].x,
            multiscatter,
        },
        LeafKind::Glass { multiscatter } => MaterialDesc::Dielectric {
            name,
            ior: v[2].x,
            roughness: v[1].x,
            color: rgb(v[0]),
            multiscatter,
        },
        LeafKind::Emission => MaterialDesc::Emission {
            name,
            color: ColorInput::Value(rgb(v[0])),
            strength: v[1].x.max(0.0),
        },
        _ => return None,
    })
}
