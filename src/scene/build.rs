//! From the validated IR to the render scene: acceleration structure, materials, textures,
//! lights (emissive triangles included), camera.

mod lights;
mod meshes;

use super::camera::Camera;
use super::desc::*;
use crate::error::{Error, Result};
use crate::geometry::{Accel, Instance, Ray, SurfaceInteraction};
use crate::lights::{EnvironmentLight, Light, LightCtx, LightSampler, TriangleLight};
use crate::materials::{texture::Texture, Material};
use crate::math::{Bounds3, Spectrum, Transform};
use crate::media::{GridMedium, Homogeneous, Medium};
use glam::{Vec2, Vec3};
use lights::light_from_desc;
use meshes::{mesh_geom, with_tangents};
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};

pub struct Scene {
    pub accel: Accel,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    pub lights: Vec<Light>,
    pub light_sampler: LightSampler,
    pub camera: Camera,
    pub width: usize,
    pub height: usize,
    /// (instance, triangle) of an emissive triangle -> its light index.
    pub emissive: HashMap<(u32, u32), u32>,
    /// Lights hit by rays that escape the scene (environment, distant lights with an angle).
    pub infinite_lights: Vec<u32>,
    /// Lights with a surface that rays can hit: area lights and point lights with a radius.
    pub hittable_lights: Vec<u32>,
    /// Per light, whether camera rays see its emitter (`LightDesc` `camera_visible`).
    pub light_camera_visible: Vec<bool>,
    pub bounds: Bounds3,
    pub center: Vec3,
    pub radius: f32,
    pub triangle_count: usize,
    pub media: Vec<Medium>,
    pub world_medium: Option<u32>,
    /// Interior medium of each instance of the acceleration structure.
    pub instance_medium: Vec<Option<u32>>,
    /// Media containing the camera, and each light's position (lights at infinity: none).
    pub camera_stack: crate::media::MediumStack,
    pub light_stacks: Vec<crate::media::MediumStack>,
    /// The object name of each instance of the acceleration structure (Cryptomatte object
    /// mattes): its `object`, else its `name`, else `mesh<i>` / `instance<i>`.
    pub instance_names: Vec<String>,
    /// Each material's name (Cryptomatte material mattes), else `material<i>`.
    pub material_names: Vec<String>,
    /// The light groups' names (`SceneDesc::lightgroups`, then `default` when some emitter
    /// is in none); empty without groups.
    pub light_groups: Vec<String>,
    /// Per light, the index of its group in `light_groups` (all 0 without groups).
    pub light_group: Vec<u8>,
    /// What the scene's IR does that renders other than it says, each naming the material
    /// or mesh (`scene::subsurface::warnings`, shading graphs); the stats carry them.
    pub warnings: Vec<String>,
    /// Whether a material lets light pass straight through somewhere (a graph's Transparent
    /// BSDF or Alpha): shadow rays then look through surfaces.
    pub transparent: bool,
    /// Per instance of the acceleration structure, whether its object is a holdout
    /// (`MeshDesc::holdout`); empty when none is.
    pub instance_holdout: Vec<bool>,
    /// Film > Transparent (`FilmDesc::transparent`): the background seen straight by the
    /// camera adds no colour, and makes the image transparent.
    pub film_transparent: bool,
    /// What the materials' shading graphs compiled to.
    pub graph_stats: crate::materials::graph::GraphStats,
    /// Per instance of the acceleration structure, the coordinate systems shading graphs
    /// read; empty when no graph reads them.
    pub objects: Vec<crate::materials::graph::point::ObjectCoords>,
}

/// What a ray found first. Analytic lights are not surfaces: they never occlude, and rays
/// see them through [`Scene::lights_crossed`].
pub enum SceneHit {
    Surface(SurfaceInteraction),
    Miss,
}

/// A ray crossing the emitting side of an analytic light (area, sphere or disk emitter).
#[derive(Clone, Copy, Debug)]
pub struct LightHit {
    pub index: u32,
    /// Ray parameter (in units of the ray's direction vector).
    pub t: f32,
    pub p: Vec3,
    pub n: Vec3,
}

fn v3(a: [f32; 3]) -> Vec3 {
    Vec3::from(a)
}

impl Scene {
    /// Builds the render scene from a scene that `validate` has accepted.
    pub fn build(desc: &SceneDesc) -> Result<Scene> {
        Self::build_cancellable(desc, None)
    }

    /// As [`Scene::build`], returning `Err(Cancelled)` soon after `cancel` is set (it is read
    /// between the steps, before each mesh's BVH and within large BVH builds).
    pub fn build_cancellable(desc: &SceneDesc, cancel: Option<&AtomicBool>) -> Result<Scene> {
        let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
        super::validate(desc)?;
        if cancelled() {
            return Err(Error::Cancelled);
        }
        let textures: Vec<Texture> = desc.textures.iter().map(Texture::from_desc).collect();
        let materials: Vec<Material> = desc
            .materials
            .iter()
            .enumerate()
            .map(|(i, m)| match m {
                crate::scene::desc::MaterialDesc::Graph(g) => {
                    Material::from_graph(g, &format!("/materials/{i}"), textures.len())
                }
                m => Material::from_desc(m),
            })
            .collect();
        // The GGX albedo tables, built once per process here on the caller's thread rather
        // than by the first render worker that needs them.
        crate::materials::layer::SchlickAlbedoTable::get();

        let prototypes: std::collections::HashSet<u32> =
            desc.instances.iter().map(|i| i.mesh).collect();
        let mut meshes = Vec::with_capacity(desc.meshes.len());
        let mut instances = Vec::new();
        let mut instance_medium = Vec::new();
        let mut instance_names = Vec::new();
        let mut instance_holdout = Vec::new();
        // The light group of each instance's emissive triangles.
        let mut instance_group: Vec<Option<u8>> = Vec::new();
        let group_of = |kind: &str, index: usize| -> Option<u8> {
            desc.lightgroups
                .iter()
                .position(|g| {
                    let list = match kind {
                        "lights" => &g.lights,
                        "meshes" => &g.meshes,
                        _ => &g.instances,
                    };
                    list.contains(&(index as u32))
                })
                .map(|i| i as u8)
        };
        let named = |object: &Option<String>, name: &str, fallback: String| match object
            .as_deref()
            .filter(|o| !o.is_empty())
        {
            Some(o) => o.to_string(),
            None if !name.is_empty() => name.to_string(),
            None => fallback,
        };
        let tangent_materials: Vec<bool> = materials
            .iter()
            .map(|m| matches!(m, Material::Graph(g) if g.needs_tangents))
            .collect();
        let mut tangent_meshes = 0;
        for (i, m) in desc.meshes.iter().enumerate() {
            let mut geom = mesh_geom(m);
            tangent_meshes += with_tangents(&mut geom, &tangent_materials) as usize;
            meshes.push(geom);
            let t = Transform::from_rows(&m.transform).unwrap_or_default();
            if !prototypes.contains(&(i as u32)) {
                instances.push(Instance {
                    mesh: i as u32,
                    transform: t,
                });
                instance_medium.push(m.interior_medium);
                instance_names.push(named(&m.object, &m.name, format!("mesh{i}")));
                instance_holdout.push(m.holdout);
                instance_group.push(group_of("meshes", i));
            }
        }
        for (j, inst) in desc.instances.iter().enumerate() {
            instance_names.push(named(&inst.object, &inst.name, format!("instance{j}")));
            instance_holdout.push(inst.holdout);
            instance_group
                .push(group_of("instances", j).or_else(|| group_of("meshes", inst.mesh as usize)));
            instance_medium.push(desc.meshes[inst.mesh as usize].interior_medium);
            let mesh_t = Transform::from_rows(&desc.meshes[inst.mesh as usize].transform)
                .unwrap_or_default();
            let t = Transform::from_rows(&inst.transform).unwrap_or_default();
            instances.push(Instance {
                mesh: inst.mesh,
                transform: mesh_t.then(&t),
            });
        }
        let triangle_count = instances
            .iter()
            .map(|i| meshes[i.mesh as usize].indices.len())
            .sum();
        if cancelled() {
            return Err(Error::Cancelled);
        }
        let accel = Accel::build_cancellable(meshes, instances, cancel).ok_or(Error::Cancelled)?;
        let mut bounds = accel.bounds();
        let objects = super::objects::object_coords(desc, &accel, &materials, &instance_names);

        let mut lights = Vec::new();
        // Each light's group; `None` = the default group.
        let mut groups: Vec<Option<u8>> = Vec::new();
        for (i, l) in desc.lights.iter().enumerate() {
            lights.push(light_from_desc(l));
            groups.push(group_of("lights", i));
        }
        for l in &lights {
            match l {
                Light::Point(p) => bounds.extend(p.position),
                Light::Area(a) => bounds.extend(a.center),
                _ => {}
            }
        }
        let (center, radius) = if bounds.is_empty() {
            (Vec3::ZERO, 1.0)
        } else {
            bounds.bounding_sphere()
        };
        let radius = radius.max(1e-6);

        // Emissive triangles.
        let mut emissive = HashMap::new();
        for (ii, inst) in accel.instances().iter().enumerate() {
            let mesh = accel.mesh(inst.mesh);
            for (prim, &mat) in mesh.material_ids.iter().enumerate() {
                if !materials.get(mat as usize).is_some_and(|m| m.is_emissive()) {
                    continue;
                }
                let v = accel.triangle_world(ii as u32, prim as u32);
                let tri = mesh.indices[prim];
                let uv = match &mesh.uvs {
                    Some(uvs) => tri.map(|k| uvs[k as usize]),
                    None => [Vec2::ZERO, Vec2::X, Vec2::Y],
                };
                emissive.insert((ii as u32, prim as u32), lights.len() as u32);
                groups.push(instance_group[ii]);
                lights.push(Light::Triangle(TriangleLight::new(
                    v,
                    uv,
                    mat,
                    ii as u32,
                    prim as u32,
                )));
            }
        }
        if let Some(env) = &desc.environment {
            let tex = env.texture.map(|t| textures[t as usize].clone());
            let scale = Vec3::from(env.color) * env.strength;
            let t = Transform::from_rows(&env.transform).unwrap_or_default();
            lights.push(Light::Environment(EnvironmentLight::new(scale, tex, t)));
            groups.push(
                desc.lightgroups
                    .iter()
                    .position(|g| g.environment)
                    .map(|i| i as u8),
            );
        }
        let ctx = LightCtx {
            materials: &materials,
            textures: &textures,
            objects: &objects,
            scene_center: center,
            scene_radius: radius,
        };
        let powers: Vec<Spectrum> = lights.iter().map(|l| l.power(&ctx)).collect();
        let light_sampler = LightSampler::new(&powers);
        let infinite_lights = (0..lights.len() as u32)
            .filter(|&i| match &lights[i as usize] {
                Light::Environment(_) => true,
                Light::Distant(d) => d.cos_half_angle < 1.0,
                _ => false,
            })
            .collect();
        let hittable_lights = (0..lights.len() as u32)
            .filter(|&i| match &lights[i as usize] {
                Light::Area(_) => true,
                Light::Point(p) => p.radius > 0.0,
                _ => false,
            })
            .collect();

        let warnings = super::subsurface::warnings(desc)
            .into_iter()
            .chain(materials.iter().flat_map(|m| match m {
                Material::Graph(g) => g.warnings().to_vec(),
                _ => Vec::new(),
            }))
            .collect();
        let mut graph_stats = crate::materials::graph::GraphStats {
            tangent_meshes,
            ..Default::default()
        };
        for (d, m) in desc.materials.iter().zip(&materials) {
            if let crate::scene::desc::MaterialDesc::Graph(_) = d {
                graph_stats.graphs += 1;
                match m {
                    Material::Graph(g) => {
                        graph_stats.instructions += g.instructions();
                        graph_stats.leaves += g.leaves();
                    }
                    _ => graph_stats.folded += 1,
                }
            }
        }
        let transparent = materials
            .iter()
            .any(|m| matches!(m, Material::Graph(g) if g.can_pass()));
        // The IR's lights come first; emissive triangles and the environment follow.
        let lights_len = lights.len();
        let mut scene = Scene {
            accel,
            materials,
            textures,
            lights,
            light_sampler,
            camera: Camera::new(&desc.camera, &desc.film),
            width: desc.film.width as usize,
            height: desc.film.height as usize,
            film_transparent: desc.film.transparent,
            instance_holdout: if instance_holdout.contains(&true) {
                instance_holdout
            } else {
                Vec::new()
            },
            emissive,
            infinite_lights,
            hittable_lights,
            light_camera_visible: desc
                .lights
                .iter()
                .map(LightDesc::camera_visible)
                .chain(std::iter::repeat(true))
                .take(lights_len)
                .collect(),
            bounds,
            center,
            radius,
            triangle_count,
            media: desc.media.iter().map(medium_from_desc).collect(),
            world_medium: desc.world_medium,
            instance_medium,
            camera_stack: Default::default(),
            light_stacks: Vec::new(),
            instance_names,
            light_groups: Vec::new(),
            light_group: Vec::new(),
            warnings,
            transparent,
            graph_stats,
            objects,
            material_names: desc
                .materials
                .iter()
                .enumerate()
                .map(|(i, m)| match m.name() {
                    "" => format!("material{i}"),
                    n => n.to_string(),
                })
                .collect(),
        };
        (scene.light_groups, scene.light_group) = light_groups(desc, &groups);
        scene.camera_stack = scene.medium_stack_at(scene.camera.position());
        scene.light_stacks = scene
            .lights
            .iter()
            .map(|l| match l {
                Light::Point(p) => scene.medium_stack_at(p.position),
                Light::Area(a) => scene.medium_stack_at(a.center),
                Light::Triangle(t) => scene.medium_stack_at((t.v[0] + t.v[1] + t.v[2]) / 3.0),
                _ => Default::default(),
            })
            .collect();
        Ok(scene)
    }

    pub fn light_ctx(&self) -> LightCtx<'_> {
        LightCtx {
            materials: &self.materials,
            textures: &self.textures,
            objects: &self.objects,
            scene_center: self.center,
            scene_radius: self.radius,
        }
    }

    /// Closest surface along the ray.
    pub fn intersect(&self, ray: &Ray) -> SceneHit {
        match self.accel.intersect(ray) {
            Some(h) => SceneHit::Surface(self.accel.interaction(ray, &h)),
            None => SceneHit::Miss,
        }
    }

    /// Every analytic light whose emitting side the ray crosses before `t_end` (in units of
    /// the ray's direction), in no particular order. Cycles draws lights this way: a ray
    /// adds what each light it crosses emits towards its origin and goes on.
    pub fn lights_crossed(&self, ray: &Ray, t_end: f32, mut f: impl FnMut(LightHit)) {
        for &i in &self.hittable_lights {
            let hit = match &self.lights[i as usize] {
                Light::Area(a) => a.intersect(ray.o, ray.d, t_end).map(|t| (t, a.n)),
                Light::Point(p) => p.intersect(ray.o, ray.d, t_end),
                _ => None,
            };
            if let Some((t, n)) = hit {
                f(LightHit {
                    index: i,
                    t,
                    p: ray.o + ray.d * t,
                    n,
                });
            }
        }
    }

    /// Radiance leaving an analytic light's surface towards the origin of a ray of
    /// direction `d` that crossed it.
    pub fn light_le(&self, index: u32, d: Vec3) -> Spectrum {
        match &self.lights[index as usize] {
            Light::Area(a) => a.le(d),
            Light::Point(pl) => pl.le(d),
            _ => Spectrum::ZERO,
        }
    }

    /// Radiance arriving along an escaping ray, from every light at infinity.
    pub fn background(&self, d: Vec3) -> Spectrum {
        self.infinite_lights
            .iter()
            .map(|&i| self.infinite_le(i, d))
            .sum()
    }

    /// Radiance arriving along an escaping ray of direction `d` from the light at infinity
    /// `index` (one of `infinite_lights`).
    pub fn infinite_le(&self, index: u32, d: Vec3) -> Spectrum {
        match &self.lights[index as usize] {
            Light::Environment(e) => e.le(d),
            Light::Distant(l) => l.le(d),
            _ => Spectrum::ZERO,
        }
    }

    /// Whether some material scatters below its surface.
    pub fn has_subsurface(&self) -> bool {
        self.materials.iter().any(|m| m.subsurface().is_some())
    }

    /// Whether any ray can travel through a participating medium.
    pub fn has_media(&self) -> bool {
        !self.media.is_empty()
            && (self.world_medium.is_some() || self.instance_medium.iter().any(Option::is_some))
    }
}

/// The group names and each light's group index: the IR's groups in order, then `default`
/// for the emitters in none (`lightgroups::light_group_names`). Without groups: no names, every
/// light 0.
fn light_groups(desc: &SceneDesc, groups: &[Option<u8>]) -> (Vec<String>, Vec<u8>) {
    let given: Vec<String> = desc.lightgroups.iter().map(|g| g.name.clone()).collect();
    let names = super::lightgroups::light_group_names(&given);
    let default = super::lightgroups::DEFAULT_LIGHTGROUP;
    let fallback = names.iter().position(|n| n == default).unwrap_or(0);
    let index = groups.iter().map(|g| g.unwrap_or(fallback as u8)).collect();
    (names, index)
}

fn medium_from_desc(m: &MediumDesc) -> Medium {
    let (sa, ss) = (Vec3::from(m.sigma_a), Vec3::from(m.sigma_s));
    match &m.density {
        None => Medium::Homogeneous(Homogeneous::new(sa, ss, m.g)),
        Some(grid) => {
            let t = Transform::from_rows(&grid.transform).unwrap_or_default();
            Medium::Grid(GridMedium::new(
                sa,
                ss,
                m.g,
                grid.resolution,
                grid.data.clone(),
                t,
            ))
        }
    }
}
