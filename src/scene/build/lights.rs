//! The IR's lights as render lights.

use super::v3;
use crate::lights::{AreaLight, AreaShape, DistantLight, Light, PointLight, SpotShape};
use crate::math::{Spectrum, Transform};
use crate::scene::desc::*;
use glam::Vec3;

pub(super) fn light_from_desc(l: &LightDesc) -> Light {
    match l {
        LightDesc::Point {
            position,
            power,
            color,
            radius,
            soft_falloff,
            ..
        } => Light::Point(PointLight::new(
            v3(*position),
            *power,
            v3(*color),
            *radius,
            None,
            *soft_falloff,
        )),
        LightDesc::Sphere {
            position,
            radius,
            power,
            color,
            ..
        } => Light::Point(PointLight::new(
            v3(*position),
            *power,
            v3(*color),
            *radius,
            None,
            false,
        )),
        LightDesc::Spot {
            position,
            direction,
            power,
            color,
            cone_angle,
            blend,
            radius,
            soft_falloff,
            ..
        } => {
            let spot = SpotShape::new(v3(*direction), *cone_angle, *blend);
            Light::Point(PointLight::new(
                v3(*position),
                *power,
                v3(*color),
                *radius,
                Some(spot),
                *soft_falloff,
            ))
        }
        LightDesc::Rect {
            transform,
            width,
            height,
            power,
            color,
            two_sided,
            spread,
            ..
        } => area_light(
            AreaShape::Rect,
            transform,
            0.5 * width,
            0.5 * height,
            *power,
            v3(*color),
            *two_sided,
            *spread,
        ),
        LightDesc::Disk {
            transform,
            radius,
            radius_y,
            power,
            color,
            two_sided,
            spread,
            ..
        } => area_light(
            AreaShape::Disk,
            transform,
            *radius,
            radius_y.unwrap_or(*radius),
            *power,
            v3(*color),
            *two_sided,
            *spread,
        ),
        LightDesc::Distant {
            direction,
            irradiance,
            color,
            angle,
            ..
        } => Light::Distant(DistantLight::new(
            v3(*direction),
            *irradiance,
            v3(*color),
            *angle,
        )),
    }
}

fn area_light(
    shape: AreaShape,
    m: &Matrix,
    hx: f32,
    hy: f32,
    power: f32,
    color: Spectrum,
    two_sided: bool,
    spread: f32,
) -> Light {
    let t = Transform::from_rows(m).unwrap_or_default();
    let center = t.point(Vec3::ZERO);
    let ex = t.vector(Vec3::X * hx);
    let ey = t.vector(Vec3::Y * hy);
    let n = t.normal(-Vec3::Z);
    Light::Area(AreaLight::new(
        shape, center, ex, ey, n, power, color, two_sided, spread,
    ))
}
