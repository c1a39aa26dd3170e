//! Closure leaves: the BSDF, emission and transparency nodes of a graph, and how their
//! weighted sum becomes one [`Bsdf`] at a shading point.

mod parse;

use super::program::{Reg, NO_REG};
use super::spec::{Dflt, NodeSpec, Ty};
use crate::materials::bsdf::Bsdf;
use crate::materials::diffuse::Lambert;
use crate::materials::fresnel::{f0_from_ior, Fresnel};
use crate::materials::layer::{CoatAlbedoTable, CoatLayer};
use crate::materials::lobe::Lobe;
use crate::materials::microfacet::NEAR_SPECULAR_ROUGHNESS;
use crate::materials::principled::Principled;
use crate::materials::texture::{ColorParam, FloatParam};
use crate::materials::translucent::Translucent;
use crate::materials::{dielectric_lobe, reflection_lobe, refraction_lobe};
use crate::math::{Frame, Spectrum};
use glam::{Vec2, Vec3};

/// A closure node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LeafKind {
    /// Principled BSDF. Inputs: see [`PRINCIPLED`].
    Principled { multiscatter: bool },
    /// Diffuse BSDF: color, roughness (ignored), normal.
    Diffuse,
    /// Glossy BSDF (Color as a tint, no Fresnel): color, roughness, normal.
    Glossy { multiscatter: bool },
    /// Glass BSDF: color, roughness, ior, normal.
    Glass { multiscatter: bool },
    /// Refraction BSDF: color, roughness, ior, normal (refraction alone, no Fresnel factor).
    Refraction,
    /// Transparent BSDF: color. Light passes straight through, weighted by the colour.
    Transparent,
    /// Emission: color, strength.
    Emission,
    /// Translucent BSDF: color, normal (diffuse transmission).
    Translucent,
    /// Holdout: renders black, and its weight makes the image transparent there (alpha)
    /// where a camera ray reaches it straight through transparent surfaces.
    Holdout,
    /// Sheen BSDF: color, roughness, normal (renders black).
    Sheen,
}

/// The Principled BSDF's inputs, in order.
pub const PRINCIPLED: [(&str, Ty, Dflt); 17] = [
    ("base_color", Ty::Color, Dflt::V([0.8, 0.8, 0.8])),
    ("metallic", Ty::Float, Dflt::F(0.0)),
    ("roughness", Ty::Float, Dflt::F(0.5)),
    ("ior", Ty::Float, Dflt::F(1.5)),
    ("alpha", Ty::Float, Dflt::F(1.0)),
    ("normal", Ty::Vector, Dflt::Normal),
    ("subsurface_weight", Ty::Float, Dflt::F(0.0)),
    ("specular_ior_level", Ty::Float, Dflt::F(0.5)),
    ("transmission_weight", Ty::Float, Dflt::F(0.0)),
    ("coat_weight", Ty::Float, Dflt::F(0.0)),
    ("coat_roughness", Ty::Float, Dflt::F(0.03)),
    ("coat_ior", Ty::Float, Dflt::F(1.5)),
    ("coat_tint", Ty::Color, Dflt::V([1.0, 1.0, 1.0])),
    ("coat_normal", Ty::Vector, Dflt::Normal),
    ("emission_color", Ty::Color, Dflt::V([1.0, 1.0, 1.0])),
    ("emission_strength", Ty::Float, Dflt::F(0.0)),
    ("sheen_weight", Ty::Float, Dflt::F(0.0)),
];

mod pin {
    pub const BASE: usize = 0;
    pub const METALLIC: usize = 1;
    pub const ROUGHNESS: usize = 2;
    pub const IOR: usize = 3;
    pub const ALPHA: usize = 4;
    pub const NORMAL: usize = 5;
    pub const SUBSURFACE: usize = 6;
    pub const LEVEL: usize = 7;
    pub const TRANSMISSION: usize = 8;
    pub const COAT: usize = 9;
    pub const COAT_ROUGHNESS: usize = 10;
    pub const COAT_IOR: usize = 11;
    pub const COAT_TINT: usize = 12;
    pub const COAT_NORMAL: usize = 13;
    pub const EMISSION: usize = 14;
    pub const STRENGTH: usize = 15;
    pub const SHEEN: usize = 16;
}

impl LeafKind {
    /// The IR types of closure nodes.
    pub const TYPES: &'static [&'static str] = &[
        "principled",
        "diffuse",
        "glossy",
        "glass",
        "transparent",
        "translucent",
        "refraction",
        "emission",
        "holdout",
        "sheen",
    ];

    /// What renders other than the node says, given its input registers (`init`/`konst`:
    /// the constant registers).
    pub fn warnings(
        &self,
        ins: &[Reg],
        init: &[Vec3],
        konst: &[bool],
        _spec: &NodeSpec,
    ) -> Vec<String> {
        let nonzero = |k: usize| {
            let r = ins[k];
            r != NO_REG && (!konst[r as usize] || init[r as usize].x != 0.0)
        };
        let mut w = Vec::new();
        match self {
            LeafKind::Principled { .. } => {
                if nonzero(pin::SUBSURFACE) {
                    w.push("Subsurface Weight in a shading graph is not supported; renders without subsurface".to_string());
                }
                if nonzero(pin::SHEEN) {
                    w.push("Sheen Weight is not supported; ignored".to_string());
                }
            }
            LeafKind::Sheen => w.push("the Sheen BSDF is not supported; renders black".to_string()),
            _ => {}
        }
        w
    }
}

/// A closure leaf: its kind, its weight (a product of mix factors: `(register, complement)`
/// reads `fac` or `1 - fac`), its input registers, and the node it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Leaf {
    pub kind: LeafKind,
    pub weight: Vec<(Reg, bool)>,
    pub ins: Vec<Reg>,
    pub node: u32,
}

impl Leaf {
    /// The register of the leaf's Normal input, if it has one.
    pub fn normal(&self) -> Option<Reg> {
        match self.kind {
            LeafKind::Principled { .. } => Some(self.ins[pin::NORMAL]),
            LeafKind::Diffuse | LeafKind::Glossy { .. } | LeafKind::Sheen => Some(self.ins[2]),
            LeafKind::Glass { .. } | LeafKind::Refraction => Some(self.ins[3]),
            LeafKind::Translucent => Some(self.ins[1]),
            _ => None,
        }
    }

    /// The leaf's weight at the registers `regs`.
    pub fn weight(&self, regs: &[Vec3]) -> f32 {
        self.weight.iter().fold(1.0, |w, &(r, c)| {
            let f = regs[r as usize].x;
            let f = if f.is_finite() {
                f.clamp(0.0, 1.0)
            } else {
                0.0
            };
            w * if c { 1.0 - f } else { f }
        })
    }

    /// Whether the leaf's input `k` is the constant `v` (over `init`/`konst`).
    fn input_is(
        &self,
        k: usize,
        konst: &[bool],
        init: &[Vec3],
        test: impl Fn(Vec3) -> bool,
    ) -> bool {
        let r = self.ins[k];
        r != NO_REG && konst[r as usize] && test(init[r as usize])
    }
}

/// What the closures give at a shading point.
#[derive(Clone, Copy, Debug)]
pub struct Shaded {
    pub bsdf: Bsdf,
    pub emission: Spectrum,
    /// The weight of light passing straight through (Transparent BSDF, Principled Alpha).
    pub transparency: Spectrum,
    /// The summed weight of the Holdout closures.
    pub holdout: f32,
}

fn unit(v: f32) -> f32 {
    if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

fn sane(v: f32, lo: f32, hi: f32, default: f32) -> f32 {
    if v.is_finite() {
        v.clamp(lo, hi)
    } else {
        default
    }
}

fn color(v: Vec3) -> Spectrum {
    if v.is_finite() {
        v.max(Vec3::ZERO)
    } else {
        Vec3::ZERO
    }
}

/// The coat albedo table for F0 `f0`, quantised when it varies over the surface so that
/// the tables stay few.
fn table(f0: f32, varies: bool) -> &'static CoatAlbedoTable {
    let f0 = if varies {
        (f0 * 512.0).round() / 512.0
    } else {
        f0
    };
    CoatAlbedoTable::for_f0(f0)
}

/// Tables a Principled leaf needs, fixed when its IOR inputs are constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeafTables {
    pub specular: Option<&'static CoatAlbedoTable>,
    pub coat: Option<&'static CoatAlbedoTable>,
}

impl LeafTables {
    pub fn new(leaf: &Leaf, konst: &[bool], init: &[Vec3]) -> Self {
        let LeafKind::Principled { .. } = leaf.kind else {
            return LeafTables {
                specular: None,
                coat: None,
            };
        };
        let c = |k: usize| {
            let r = leaf.ins[k];
            (r != NO_REG && konst[r as usize]).then(|| init[r as usize].x)
        };
        let specular = match (c(pin::IOR), c(pin::LEVEL)) {
            (Some(ior), Some(level)) => {
                let ior = sane(ior, 1.0, 10.0, 1.5);
                Some(table(coat_f0(ior, 2.0 * level), false))
            }
            _ => None,
        };
        let coat =
            c(pin::COAT_IOR).map(|i| CoatAlbedoTable::for_f0(f0_from_ior(sane(i, 1.0, 10.0, 1.5))));
        LeafTables { specular, coat }
    }
}

fn coat_f0(ior: f32, specular: f32) -> f32 {
    (specular.clamp(0.0, 10.0) * f0_from_ior(ior)).clamp(0.0, 0.9)
}

/// Whether a leaf can scatter through a delta or near-specular lobe (the scene then needs a
/// caustic map).
pub fn leaf_has_specular(leaf: &Leaf, konst: &[bool], init: &[Vec3]) -> bool {
    let rough_above = |k: usize| leaf.input_is(k, konst, init, |v| v.x > NEAR_SPECULAR_ROUGHNESS);
    let zero = |k: usize| leaf.input_is(k, konst, init, |v| v.x <= 0.0);
    match leaf.kind {
        LeafKind::Principled { .. } => {
            !zero(pin::TRANSMISSION)
                || !rough_above(pin::ROUGHNESS)
                || (!zero(pin::COAT) && !rough_above(pin::COAT_ROUGHNESS))
        }
        LeafKind::Glossy { .. } => !rough_above(1),
        LeafKind::Glass { .. } | LeafKind::Refraction => true,
        _ => false,
    }
}

/// Whether a leaf can emit.
pub fn leaf_emits(leaf: &Leaf, konst: &[bool], init: &[Vec3]) -> bool {
    let zero = |k: usize| leaf.input_is(k, konst, init, |v| v.max_element() <= 0.0);
    match leaf.kind {
        LeafKind::Emission => !zero(0) && !zero(1),
        LeafKind::Principled { .. } => !zero(pin::EMISSION) && !zero(pin::STRENGTH),
        _ => false,
    }
}

/// Whether a leaf can scatter light: reflect it, or transmit it other than straight through.
/// Emission, Transparent and Holdout cannot, nor Sheen while it renders black.
pub fn leaf_scatters(leaf: &Leaf, _konst: &[bool], _init: &[Vec3]) -> bool {
    !matches!(
        leaf.kind,
        LeafKind::Emission | LeafKind::Transparent | LeafKind::Holdout | LeafKind::Sheen
    )
}

/// Whether a leaf can let light pass straight through.
pub fn leaf_transparent(leaf: &Leaf, konst: &[bool], init: &[Vec3]) -> bool {
    match leaf.kind {
        LeafKind::Transparent => !leaf.input_is(0, konst, init, |v| v.max_element() <= 0.0),
        LeafKind::Principled { .. } => !leaf.input_is(pin::ALPHA, konst, init, |v| v.x >= 1.0),
        _ => false,
    }
}

/// Adds leaf `leaf` with weight `w` to `out` at registers `regs`; `backfacing` inverts the
/// relative IOR of transmitting lobes (the frame faces the ray, as Cycles shades).
pub fn add_leaf(
    out: &mut Shaded,
    leaf: &Leaf,
    tables: &LeafTables,
    w: f32,
    regs: &[Vec3],
    frame: Frame,
    sp: &super::ShadingPoint,
    want_bsdf: bool,
) {
    let x = |k: usize| regs[leaf.ins[k] as usize].x;
    let v = |k: usize| regs[leaf.ins[k] as usize];
    let eta = |ior: f32| if sp.backfacing { 1.0 / ior } else { ior };
    match leaf.kind {
        LeafKind::Principled { multiscatter } => {
            let alpha = unit(x(pin::ALPHA));
            if alpha < 1.0 {
                out.transparency += Spectrum::splat(w * (1.0 - alpha));
            }
            let w = w * alpha;
            if !(w > 0.0) {
                return;
            }
            let strength = x(pin::STRENGTH);
            if strength > 0.0 && strength.is_finite() {
                out.emission += w * color(v(pin::EMISSION)) * strength;
            }
            if !want_bsdf {
                return;
            }
            let ior = sane(x(pin::IOR), 1.0, 10.0, 1.5);
            let specular = sane(2.0 * x(pin::LEVEL), 0.0, 10.0, 1.0);
            let coat_w = unit(x(pin::COAT));
            let clearcoat = (coat_w > 0.0).then(|| {
                let coat_ior = sane(x(pin::COAT_IOR), 1.0, 10.0, 1.5);
                CoatLayer {
                    weight: coat_w,
                    roughness: unit(x(pin::COAT_ROUGHNESS)),
                    ior: coat_ior,
                    tint: color(v(pin::COAT_TINT)).min(Spectrum::ONE),
                    table: tables
                        .coat
                        .unwrap_or_else(|| table(f0_from_ior(coat_ior), true)),
                    multiscatter,
                }
            });
            let p = Principled {
                name: String::new(),
                base_color: ColorParam::Const(color(v(pin::BASE))),
                metallic: FloatParam::Const(unit(x(pin::METALLIC))),
                roughness: FloatParam::Const(unit(x(pin::ROUGHNESS))),
                transmission: unit(x(pin::TRANSMISSION)),
                ior: eta(ior),
                specular,
                emission_color: ColorParam::Const(Vec3::ZERO),
                emission_strength: 0.0,
                multiscatter,
                clearcoat,
                coat_table: tables
                    .specular
                    .unwrap_or_else(|| table(coat_f0(ior, specular), true)),
                subsurface: None,
            };
            out.bsdf.absorb(&p.bsdf(frame, Vec2::ZERO, &[]), w);
            if coat_w > 0.0 {
                // The coat's normal is its own input, the surface's normal when unlinked
                // (not the Normal input), as in Cycles.
                let n = match leaf.ins[pin::COAT_NORMAL] {
                    NO_REG => sp.n,
                    r => regs[r as usize].try_normalize().unwrap_or(sp.n),
                };
                let n = if n == sp.n {
                    n
                } else {
                    super::geometry_nodes::ensure_valid_reflection(sp.ng, sp.wo, n)
                };
                out.bsdf.set_coat_normal(n, sp.dpdu);
            }
        }
        LeafKind::Diffuse => {
            if want_bsdf {
                let albedo = color(v(0));
                out.bsdf.add(w, Lobe::Lambert(Lambert { albedo }));
            }
        }
        LeafKind::Translucent => {
            if want_bsdf {
                let albedo = color(v(0));
                out.bsdf.add(w, Lobe::Translucent(Translucent { albedo }));
            }
        }
        LeafKind::Glossy { multiscatter } => {
            if want_bsdf {
                let lobe =
                    reflection_lobe(unit(x(1)), Fresnel::Constant(color(v(0))), multiscatter);
                out.bsdf.add(w, lobe);
            }
        }
        LeafKind::Glass { multiscatter } => {
            if want_bsdf {
                let ior = sane(x(2), 1.0, 10.0, 1.5);
                out.bsdf.add(
                    w,
                    dielectric_lobe(eta(ior), unit(x(1)), color(v(0)), multiscatter),
                );
            }
        }
        LeafKind::Refraction => {
            if want_bsdf {
                let ior = sane(x(2), 1.0, 10.0, 1.45);
                out.bsdf
                    .add(w, refraction_lobe(eta(ior), unit(x(1)), color(v(0))));
            }
        }
        LeafKind::Transparent => out.transparency += w * color(v(0)),
        LeafKind::Emission => {
            let s = x(1);
            if s > 0.0 && s.is_finite() {
                out.emission += w * color(v(0)) * s;
            }
        }
        LeafKind::Holdout => out.holdout += w,
        LeafKind::Sheen => {}
    }
}
