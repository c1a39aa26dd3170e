//! Checks a scene IR before anything is built from it. Every error names the field by JSON
//! pointer and the object by name; nothing here panics on any input.

mod lights;
mod mesh;

use super::desc::*;
use crate::error::{Error, Result};
use crate::math::Transform;
use lights::{validate_light, validate_lightgroups};
use mesh::validate_mesh;

struct Ctx<'a> {
    ptr: String,
    object: &'a str,
}

impl<'a> Ctx<'a> {
    fn new(ptr: String, object: &'a str) -> Self {
        Ctx { ptr, object }
    }
    fn err(&self, field: &str, msg: impl Into<String>) -> Error {
        let pointer = if field.is_empty() {
            self.ptr.clone()
        } else {
            format!("{}/{}", self.ptr, field)
        };
        Error::scene(pointer, self.object, msg)
    }
    fn finite(&self, field: &str, v: f32) -> Result<()> {
        if v.is_finite() {
            Ok(())
        } else {
            Err(self.err(field, format!("must be finite, got {v}")))
        }
    }
    fn non_negative(&self, field: &str, v: f32) -> Result<()> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(self.err(field, format!("must be a finite number >= 0, got {v}")))
        }
    }
    fn positive(&self, field: &str, v: f32) -> Result<()> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(self.err(field, format!("must be a finite number > 0, got {v}")))
        }
    }
    fn range(&self, field: &str, v: f32, lo: f32, hi: f32) -> Result<()> {
        if v.is_finite() && v >= lo && v <= hi {
            Ok(())
        } else {
            Err(self.err(field, format!("must be in [{lo}, {hi}], got {v}")))
        }
    }
    fn rgb(&self, field: &str, c: &Rgb) -> Result<()> {
        for (i, v) in c.iter().enumerate() {
            self.non_negative(&format!("{field}/{i}"), *v)?;
        }
        Ok(())
    }
    fn vec3(&self, field: &str, c: &[f32; 3]) -> Result<()> {
        for (i, v) in c.iter().enumerate() {
            if !v.is_finite() {
                self.finite(&format!("{field}/{i}"), *v)?;
            }
        }
        Ok(())
    }
    fn direction(&self, field: &str, c: &[f32; 3]) -> Result<()> {
        self.vec3(field, c)?;
        let l2 = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
        if l2 > 1e-20 && l2.is_finite() {
            Ok(())
        } else {
            Err(self.err(field, "must be a non-zero direction"))
        }
    }
    fn matrix(&self, field: &str, m: &Matrix) -> Result<()> {
        for (r, row) in m.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                self.finite(&format!("{field}/{r}/{c}"), *v)?;
            }
        }
        if Transform::from_rows(m).is_none() {
            return Err(self.err(field, "matrix is singular (zero scale?)"));
        }
        Ok(())
    }
    fn texture_ref(&self, field: &str, t: u32, scene: &SceneDesc) -> Result<()> {
        if (t as usize) < scene.textures.len() {
            Ok(())
        } else {
            Err(self.err(
                field,
                format!(
                    "texture index {t} out of range ({} textures)",
                    scene.textures.len()
                ),
            ))
        }
    }
    fn color_input(&self, field: &str, c: &ColorInput, scene: &SceneDesc) -> Result<()> {
        match c {
            ColorInput::Value(v) => self.rgb(field, v),
            ColorInput::Texture { texture, scale } => {
                self.texture_ref(&format!("{field}/texture"), *texture, scene)?;
                self.rgb(&format!("{field}/scale"), scale)
            }
        }
    }
    fn float_input(
        &self,
        field: &str,
        f: &FloatInput,
        lo: f32,
        hi: f32,
        scene: &SceneDesc,
    ) -> Result<()> {
        match f {
            FloatInput::Value(v) => self.range(field, *v, lo, hi),
            FloatInput::Texture {
                texture,
                channel,
                scale,
            } => {
                self.texture_ref(&format!("{field}/texture"), *texture, scene)?;
                let chans = scene.textures[*texture as usize].channels;
                if *channel >= chans {
                    return Err(self.err(
                        &format!("{field}/channel"),
                        format!("channel {channel} but the texture has {chans}"),
                    ));
                }
                self.non_negative(&format!("{field}/scale"), *scale)
            }
        }
    }
}

/// Validates the whole scene.
pub fn validate(scene: &SceneDesc) -> Result<()> {
    validate_camera(&scene.camera, &scene.film)?;
    for (i, t) in scene.textures.iter().enumerate() {
        validate_texture(i, t)?;
    }
    for (i, m) in scene.materials.iter().enumerate() {
        validate_material(i, m, scene)?;
    }
    for (i, m) in scene.media.iter().enumerate() {
        let c = Ctx::new(format!("/media/{i}"), &m.name);
        c.rgb("sigma_a", &m.sigma_a)?;
        c.rgb("sigma_s", &m.sigma_s)?;
        for (k, v) in m.sigma_a.iter().chain(m.sigma_s.iter()).enumerate() {
            if *v > 1e8 {
                let field = if k < 3 {
                    format!("sigma_a/{k}")
                } else {
                    format!("sigma_s/{}", k - 3)
                };
                return Err(c.err(&field, format!("must be at most 1e8, got {v}")));
            }
        }
        if !(m.g.is_finite() && m.g > -1.0 && m.g < 1.0) {
            return Err(c.err("g", format!("must be in (-1, 1), got {}", m.g)));
        }
        if let Some(grid) = &m.density {
            validate_grid(&c, m, grid)?;
        }
    }
    if let Some(w) = scene.world_medium {
        if w as usize >= scene.media.len() {
            return Err(Error::scene(
                "/world_medium",
                "",
                format!(
                    "medium index {w} out of range ({} media)",
                    scene.media.len()
                ),
            ));
        }
    }
    for (i, m) in scene.meshes.iter().enumerate() {
        validate_mesh(i, m, scene)?;
    }
    for (i, inst) in scene.instances.iter().enumerate() {
        let c = Ctx::new(format!("/instances/{i}"), &inst.name);
        if inst.mesh as usize >= scene.meshes.len() {
            return Err(c.err(
                "mesh",
                format!(
                    "mesh index {} out of range ({} meshes)",
                    inst.mesh,
                    scene.meshes.len()
                ),
            ));
        }
        c.matrix("transform", &inst.transform)?;
    }
    for (i, l) in scene.lights.iter().enumerate() {
        validate_light(i, l)?;
    }
    if let Some(env) = &scene.environment {
        let c = Ctx::new("/environment".into(), "");
        c.rgb("color", &env.color)?;
        c.non_negative("strength", env.strength)?;
        c.matrix("transform", &env.transform)?;
        if let Some(t) = env.texture {
            c.texture_ref("texture", t, scene)?;
        }
    }
    validate_lightgroups(scene)
}

fn validate_grid(c: &Ctx, m: &MediumDesc, grid: &DensityGridDesc) -> Result<()> {
    let [x, y, z] = grid.resolution;
    if x == 0 || y == 0 || z == 0 {
        return Err(c.err(
            "density/resolution",
            format!("must be at least 1 voxel per axis, got {x}x{y}x{z}"),
        ));
    }
    let n = x as u64 * y as u64 * z as u64;
    if n > (1 << 28) {
        return Err(c.err(
            "density/resolution",
            format!("{n} voxels is more than the 2^28 supported"),
        ));
    }
    if grid.data.len() as u64 != n {
        return Err(c.err(
            "density/data",
            format!("has {} values, expected {x}x{y}x{z} = {n}", grid.data.len()),
        ));
    }
    if let Some(j) = grid.data.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        return Err(c.err(
            &format!("density/data/{j}"),
            format!("must be a finite number >= 0, got {}", grid.data[j]),
        ));
    }
    c.matrix("density/transform", &grid.transform)?;
    let st = [0, 1, 2].map(|k| m.sigma_a[k] + m.sigma_s[k]);
    let spread =
        st.iter().cloned().fold(f32::MIN, f32::max) - st.iter().cloned().fold(f32::MAX, f32::min);
    if spread > 1e-6 * st[0].abs().max(1e-30) {
        return Err(c.err(
            "sigma_s",
            format!("a medium with a density grid needs a grey extinction sigma_a + sigma_s, got {st:?}"),
        ));
    }
    Ok(())
}

fn validate_camera(cam: &CameraDesc, film: &FilmDesc) -> Result<()> {
    let c = Ctx::new("/camera".into(), "");
    c.matrix("transform", &cam.transform)?;
    if let Some(fov) = cam.fov {
        if !(fov.is_finite() && fov > 0.0 && fov < std::f32::consts::PI) {
            return Err(c.err("fov", format!("must be in (0, pi) radians, got {fov}")));
        }
    }
    c.positive("focal_length", cam.focal_length)?;
    c.positive("sensor_width", cam.sensor_width)?;
    if let Some(h) = cam.sensor_height {
        c.positive("sensor_height", h)?;
    }
    c.finite("shift/0", cam.shift[0])?;
    c.finite("shift/1", cam.shift[1])?;
    c.non_negative("near", cam.near)?;
    if !(cam.far > cam.near) {
        return Err(c.err(
            "far",
            format!("must be greater than near ({}), got {}", cam.near, cam.far),
        ));
    }
    if let Some(f) = cam.fstop {
        c.non_negative("fstop", f)?;
    }
    if let Some(d) = cam.focus_distance {
        c.positive("focus_distance", d)?;
    }
    c.positive("units_per_mm", cam.units_per_mm)?;
    let f = Ctx::new("/film".into(), "");
    for (name, v) in [("width", film.width), ("height", film.height)] {
        if v == 0 || v > 65536 {
            return Err(f.err(name, format!("must be in 1..=65536, got {v}")));
        }
    }
    Ok(())
}

fn validate_texture(i: usize, t: &TextureDesc) -> Result<()> {
    let c = Ctx::new(format!("/textures/{i}"), &t.name);
    if t.width == 0 || t.height == 0 {
        return Err(c.err("", format!("empty texture {}x{}", t.width, t.height)));
    }
    if !matches!(t.channels, 1 | 3 | 4) {
        return Err(c.err("channels", format!("must be 1, 3 or 4, got {}", t.channels)));
    }
    let expected = t.width as u64 * t.height as u64 * t.channels as u64;
    if t.data.len() as u64 != expected {
        return Err(c.err(
            "data",
            format!(
                "has {} values, expected width*height*channels = {expected}",
                t.data.len()
            ),
        ));
    }
    if let Some(j) = t.data.iter().position(|v| !v.is_finite()) {
        return Err(c.err(
            &format!("data/{j}"),
            format!("must be finite, got {}", t.data[j]),
        ));
    }
    Ok(())
}

fn validate_material(i: usize, m: &MaterialDesc, scene: &SceneDesc) -> Result<()> {
    let c = Ctx::new(format!("/materials/{i}"), m.name());
    match m {
        MaterialDesc::Diffuse { color, .. } => c.color_input("color", color, scene),
        MaterialDesc::Mirror { color, .. } => c.rgb("color", color),
        MaterialDesc::Conductor {
            eta, k, roughness, ..
        } => {
            c.rgb("eta", eta)?;
            c.rgb("k", k)?;
            c.range("roughness", *roughness, 0.0, 1.0)
        }
        MaterialDesc::Dielectric {
            ior,
            roughness,
            color,
            ..
        } => {
            c.range("ior", *ior, 1.0, 10.0)?;
            c.range("roughness", *roughness, 0.0, 1.0)?;
            c.rgb("color", color)
        }
        MaterialDesc::Glossy {
            color, roughness, ..
        } => {
            c.rgb("color", color)?;
            c.range("roughness", *roughness, 0.0, 1.0)
        }
        MaterialDesc::Emission {
            color, strength, ..
        } => {
            c.color_input("color", color, scene)?;
            c.non_negative("strength", *strength)
        }
        MaterialDesc::Null { .. } => Ok(()),
        MaterialDesc::Graph(g) => crate::materials::graph::ShaderGraph::new(
            g,
            &format!("/materials/{i}"),
            scene.textures.len(),
        )
        .map(|_| ()),
        MaterialDesc::Principled(p) => {
            c.color_input("base_color", &p.base_color, scene)?;
            c.float_input("metallic", &p.metallic, 0.0, 1.0, scene)?;
            c.float_input("roughness", &p.roughness, 0.0, 1.0, scene)?;
            c.range("transmission", p.transmission, 0.0, 1.0)?;
            c.range("ior", p.ior, 1.0, 10.0)?;
            c.range("specular", p.specular, 0.0, 10.0)?;
            c.color_input("emission_color", &p.emission_color, scene)?;
            c.non_negative("emission_strength", p.emission_strength)?;
            c.range("coat_weight", p.coat_weight, 0.0, 1.0)?;
            c.range("coat_roughness", p.coat_roughness, 0.0, 1.0)?;
            c.range("coat_ior", p.coat_ior, 1.0, 10.0)?;
            c.rgb("coat_tint", &p.coat_tint)
        }
    }
}
