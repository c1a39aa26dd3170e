//! The eye pass: one camera path per sample, split into terms. The path follows perfectly
//! specular bounces; every other surface ends the path, and there the estimators of the
//! `direct`, `caustic` and `indirect` terms run (routed to `specular` after a bounce).

use super::aov::{Term, TermMask};
use super::compositing::{Guides, SampleAovs};
use super::film::TermRadiance;
use super::irradiance_cache::IrradianceCache;
use super::lightgroups::Split;
use super::photons::PhotonMaps;
use super::terms::specular::Follow;
use super::terms::volume::{self, MarchSettings};
use super::terms::{caustic, direct, emission, indirect, specular, subsurface};
use crate::geometry::{Ray, RayPath};
use crate::materials::bsdf::{Bsdf, LobeFlags};
use crate::math::{is_finite3, Spectrum};
use crate::photon::KnnScratch;
use crate::sampling::Rng;
use crate::scene::shading::{Crossing, MAX_TRANSPARENT};
use crate::scene::{Scene, SceneHit};

/// Samples of the environment at the surfaces a camera path reaches (one at final-gather
/// hits, which are many more and each weighs less): see `direct::estimate_with`.
pub const EYE_LIGHT_SAMPLES: u32 = 4;

#[derive(Clone, Copy, Debug)]
pub struct EyeSettings {
    pub terms: TermMask,
    pub max_specular_depth: u32,
    /// Gather rays per record of the irradiance cache.
    pub final_gather_rays: u32,
    /// Gather rays per camera sample where the cache does not apply.
    pub gather_rays_per_sample: u32,
}

/// Everything the eye pass reads.
pub struct EyeCtx<'a> {
    pub scene: &'a Scene,
    /// Counts of the work done, for the stats.
    pub work: &'a crate::render::work::WorkCounts,
    pub maps: &'a PhotonMaps,
    pub cache: Option<&'a IrradianceCache>,
    pub settings: EyeSettings,
    pub march: MarchSettings,
}

/// The camera ray of pixel (x, y) for the sample `u` in [0,1)^2, which `filter` warps into
/// an offset from the pixel centre; the lens sample comes from `rng`.
pub fn camera_ray(
    scene: &Scene,
    filter: &super::film::Filter,
    x: usize,
    y: usize,
    u: glam::Vec2,
    rng: &mut Rng,
) -> Ray {
    let film = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + filter.sample(u);
    let cr = scene.camera.generate_ray(film, rng.vec2());
    Ray {
        o: cr.o,
        d: cr.d,
        t_max: cr.t_max,
    }
}

/// A non-specular point an eye path reached, where progressive photon mapping (`sppm`)
/// estimates the photon terms: the point, its geometric normal on the side of `wo`, the BSDF,
/// the path throughput, and the specular bounces before it (for routing to `specular`).
#[derive(Clone, Copy)]
pub struct VisiblePoint {
    pub p: glam::Vec3,
    pub n: glam::Vec3,
    pub wo: glam::Vec3,
    pub bsdf: Bsdf,
    pub beta: Spectrum,
    pub bounces: u32,
    /// Whether the point is a subsurface walk's exit (its light is `subsurface`).
    pub subsurface: bool,
}

impl VisiblePoint {
    /// The term a photon of flags `flags` gathered here goes to, if any.
    pub fn photon_term(&self, flags: u16) -> Option<Term> {
        let t = super::terms::of_photon(flags, self.bounces)?;
        Some(if self.subsurface { Term::Subsurface } else { t })
    }
}

/// The mean of a colour's channels.
fn average(s: Spectrum) -> f32 {
    (s.x + s.y + s.z) / 3.0
}

/// Radiance along `ray`, per term. Non-finite estimates are dropped (counted by the caller).
/// What the path gives the compositing AOVs that `aovs` asks for goes into it.
pub fn trace(
    ctx: &EyeCtx,
    ray: Ray,
    rng: &mut Rng,
    scratch: &mut KnnScratch,
    aovs: &mut SampleAovs,
) -> TermRadiance {
    trace_split(ctx, ray, rng, scratch, None, aovs)
}

/// The denoising guides at the non-specular surface `si` that a path reaches through
/// specular bounces of tint `tint` (their weights, without Russian roulette): the surface's
/// directional albedo (every lobe's, as Open Image Denoise defines it) times the tint, and
/// its shading normal turned towards the path.
fn guides(si: &crate::geometry::SurfaceInteraction, bsdf: &Bsdf, tint: Spectrum) -> Guides {
    let (d, s, t) = bsdf.rr_reflectivities(si.wo);
    let n = if si.ns.dot(si.wo) < 0.0 {
        -si.ns
    } else {
        si.ns
    };
    Guides {
        albedo: tint * (d + s + t).min(Spectrum::ONE),
        normal: n,
    }
}

/// As [`trace`]; with `visible` given, the caustic and indirect estimators do not run at the
/// non-specular points the path reaches: each point is handed to `visible` instead, for a
/// progressive photon pass to estimate.
pub fn trace_split(
    ctx: &EyeCtx,
    mut ray: Ray,
    rng: &mut Rng,
    scratch: &mut KnnScratch,
    mut visible: Option<&mut dyn FnMut(VisiblePoint)>,
    aovs: &mut SampleAovs,
) -> TermRadiance {
    let scene = ctx.scene;
    let s = &ctx.settings;
    let mut out = TermRadiance::default();
    let mut beta = Spectrum::ONE;
    // The tint of the specular bounces so far, for the denoising guides; `None` once they
    // are recorded (or not asked for).
    let mut guide_tint = aovs.want_guides.then_some(Spectrum::ONE);
    // The kind of ray the path is (the Light Path node's).
    let mut path = RayPath::CAMERA_RAY;
    let want_first_hit = aovs.want_first_hit;
    let (rec_guides, first_hit) = (&mut aovs.guides, &mut aovs.first_hit);
    // How much of the sample the camera sees through to a transparent background or a
    // Holdout (Cycles' `transparent`; the pixel's alpha is one minus its mean).
    let transparent = &mut aovs.transparent;
    // With light groups, each group's share of what the path adds.
    let mut split = (!aovs.groups.is_empty()).then(|| Split::new(&mut aovs.groups));
    // An emitter's share, seen along the path (where finite, as `add` takes it).
    let share = |split: &mut Option<Split>, light: u32, l: Spectrum| {
        if let Some(sp) = split.as_mut() {
            if is_finite3(l) {
                sp.add_light(scene, light, l);
            }
        }
    };
    let mut bounces = 0u32;
    let wants = |term: Term, bounces: u32| s.terms.contains(specular::route(term, bounces));
    let add = |out: &mut TermRadiance, term: Term, bounces: u32, l: Spectrum| {
        let t = specular::route(term, bounces);
        if s.terms.contains(t) && is_finite3(l) {
            out.add(t, l);
        }
    };
    let mut stack = scene.camera_stack;
    let mut crossings = 0u32;
    let mut transparent_hits = 0u32;
    let mut skip_emission = false;
    loop {
        let hit = scene.intersect(&ray);
        let len = ray.d.length();
        let t_end = match &hit {
            SceneHit::Surface(si) => si.t,
            SceneHit::Miss => f32::INFINITY,
        };
        // Analytic lights in front of the hit: seen, and seen through.
        if wants(Term::Emission, bounces) && !skip_emission {
            let medium = stack.current(scene.world_medium);
            scene.lights_crossed(&ray, t_end, |lh| {
                if bounces == 0 && !scene.light_camera_visible[lh.index as usize] {
                    return;
                }
                let tr = match medium {
                    Some(m) => {
                        scene.media[m as usize].transmittance_along(ray.o, ray.d / len, lh.t * len)
                    }
                    None => Spectrum::ONE,
                };
                let l = beta * tr * scene.light_le(lh.index, ray.d);
                add(&mut out, Term::Emission, bounces, l);
                share(&mut split, lh.index, l);
            });
        }
        // Participating medium between the ray origin and the hit: in-scattered light, and
        // attenuation of whatever lies behind.
        if let Some(m) = stack.current(scene.world_medium) {
            let dist = t_end * len;
            let tr = if wants(Term::Volume, bounces) {
                let mut sp = split.as_mut().map(|sp| sp.scaled(beta));
                let mr = volume::march(
                    scene,
                    ctx.maps,
                    m,
                    &stack,
                    ray.o,
                    ray.d / len,
                    dist,
                    &ctx.march,
                    rng,
                    scratch,
                    sp.as_mut(),
                );
                ctx.work
                    .march(mr.steps, mr.volume_lookups, mr.volume_point_reads);
                add(&mut out, Term::Volume, bounces, beta * mr.radiance);
                mr.transmittance
            } else {
                scene.media[m as usize].transmittance_along(ray.o, ray.d / len, dist)
            };
            beta *= tr;
            if beta.max_element() <= 0.0 {
                break;
            }
        }
        match hit {
            SceneHit::Miss => {
                if bounces == 0 && scene.film_transparent {
                    // Film > Transparent: the background the camera sees straight through
                    // transparent surfaces and media is not drawn.
                    *transparent += average(beta);
                } else if !skip_emission {
                    add(
                        &mut out,
                        Term::Emission,
                        bounces,
                        beta * emission::background(scene, ray.d),
                    );
                    if wants(Term::Emission, bounces) {
                        for &i in &scene.infinite_lights {
                            share(&mut split, i, beta * scene.infinite_le(i, ray.d));
                        }
                    }
                }
                break;
            }
            SceneHit::Surface(mut si) => {
                si.path = path;
                let Some(mat) = scene.materials.get(si.material as usize) else {
                    break;
                };
                match scene.crossing(mat, &si, || rng.f32()) {
                    Crossing::Pass(w) => {
                        // An invisible medium boundary or a transparent surface: cross it
                        // and go on.
                        crossings += 1;
                        if !mat.is_null() {
                            transparent_hits += 1;
                            path = path.crossed();
                        }
                        if crossings > 64 || transparent_hits > MAX_TRANSPARENT {
                            break;
                        }
                        beta *= w;
                        scene.update_stack(&mut stack, &si, ray.d);
                        ray = si.spawn_ray(ray.d);
                        continue;
                    }
                    Crossing::Stop(w) => beta *= w,
                }
                if want_first_hit && bounces == 0 && first_hit.is_none() {
                    *first_hit = Some((si.instance, si.material));
                }
                if bounces == 0 {
                    // A Holdout seen straight through transparent surfaces: that share of
                    // the sample is transparent (black, as every Holdout renders). A holdout
                    // object is wholly a Holdout where it is opaque (the ray stopped here:
                    // with the stop's weight, 1 - transparency is that share).
                    if scene.instance_holdout.get(si.instance as usize) == Some(&true) {
                        *transparent +=
                            average(beta) * (1.0 - average(scene.transparency(mat, &si)));
                        break;
                    }
                    let h = scene.holdout(mat, &si);
                    if h > 0.0 {
                        *transparent += average(beta * h);
                        if h >= 1.0 {
                            break;
                        }
                    }
                }
                if !skip_emission {
                    let l = beta * emission::surface_emission(scene, &si);
                    add(&mut out, Term::Emission, bounces, l);
                    if wants(Term::Emission, bounces) && l.max_element() > 0.0 {
                        if let Some(&light) = scene.emissive.get(&(si.instance, si.prim)) {
                            share(&mut split, light, l);
                        }
                    }
                }
                let bsdf = scene.shading_bsdf(mat, &mut si);
                let passes = bsdf.passes_through();
                if let Some(tint) = guide_tint {
                    if bsdf.has_non_delta() || bsdf.is_black() {
                        *rec_guides = Some(guides(&si, &bsdf, tint));
                        guide_tint = None;
                    }
                }
                // The estimates below add their groups' shares times the path's throughput.
                let mut sp = split.as_mut().map(|sp| sp.scaled(beta));
                let entry = bsdf.subsurface_entry(si.wo);
                let here = if entry.is_some() {
                    bsdf.without_subsurface()
                } else {
                    bsdf
                };
                if here.has_non_delta() {
                    let at = Estimates {
                        si: &si,
                        bsdf: &here,
                        beta,
                        bounces,
                        subsurface: false,
                    };
                    at.run(
                        ctx,
                        &stack,
                        passes,
                        &mut out,
                        &mut visible,
                        rng,
                        scratch,
                        sp.as_mut(),
                    );
                }
                if let (Some((w, roughness)), Some(ss)) = (entry, mat.subsurface()) {
                    if s.terms.contains(Term::Subsurface) {
                        if let Some(exit) = subsurface::walk(scene, &si, ss, roughness, rng) {
                            ctx.work.subsurface_walk(exit.events as u64);
                            let b = beta * w * exit.weight;
                            let mut sp = split.as_mut().map(|sp| sp.scaled(b));
                            let at = Estimates {
                                si: &exit.si,
                                bsdf: &exit.bsdf,
                                beta: b,
                                bounces,
                                subsurface: true,
                            };
                            at.run(
                                ctx,
                                &stack,
                                false,
                                &mut out,
                                &mut visible,
                                rng,
                                scratch,
                                sp.as_mut(),
                            );
                        } else {
                            ctx.work.subsurface_walk_lost();
                        }
                    }
                }
                if bounces >= s.max_specular_depth {
                    break;
                }
                // The non-delta part was estimated above.
                let Some(bs) = specular::next_bounce(&bsdf, si.wo, Follow::Specular, rng) else {
                    break;
                };
                // After a rough-glass bounce the emitter it reaches was counted by that
                // vertex's direct estimate (light and BSDF samples, MIS).
                skip_emission = !bs.is_delta();
                path = bs.next_path(path);
                beta *= bs.weight;
                if let Some(tint) = guide_tint.as_mut() {
                    *tint *= bs.weight;
                }
                bounces += 1;
                match specular::continue_chain(beta, bounces, rng.f32()) {
                    Some(b) => beta = b,
                    None => break,
                }
                if bs.flags & LobeFlags::TRANSMISSION != 0 {
                    scene.update_stack(&mut stack, &si, bs.wi);
                }
                ray = si.spawn_ray(bs.wi);
            }
        }
    }
    out
}

/// A non-delta surface point where a camera path's estimates run, and what they are weighted
/// by.
struct Estimates<'a> {
    si: &'a crate::geometry::SurfaceInteraction,
    bsdf: &'a Bsdf,
    beta: Spectrum,
    bounces: u32,
    /// Whether the point is a subsurface walk's exit.
    subsurface: bool,
}

impl Estimates<'_> {
    /// Where the estimate of `term` goes: `subsurface` at a walk's exit, else as
    /// [`specular::route`] says.
    fn route(&self, term: Term) -> Term {
        if self.subsurface {
            Term::Subsurface
        } else {
            specular::route(term, self.bounces)
        }
    }

    /// The `direct`, `caustic` and `indirect` estimates at the point, each added to `out`
    /// under its term (`route`); with `visible`, the point is handed to it for the photon
    /// terms instead. `passes`: rough glass, which the path goes on through (only the direct
    /// estimate runs).
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        ctx: &EyeCtx,
        stack: &crate::media::MediumStack,
        passes: bool,
        out: &mut TermRadiance,
        visible: &mut Option<&mut dyn FnMut(VisiblePoint)>,
        rng: &mut Rng,
        scratch: &mut KnnScratch,
        mut sp: Option<&mut Split>,
    ) {
        let terms = ctx.settings.terms;
        let wants = |t: Term| terms.contains(self.route(t));
        let mut add = |t: Term, l: Spectrum| {
            let t = self.route(t);
            if terms.contains(t) && is_finite3(l) {
                out.add(t, l);
            }
        };
        let (si, bsdf, beta) = (self.si, self.bsdf, self.beta);
        if wants(Term::Direct) {
            let l = direct::estimate_with(
                ctx.scene,
                si,
                bsdf,
                stack,
                EYE_LIGHT_SAMPLES,
                rng,
                sp.as_deref_mut(),
            );
            add(Term::Direct, beta * l);
        }
        if passes {
            // Rough glass: the path goes on through it; what reaches it from the lights was
            // estimated just above.
            return;
        }
        if let Some(record) = visible.as_mut() {
            if wants(Term::Caustic) || wants(Term::Indirect) {
                record(VisiblePoint {
                    p: si.p,
                    n: si.ng,
                    wo: si.wo,
                    bsdf: *bsdf,
                    beta,
                    bounces: self.bounces,
                    subsurface: self.subsurface,
                });
            }
            return;
        }
        if wants(Term::Caustic) && ctx.maps.caustic.is_some() {
            ctx.work.caustic_lookup();
            let l = caustic::estimate(ctx.maps, si, bsdf, scratch, sp.as_deref_mut());
            add(Term::Caustic, beta * l);
        }
        if wants(Term::Indirect) {
            let l = indirect::estimate(ctx, si, bsdf, stack, rng, scratch, sp);
            add(Term::Indirect, beta * l);
        }
    }
}
