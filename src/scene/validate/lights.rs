//! Checks of the IR's lights and light groups.

use super::Ctx;
use crate::error::{Error, Result};
use crate::scene::desc::*;

/// The most light groups a scene may have (a photon carries its group in 8 bits), the
/// `default` group included.
pub const MAX_LIGHTGROUPS: usize = 255;

pub(super) fn validate_lightgroups(scene: &SceneDesc) -> Result<()> {
    if scene.lightgroups.len() >= MAX_LIGHTGROUPS {
        return Err(Error::scene(
            "/lightgroups",
            "",
            format!(
                "{} light groups, at most {} are supported",
                scene.lightgroups.len(),
                MAX_LIGHTGROUPS - 1
            ),
        ));
    }
    // Which group each member is in so far: (kind, index) -> group.
    let mut owner: std::collections::HashMap<(&str, u32), usize> = Default::default();
    for (i, g) in scene.lightgroups.iter().enumerate() {
        let c = Ctx::new(format!("/lightgroups/{i}"), &g.name);
        let ok = |ch: char| ch.is_ascii_alphanumeric() || ch == '_' || ch == '-';
        if g.name.is_empty() || !g.name.chars().all(ok) {
            return Err(c.err(
                "name",
                format!(
                    "`{}` is not a light group name: letters, digits, `_` and `-` only",
                    g.name
                ),
            ));
        }
        if let Some(j) = scene.lightgroups[..i].iter().position(|o| o.name == g.name) {
            return Err(c.err("name", format!("the same name as /lightgroups/{j}")));
        }
        for (kind, list, len) in [
            ("lights", &g.lights, scene.lights.len()),
            ("meshes", &g.meshes, scene.meshes.len()),
            ("instances", &g.instances, scene.instances.len()),
        ] {
            for (k, &m) in list.iter().enumerate() {
                if m as usize >= len {
                    return Err(c.err(
                        &format!("{kind}/{k}"),
                        format!("index {m} out of range ({len} {kind})"),
                    ));
                }
                if let Some(&j) = owner.get(&(kind, m)) {
                    if j != i {
                        return Err(c.err(
                            &format!("{kind}/{k}"),
                            format!(
                                "{kind} {m} is already in light group `{}` (/lightgroups/{j}); \
                                 an emitter belongs to one group at most",
                                scene.lightgroups[j].name
                            ),
                        ));
                    }
                }
                owner.insert((kind, m), i);
            }
        }
        if g.environment {
            if let Some(&j) = owner.get(&("environment", 0)) {
                return Err(c.err(
                    "environment",
                    format!(
                        "the environment is already in light group `{}` (/lightgroups/{j})",
                        scene.lightgroups[j].name
                    ),
                ));
            }
            owner.insert(("environment", 0), i);
        }
    }
    Ok(())
}

/// An area light's spread: the full emission angle, in (0, pi] radians.
fn spread_ok(c: &Ctx, spread: f32) -> Result<()> {
    if spread.is_finite() && spread > 0.0 && spread <= std::f32::consts::PI * (1.0 + 1e-6) {
        Ok(())
    } else {
        Err(c.err(
            "spread",
            format!("must be in (0, pi] radians, got {spread}"),
        ))
    }
}

pub(super) fn validate_light(i: usize, l: &LightDesc) -> Result<()> {
    let c = Ctx::new(format!("/lights/{i}"), l.name());
    match l {
        LightDesc::Point {
            position,
            power,
            color,
            radius,
            ..
        } => {
            c.vec3("position", position)?;
            c.non_negative("power", *power)?;
            c.rgb("color", color)?;
            c.non_negative("radius", *radius)
        }
        LightDesc::Spot {
            position,
            direction,
            power,
            color,
            cone_angle,
            blend,
            radius,
            ..
        } => {
            c.vec3("position", position)?;
            c.direction("direction", direction)?;
            c.non_negative("power", *power)?;
            c.rgb("color", color)?;
            if !(cone_angle.is_finite() && *cone_angle > 0.0 && *cone_angle <= std::f32::consts::PI)
            {
                return Err(c.err(
                    "cone_angle",
                    format!("must be in (0, pi] radians, got {cone_angle}"),
                ));
            }
            c.range("blend", *blend, 0.0, 1.0)?;
            c.non_negative("radius", *radius)
        }
        LightDesc::Rect {
            transform,
            width,
            height,
            power,
            color,
            spread,
            ..
        } => {
            c.matrix("transform", transform)?;
            c.positive("width", *width)?;
            c.positive("height", *height)?;
            c.non_negative("power", *power)?;
            c.rgb("color", color)?;
            spread_ok(&c, *spread)
        }
        LightDesc::Disk {
            transform,
            radius,
            radius_y,
            power,
            color,
            spread,
            ..
        } => {
            c.matrix("transform", transform)?;
            c.positive("radius", *radius)?;
            if let Some(ry) = radius_y {
                c.positive("radius_y", *ry)?;
            }
            c.non_negative("power", *power)?;
            c.rgb("color", color)?;
            spread_ok(&c, *spread)
        }
        LightDesc::Sphere {
            position,
            radius,
            power,
            color,
            ..
        } => {
            c.vec3("position", position)?;
            c.positive("radius", *radius)?;
            c.non_negative("power", *power)?;
            c.rgb("color", color)
        }
        LightDesc::Distant {
            direction,
            irradiance,
            color,
            angle,
            ..
        } => {
            c.direction("direction", direction)?;
            c.non_negative("irradiance", *irradiance)?;
            c.rgb("color", color)?;
            c.range("angle", *angle, 0.0, std::f32::consts::PI)
        }
    }
}
