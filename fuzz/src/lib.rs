//! Shared code of the fuzz targets: the tiny render every input goes through, the check on
//! its output, and the structured scene generator of `ir_builder`.

use arbitrary::{Arbitrary, Result, Unstructured};
use photonmap::render::aov::Term;
use photonmap::render::settings::{Bytes, FilterName};
use photonmap::render::{RenderOutput, RenderSettings, Renderer};
use photonmap::scene::desc::*;
use photonmap::scene::{Scene, SceneDesc};

/// 1 sample per pixel, ~100 photons per map, a few gather rays, one thread, 256 MiB limit.
pub fn tiny_settings() -> RenderSettings {
    RenderSettings {
        spp: 1,
        seed: 7,
        threads: 1,
        max_specular_depth: 4,
        filter: FilterName::Box,
        photons: 100,
        caustic_photons: 100,
        volume_photons: 100,
        gather: 16,
        final_gather_rays: 4,
        max_bounces: 16,
        memory_limit: Some(Bytes(256 << 20)),
        ..Default::default()
    }
}

/// Builds and renders `desc` at 8x8 (the film of the scene is replaced). Errors are fine; a
/// panic is the bug. When it renders, every pixel of every AOV must be finite and >= 0.
pub fn tiny_render(desc: &SceneDesc) -> Option<RenderOutput> {
    let mut desc = desc.clone();
    desc.film = FilmDesc {
        width: 8,
        height: 8,
        transparent: false,
    };
    let scene = Scene::build(&desc).ok()?;
    let out = Renderer::new(&scene)
        .settings(tiny_settings())
        .render()
        .ok()?;
    check_finite(&out);
    Some(out)
}

pub fn check_finite(out: &RenderOutput) {
    for t in Term::ALL {
        for (i, p) in out.film.term(t).data.iter().enumerate() {
            assert!(
                p.iter().all(|c| c.is_finite() && *c >= 0.0),
                "{} pixel {i} = {p:?}",
                t.name()
            );
        }
    }
    for (i, a) in out.film.alpha.iter().enumerate() {
        assert!((0.0..=1.0).contains(a), "alpha of pixel {i} = {a}");
    }
}

// ---------------------------------------------------------------------------------------
// Structured scenes for `ir_builder`.

/// A float that is usually ordinary and sometimes NaN, infinite, huge, tiny or negative.
#[derive(Debug, Clone, Copy)]
pub struct F(pub f32);

impl<'a> Arbitrary<'a> for F {
    fn arbitrary(u: &mut Unstructured<'a>) -> Result<Self> {
        let sel = u8::arbitrary(u)?;
        Ok(F(match sel % 40 {
            0 => f32::NAN,
            1 => f32::INFINITY,
            2 => f32::NEG_INFINITY,
            3 => 1e30,
            4 => -1e30,
            5 => f32::MAX,
            6 => f32::MIN_POSITIVE,
            7 => 1e-30,
            8 => -0.0,
            9 => 0.0,
            10 => 1e8,
            11 => 1e-8,
            12 => f32::from_bits(u32::arbitrary(u)?),
            13 => -(u8::arbitrary(u)? as f32) / 16.0,
            _ => i16::arbitrary(u)? as f32 / 4096.0,
        }))
    }
}

/// A non-negative value in [0, 8] most of the time.
#[derive(Debug, Clone, Copy)]
pub struct P(pub f32);

impl<'a> Arbitrary<'a> for P {
    fn arbitrary(u: &mut Unstructured<'a>) -> Result<Self> {
        if u8::arbitrary(u)? < 230 {
            Ok(P(u8::arbitrary(u)? as f32 / 32.0))
        } else {
            Ok(P(F::arbitrary(u)?.0))
        }
    }
}

fn rgb(c: [P; 3]) -> Rgb {
    c.map(|v| v.0)
}
fn v3(c: [F; 3]) -> [f32; 3] {
    c.map(|v| v.0)
}

#[derive(Debug, Arbitrary)]
pub enum Xf {
    Identity,
    Translate([F; 3]),
    Scale(F, [F; 3]),
    /// Rotation about z by an angle, then a translation.
    Rotate(F, [F; 3]),
    Raw([[F; 4]; 4]),
}

impl Xf {
    fn matrix(&self) -> Matrix {
        let mut m = IDENTITY;
        match self {
            Xf::Identity => {}
            Xf::Translate(t) => {
                for r in 0..3 {
                    m[r][3] = t[r].0;
                }
            }
            Xf::Scale(s, t) => {
                for r in 0..3 {
                    m[r][r] = s.0;
                    m[r][3] = t[r].0;
                }
            }
            Xf::Rotate(a, t) => {
                let (s, c) = a.0.sin_cos();
                m[0][0] = c;
                m[0][1] = -s;
                m[1][0] = s;
                m[1][1] = c;
                for r in 0..3 {
                    m[r][3] = t[r].0;
                }
            }
            Xf::Raw(r) => m = r.map(|row| row.map(|v| v.0)),
        }
        m
    }
}

#[derive(Debug, Arbitrary)]
pub enum Shape {
    /// An axis-aligned box of half-size `s` at `c` (closed: can hold a medium).
    Cube { c: [F; 3], s: F },
    /// A quad facing +z.
    Quad { c: [F; 3], s: F },
    /// Free triangles over arbitrary points; indices may be out of range.
    Soup {
        points: Vec<[F; 3]>,
        tris: Vec<[u8; 3]>,
    },
    /// Every vertex at one point.
    Degenerate { p: [F; 3], n: u8 },
}

#[derive(Debug, Arbitrary)]
pub struct Mesh {
    shape: Shape,
    material: u8,
    per_triangle: Option<Vec<u8>>,
    normals: Option<Vec<[F; 3]>>,
    /// Normals or UVs with one entry too few.
    short_attrs: bool,
    uvs: Option<Vec<[F; 2]>>,
    transform: Xf,
    interior_medium: Option<u8>,
}

fn cube(c: [f32; 3], s: f32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let mut p = Vec::new();
    for i in 0..8 {
        let sx = if i & 1 == 0 { -s } else { s };
        let sy = if i & 2 == 0 { -s } else { s };
        let sz = if i & 4 == 0 { -s } else { s };
        p.push([c[0] + sx, c[1] + sy, c[2] + sz]);
    }
    let idx = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    (p, idx)
}

impl Mesh {
    fn desc(&self, i: usize) -> MeshDesc {
        let (positions, indices) = match &self.shape {
            Shape::Cube { c, s } => cube(v3(*c), s.0),
            Shape::Quad { c, s } => {
                let c = v3(*c);
                let s = s.0;
                (
                    vec![
                        [c[0] - s, c[1] - s, c[2]],
                        [c[0] + s, c[1] - s, c[2]],
                        [c[0] + s, c[1] + s, c[2]],
                        [c[0] - s, c[1] + s, c[2]],
                    ],
                    vec![[0, 1, 2], [0, 2, 3]],
                )
            }
            Shape::Soup { points, tris } => {
                let n = points.len().max(1) as u32;
                (
                    points.iter().take(64).map(|p| v3(*p)).collect(),
                    tris.iter()
                        .take(64)
                        .map(|t| t.map(|k| k as u32 % (n + 1)))
                        .collect(),
                )
            }
            Shape::Degenerate { p, n } => {
                let p = v3(*p);
                let n = (*n % 8) as u32 + 1;
                (vec![p; 3], (0..n).map(|_| [0, 1, 2]).collect())
            }
        };
        let nv = positions.len();
        let short = usize::from(self.short_attrs);
        let attr = |k: usize| (0..nv.saturating_sub(short)).map(move |j| j % k.max(1));
        MeshDesc {
            name: format!("mesh{i}"),
            normals: self.normals.as_ref().map(|ns| {
                attr(ns.len())
                    .map(|j| ns.get(j).map_or([0.0, 0.0, 1.0], |n| v3(*n)))
                    .collect()
            }),
            uvs: self.uvs.as_ref().map(|uv| {
                attr(uv.len())
                    .map(|j| uv.get(j).map_or([0.0, 0.0], |t| [t[0].0, t[1].0]))
                    .collect()
            }),
            material: self.material as u32 % 8,
            material_indices: self.per_triangle.as_ref().map(|m| {
                (0..indices.len())
                    .map(|j| m.get(j).copied().unwrap_or(0) as u32 % 8)
                    .collect()
            }),
            positions,
            indices,
            transform: self.transform.matrix(),
            interior_medium: self.interior_medium.map(|m| m as u32 % 4),
            holdout: self.material & 16 != 0,
            ..Default::default()
        }
    }
}

#[derive(Debug, Arbitrary)]
pub enum Color {
    Value([P; 3]),
    Texture(u8, [P; 3]),
}
impl Color {
    fn desc(&self) -> ColorInput {
        match self {
            Color::Value(c) => ColorInput::Value(rgb(*c)),
            Color::Texture(t, s) => ColorInput::Texture {
                texture: *t as u32 % 4,
                scale: rgb(*s),
            },
        }
    }
}

#[derive(Debug, Arbitrary)]
pub enum Float {
    Value(F),
    Texture(u8, u8, P),
}
impl Float {
    fn desc(&self) -> FloatInput {
        match self {
            Float::Value(v) => FloatInput::Value(unit(*v)),
            Float::Texture(t, c, s) => FloatInput::Texture {
                texture: *t as u32 % 4,
                channel: *c as u32 % 5,
                scale: s.0,
            },
        }
    }
}

/// A unit-interval value most of the time.
fn unit(v: F) -> f32 {
    if v.0.is_finite() && v.0.abs() < 8.0 {
        v.0.abs().fract()
    } else {
        v.0
    }
}

#[derive(Debug, Arbitrary)]
pub enum Material {
    Diffuse(Color),
    Mirror([P; 3]),
    Conductor([P; 3], [P; 3], F),
    Dielectric(F, F, [P; 3]),
    Glossy([P; 3], F),
    Emission(Color, P),
    Null,
    Principled {
        base: Color,
        metallic: Float,
        roughness: Float,
        transmission: F,
        ior: F,
        specular: P,
        emission: Color,
        emission_strength: P,
    },
}

fn ior(v: F) -> f32 {
    if v.0.is_finite() && v.0.abs() < 8.0 {
        1.0 + v.0.abs()
    } else {
        v.0
    }
}

impl Material {
    fn desc(&self) -> MaterialDesc {
        let name = String::new();
        match self {
            Material::Diffuse(c) => MaterialDesc::Diffuse {
                name,
                color: c.desc(),
            },
            Material::Mirror(c) => MaterialDesc::Mirror {
                name,
                color: rgb(*c),
            },
            Material::Conductor(eta, k, r) => MaterialDesc::Conductor {
                name,
                eta: rgb(*eta),
                k: rgb(*k),
                roughness: unit(*r),
            },
            Material::Dielectric(i, r, c) => MaterialDesc::Dielectric {
                name,
                ior: ior(*i),
                roughness: unit(*r),
                color: rgb(*c),
                multiscatter: r.0.to_bits() & 1 == 0,
            },
            Material::Glossy(c, r) => MaterialDesc::Glossy {
                name,
                color: rgb(*c),
                roughness: unit(*r),
                multiscatter: r.0.to_bits() & 1 == 0,
            },
            Material::Emission(c, s) => MaterialDesc::Emission {
                name,
                color: c.desc(),
                strength: s.0,
            },
            Material::Null => MaterialDesc::Null { name },
            Material::Principled {
                base,
                metallic,
                roughness,
                transmission,
                ior: i,
                specular,
                emission,
                emission_strength,
            } => MaterialDesc::Principled(Box::new(PrincipledDesc {
                name,
                base_color: base.desc(),
                metallic: metallic.desc(),
                roughness: roughness.desc(),
                transmission: unit(*transmission),
                ior: ior(*i),
                specular: specular.0,
                emission_color: emission.desc(),
                emission_strength: emission_strength.0,
                multiscatter: specular.0.to_bits() & 1 == 0,
                coat_weight: if specular.0.to_bits() & 2 == 0 {
                    0.0
                } else {
                    unit(*transmission)
                },
                coat_roughness: unit(*transmission) * 0.5,
                coat_ior: ior(*i),
                coat_tint: [1.0, 0.9, 0.8],
                subsurface: None,
            })),
        }
    }
}

#[derive(Debug, Arbitrary)]
pub enum Light {
    Point([F; 3], P, [P; 3], P),
    Spot([F; 3], [F; 3], P, F, F, P),
    Rect(Xf, P, P, P, bool),
    Disk(Xf, P, P, bool),
    Sphere([F; 3], P, P),
    Distant([F; 3], P, F),
}

impl Light {
    fn desc(&self) -> LightDesc {
        let name = String::new();
        let white = [1.0; 3];
        match self {
            Light::Point(p, w, c, r) => LightDesc::Point {
                name,
                position: v3(*p),
                power: w.0 * 100.0,
                color: rgb(*c),
                radius: r.0 / 8.0,
                soft_falloff: w.0.to_bits() & 1 == 1,
                camera_visible: w.0.to_bits() & 2 == 0,
            },
            Light::Spot(p, d, w, cone, blend, r) => LightDesc::Spot {
                name,
                position: v3(*p),
                direction: v3(*d),
                power: w.0 * 100.0,
                color: white,
                cone_angle: if cone.0.is_finite() {
                    cone.0.abs().min(3.2)
                } else {
                    cone.0
                },
                blend: unit(*blend),
                radius: r.0 / 8.0,
                soft_falloff: w.0.to_bits() & 1 == 1,
                camera_visible: true,
            },
            Light::Rect(t, w, h, p, two) => LightDesc::Rect {
                name,
                transform: t.matrix(),
                width: w.0,
                height: h.0,
                power: p.0 * 100.0,
                color: white,
                two_sided: *two,
                spread: if p.0.to_bits() & 1 == 1 {
                    1.0
                } else {
                    std::f32::consts::PI
                },
                camera_visible: true,
            },
            Light::Disk(t, r, p, two) => LightDesc::Disk {
                name,
                transform: t.matrix(),
                radius: r.0,
                radius_y: (p.0.to_bits() & 2 == 2).then_some(0.5 * r.0),
                power: p.0 * 100.0,
                color: white,
                two_sided: *two,
                spread: if p.0.to_bits() & 1 == 1 {
                    0.7
                } else {
                    std::f32::consts::PI
                },
                camera_visible: true,
            },
            Light::Sphere(p, r, w) => LightDesc::Sphere {
                name,
                position: v3(*p),
                radius: r.0,
                power: w.0 * 100.0,
                color: white,
                camera_visible: true,
            },
            Light::Distant(d, e, a) => LightDesc::Distant {
                name,
                direction: v3(*d),
                irradiance: e.0,
                color: white,
                angle: if a.0.is_finite() {
                    a.0.abs().min(3.2)
                } else {
                    a.0
                },
            },
        }
    }
}

#[derive(Debug, Arbitrary)]
pub struct Texture {
    w: u8,
    h: u8,
    channels: u8,
    data: Vec<P>,
    /// Length off by one.
    wrong_len: bool,
    wrap: u8,
}

impl Texture {
    fn desc(&self) -> TextureDesc {
        let (w, h) = (self.w as u32 % 5, self.h as u32 % 5);
        let channels = [1, 3, 4, 2][self.channels as usize % 4];
        let n = (w * h * channels) as usize + usize::from(self.wrong_len);
        TextureDesc {
            name: String::new(),
            width: w,
            height: h,
            channels,
            data: (0..n)
                .map(|j| self.data.get(j).map_or(0.5, |v| v.0))
                .collect(),
            wrap: [
                WrapMode::Repeat,
                WrapMode::Clamp,
                WrapMode::Mirror,
                WrapMode::Black,
            ][self.wrap as usize % 4],
            encoding: if self.wrap & 4 != 0 {
                photonmap::scene::desc::TextureEncoding::Srgb
            } else {
                photonmap::scene::desc::TextureEncoding::Linear
            },
        }
    }
}

#[derive(Debug, Arbitrary)]
pub struct Medium {
    sigma_a: [P; 3],
    sigma_s: [P; 3],
    /// Multiplies both coefficients by 10^(k % 10 - 2).
    density_decade: u8,
    g: F,
    grid: Option<Grid>,
}

/// A density grid: up to 4x4x4 voxels, the data sometimes one value short or long, and the
/// medium's extinction made grey (as a grid requires) unless `coloured`.
#[derive(Debug, Arbitrary)]
pub struct Grid {
    resolution: [u8; 3],
    data: Vec<P>,
    /// -1, 0 or +1 values relative to the resolution's product.
    length_error: u8,
    coloured: bool,
    transform: Xf,
}

impl Grid {
    fn desc(&self) -> DensityGridDesc {
        let resolution = self.resolution.map(|r| r as u32 % 5);
        let n = resolution.iter().product::<u32>() as usize;
        let n = match self.length_error % 8 {
            0 => n.saturating_sub(1),
            1 => n + 1,
            _ => n,
        };
        DensityGridDesc {
            resolution,
            data: (0..n)
                .map(|i| {
                    self.data
                        .get(i % self.data.len().max(1))
                        .map_or(1.0, |v| v.0)
                })
                .collect(),
            transform: self.transform.matrix(),
        }
    }
}

#[derive(Debug, Arbitrary)]
pub struct Camera {
    transform: Option<Xf>,
    fov: Option<F>,
    fstop: Option<P>,
    focus_distance: Option<F>,
    shift: Option<[F; 2]>,
    near: Option<F>,
    far: Option<F>,
}

#[derive(Debug, Arbitrary)]
pub struct Env {
    color: [P; 3],
    strength: P,
    texture: Option<u8>,
    transform: Xf,
}

#[derive(Debug, Arbitrary)]
pub struct FuzzScene {
    camera: Camera,
    meshes: Vec<Mesh>,
    instances: Vec<(u8, Xf)>,
    materials: Vec<Material>,
    textures: Vec<Texture>,
    lights: Vec<Light>,
    environment: Option<Env>,
    media: Vec<Medium>,
    world_medium: Option<u8>,
}

impl FuzzScene {
    /// The scene IR; at most 8 of each kind of object.
    pub fn desc(&self) -> SceneDesc {
        let mut cam = CameraDesc {
            transform: Xf::Translate([F(0.0), F(0.0), F(4.0)]).matrix(),
            fov: Some(0.7),
            ..Default::default()
        };
        let c = &self.camera;
        if let Some(t) = &c.transform {
            cam.transform = t.matrix();
        }
        if let Some(f) = c.fov {
            cam.fov = Some(f.0);
        }
        cam.fstop = c.fstop.map(|f| f.0);
        cam.focus_distance = c.focus_distance.map(|f| f.0);
        if let Some(s) = c.shift {
            cam.shift = [s[0].0, s[1].0];
        }
        if let Some(n) = c.near {
            cam.near = n.0;
        }
        if let Some(f) = c.far {
            cam.far = f.0;
        }
        SceneDesc {
            camera: cam,
            film: FilmDesc {
                width: 8,
                height: 8,
                transparent: self.meshes.len() % 2 == 1,
            },
            meshes: self
                .meshes
                .iter()
                .take(8)
                .enumerate()
                .map(|(i, m)| m.desc(i))
                .collect(),
            instances: self
                .instances
                .iter()
                .take(8)
                .map(|(m, t)| InstanceDesc {
                    name: String::new(),
                    mesh: *m as u32 % 9,
                    transform: t.matrix(),
                    ..Default::default()
                })
                .collect(),
            materials: self.materials.iter().take(8).map(|m| m.desc()).collect(),
            textures: self.textures.iter().take(4).map(|t| t.desc()).collect(),
            lights: self.lights.iter().take(8).map(|l| l.desc()).collect(),
            environment: self.environment.as_ref().map(|e| EnvironmentDesc {
                color: rgb(e.color),
                strength: e.strength.0,
                texture: e.texture.map(|t| t as u32 % 4),
                transform: e.transform.matrix(),
            }),
            media: self
                .media
                .iter()
                .take(4)
                .map(|m| {
                    let k = 10f32.powi((m.density_decade % 10) as i32 - 2);
                    let mut sigma_a = rgb(m.sigma_a).map(|v| v * k);
                    let mut sigma_s = rgb(m.sigma_s).map(|v| v * k);
                    if m.grid.as_ref().is_some_and(|g| !g.coloured) {
                        // Grey extinction, coloured albedo: scale sigma_s per channel.
                        let t = sigma_a[0] + sigma_s[0];
                        for c in 0..3 {
                            let a = sigma_a[c] / (sigma_a[c] + sigma_s[c]).max(1e-6);
                            sigma_a[c] = t * a;
                            sigma_s[c] = t - sigma_a[c];
                        }
                    }
                    MediumDesc {
                        name: String::new(),
                        sigma_a,
                        sigma_s,
                        density: m.grid.as_ref().map(Grid::desc),
                        g: if m.g.0.is_finite() && m.g.0.abs() < 8.0 {
                            m.g.0.fract()
                        } else {
                            m.g.0
                        },
                    }
                })
                .collect(),
            world_medium: self.world_medium.map(|w| w as u32 % 5),
            lightgroups: Vec::new(),
        }
    }
}
