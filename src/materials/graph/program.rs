//! The flat program a graph compiles to: instructions over a register file of `Vec3`s (a
//! float lives in `x`), run in order at every shading point.

use super::geometry_nodes as geo;
use super::point::ShadingPoint;
use crate::materials::texture::{Interp, Texture};
use glam::{Vec2, Vec3};

/// A register index.
pub type Reg = u16;

/// "Not linked": the node reads the shading normal instead.
pub const NO_REG: Reg = Reg::MAX;

/// Most registers a program may use.
pub const MAX_REGS: usize = 512;

/// Rec. 709 luminance as Cycles derives it, its colour-to-float conversion.
pub const LUMINANCE: Vec3 = super::ops::color::REC709_TO_Y;

/// One operation. Sources with a `variant` read the shading point moved by that variant's
/// offset (0: the point itself; 1, 2: the Bump node's tangent offsets).
#[derive(Clone, Debug, PartialEq)]
pub enum Op {
    /// Outputs: generated, normal, uv, object, reflection.
    TexCoord { variant: u8 },
    /// Outputs: position, normal, tangent, true_normal, incoming, parametric, backfacing.
    Geometry { variant: u8 },
    /// Output: uv; with `key`, the mesh's UV map of that name (an attribute; zero where the
    /// mesh has none, as in Cycles).
    UvMap { variant: u8, key: Option<u64> },
    /// Outputs: location, random, object_index.
    ObjectInfo,
    /// A named mesh attribute (by [`crate::geometry::attribute_key`]). Outputs: color,
    /// vector, fac (the mean of the colour, as Cycles reads a colour as a float here), alpha;
    /// `fallback` where the mesh has no such attribute (zero by default, as in Cycles).
    Attribute {
        key: u64,
        fallback: glam::Vec4,
        variant: u8,
    },
    /// Light Path: the kind of ray that reached the point (Cycles' flags and depths, see
    /// [`crate::geometry::RayPath`]). Outputs: is_camera_ray ... is_volume_scatter_ray,
    /// ray_length, ray_depth, diffuse_depth, glossy_depth, transparent_depth,
    /// transmission_depth, portal_depth.
    LightPath,
    /// Inputs: blend, normal. Outputs: fresnel, facing.
    LayerWeight,
    /// Inputs: ior, normal. Output: fac.
    Fresnel,
    /// Inputs: vector, location, rotation, scale. Output: vector.
    Mapping(geo::MappingKind),
    /// Input: vector. Outputs: x, y, z.
    SeparateXyz,
    /// Inputs: x, y, z. Output: vector.
    CombineXyz,
    /// Inputs: strength, color. Output: normal.
    NormalMap(geo::NormalSpace),
    /// Inputs: strength, distance, height (at the point, then at the two offsets), normal.
    /// Output: normal.
    Bump { invert: bool },
    /// Displacement: the offset (height - midlevel) x scale along the normal, in object space
    /// (`object`: the object's normal, the offset taken back to world space) or world space.
    /// Inputs: height, midlevel, scale, normal. Output: displacement.
    Displacement { object: bool },
    /// The shading normal bumped by a displacement (Cycles' Bump Only displacement): the
    /// height is the displacement along the normal, at the point and at the two offsets.
    /// Inputs: displacement x 3. Output: normal.
    DisplacementBump,
    /// Input: vector (mapped to the image by `projection`: Flat reads its x, y as the UV).
    /// Outputs: color, alpha.
    Image {
        texture: u32,
        interp: Interp,
        projection: geo::ImageProjection,
    },
    /// Box projection: the image projected along the object's three axes from the vector,
    /// blended by the object-space normal over `blend` (Cycles' Image Texture, Box).
    /// Input: vector. Outputs: color, alpha.
    ImageBox {
        texture: u32,
        blend: f32,
        interp: Interp,
    },
    /// A colour read as a float (luminance).
    Gray,
    /// A vector read as a float (the mean of its components).
    Average,
    /// A converter or texture node (`super::nodes`).
    Node(super::nodes::NodeOp),
}

/// An instruction: an operation, the registers it reads and those it writes.
#[derive(Clone, Debug, PartialEq)]
pub struct Instr {
    pub op: Op,
    pub ins: Box<[Reg]>,
    pub outs: Box<[Reg]>,
}

/// What a program reads besides its registers.
pub struct EvalCtx<'a> {
    pub sp: &'a ShadingPoint,
    pub textures: &'a [Texture],
    /// Position offsets of the variants (index 0 is zero).
    pub offsets: [Vec3; 3],
}

impl<'a> EvalCtx<'a> {
    /// A context whose bump offsets lie in the tangent plane of the shading normal.
    pub fn new(sp: &'a ShadingPoint, textures: &'a [Texture]) -> Self {
        let [dx, dy] = geo::bump_offsets(sp, sp.n);
        EvalCtx {
            sp,
            textures,
            offsets: [Vec3::ZERO, dx, dy],
        }
    }

    /// The mesh attribute `key` at the point moved to tangent offset `variant`.
    fn attribute(&self, key: u64, variant: u8) -> Option<glam::Vec4> {
        let d = self.offsets[variant as usize % 3];
        if d == Vec3::ZERO {
            self.sp.attributes.get(key)
        } else {
            self.sp.attributes.get_moved(key, d)
        }
    }

    fn moved(&self, variant: u8) -> (Vec3, Vec2) {
        let d = self.offsets[variant as usize % 3];
        if d == Vec3::ZERO {
            (self.sp.p, self.sp.uv)
        } else {
            (self.sp.p + d, self.sp.uv + self.sp.duv(d))
        }
    }
}

#[inline]
fn f(v: f32) -> Vec3 {
    Vec3::new(v, 0.0, 0.0)
}

impl Instr {
    /// Runs the instruction on `regs`.
    pub fn run(&self, regs: &mut [Vec3], ctx: &EvalCtx) {
        let mut inp = [Vec3::ZERO; 24];
        for (k, &r) in self.ins.iter().enumerate().take(inp.len()) {
            inp[k] = if r == NO_REG {
                ctx.sp.n
            } else {
                regs[r as usize]
            };
        }
        let linked = |k: usize| self.ins.get(k).is_some_and(|&r| r != NO_REG);
        let mut out = [Vec3::ZERO; 8];
        let sp = ctx.sp;
        match &self.op {
            Op::TexCoord { variant } => {
                let (p, uv) = ctx.moved(*variant);
                out[0] = sp.object.generated(p);
                out[1] = (sp.object.to_object.transform_vector3(sp.n)).normalize_or_zero();
                out[2] = uv.extend(0.0);
                out[3] = sp.object.object_point(p);
                out[4] = 2.0 * sp.n.dot(sp.wo) * sp.n - sp.wo;
            }
            Op::Geometry { variant } => {
                let (p, _) = ctx.moved(*variant);
                out[0] = p;
                out[1] = sp.n;
                out[2] = geo::safe_normalize(sp.dpdu - sp.n * sp.n.dot(sp.dpdu));
                out[3] = sp.ng;
                out[4] = sp.wo;
                out[5] = Vec3::ZERO;
                out[6] = f(if sp.backfacing { 1.0 } else { 0.0 });
            }
            Op::UvMap { variant, key: None } => out[0] = ctx.moved(*variant).1.extend(0.0),
            Op::UvMap {
                variant,
                key: Some(key),
            } => {
                let v = ctx.attribute(*key, *variant).unwrap_or_default();
                out[0] = Vec3::new(v.x, v.y, 0.0);
            }
            Op::Attribute {
                key,
                fallback,
                variant,
            } => {
                let v = ctx.attribute(*key, *variant).unwrap_or(*fallback);
                out[0] = v.truncate();
                out[1] = v.truncate();
                out[2] = f((v.x + v.y + v.z) / 3.0);
                out[3] = f(v.w);
            }
            Op::ObjectInfo => {
                out[0] = sp.object.location;
                out[1] = f(sp.object.random);
                out[2] = f(sp.object.index);
            }
            Op::LightPath => {
                let path = &sp.path;
                for (k, o) in out.iter_mut().enumerate() {
                    *o = f(if path.is(1 << k) { 1.0 } else { 0.0 });
                }
                let mut more = [Vec3::ZERO; 7];
                more[0] = f(sp.ray_length);
                more[1] = f(path.depth as f32);
                more[2] = f(path.diffuse_depth as f32);
                more[3] = f(path.glossy_depth as f32);
                more[4] = f(path.transparent_depth as f32);
                more[5] = f(path.transmission_depth as f32);
                for (o, m) in self.outs.iter().skip(8).zip(more) {
                    regs[*o as usize] = m;
                }
            }
            Op::LayerWeight => {
                let n = linked(1).then_some(inp[1]);
                let (fr, fa) = geo::layer_weight(sp, inp[0].x, n);
                out[0] = f(fr);
                out[1] = f(fa);
            }
            Op::Fresnel => {
                let n = linked(1).then_some(inp[1]);
                out[0] = f(geo::fresnel(sp, inp[0].x, n));
            }
            Op::Mapping(kind) => out[0] = geo::mapping(*kind, inp[0], inp[1], inp[2], inp[3]),
            Op::SeparateXyz => {
                out[0] = f(inp[0].x);
                out[1] = f(inp[0].y);
                out[2] = f(inp[0].z);
            }
            Op::CombineXyz => out[0] = Vec3::new(inp[0].x, inp[1].x, inp[2].x),
            Op::NormalMap(space) => out[0] = geo::normal_map(sp, *space, inp[0].x, inp[1]),
            Op::Bump { invert } => {
                let n = if linked(5) { inp[5] } else { sp.n };
                out[0] = geo::bump(
                    n,
                    [ctx.offsets[1], ctx.offsets[2]],
                    inp[2].x,
                    inp[3].x,
                    inp[4].x,
                    inp[0].x,
                    inp[1].x,
                    *invert,
                );
            }
            Op::Displacement { object } => {
                let n = if linked(3) { inp[3] } else { sp.n };
                let h = (inp[0].x - inp[1].x) * inp[2].x;
                out[0] = if *object {
                    geo::object_displacement(&sp.object, n, h)
                } else {
                    n * h
                };
            }
            Op::DisplacementBump => {
                let h = |k: usize| inp[k].dot(sp.n);
                out[0] = geo::bump(
                    sp.n,
                    [ctx.offsets[1], ctx.offsets[2]],
                    h(0),
                    h(1),
                    h(2),
                    1.0,
                    1.0,
                    false,
                );
            }
            Op::Image {
                texture,
                interp,
                projection,
            } => match ctx.textures.get(*texture as usize) {
                Some(t) => {
                    let uv = projection.uv(inp[0]);
                    out[0] = t.eval_rgb_with(uv, *interp);
                    out[1] = f(if t.channels() == 4 {
                        t.eval_channel_with(uv, 3, *interp)
                    } else {
                        1.0
                    });
                }
                None => out[1] = f(1.0),
            },
            Op::ImageBox {
                texture,
                blend,
                interp,
            } => match ctx.textures.get(*texture as usize) {
                Some(t) => {
                    let n = sp.object.to_object.transform_vector3(sp.n);
                    let (rgb, a) = geo::image_box(t, inp[0], n, *blend, *interp);
                    out[0] = rgb;
                    out[1] = f(a);
                }
                None => out[1] = f(1.0),
            },
            Op::Gray => out[0] = f(super::ops::rgb_to_bw(inp[0])),
            Op::Average => out[0] = f((inp[0].x + inp[0].y + inp[0].z) / 3.0),
            Op::Node(n) => n.run(&inp[..self.ins.len().min(inp.len())], &mut out, ctx),
        }
        for (k, &r) in self.outs.iter().enumerate().take(out.len()) {
            if let Some(slot) = regs.get_mut(r as usize) {
                *slot = out[k];
            }
        }
    }
}

/// A compiled program: the initial register file (constants) and the instructions.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Program {
    pub init: Vec<Vec3>,
    pub code: Vec<Instr>,
}

impl Program {
    /// Runs the program at a shading point, into `regs` (at least `init.len()` long).
    pub fn run(&self, regs: &mut [Vec3], ctx: &EvalCtx) {
        regs[..self.init.len()].copy_from_slice(&self.init);
        self.run_range(regs, ctx, 0..self.code.len());
    }

    /// Runs instructions `range` on `regs` (already initialised).
    pub fn run_range(&self, regs: &mut [Vec3], ctx: &EvalCtx, range: std::ops::Range<usize>) {
        for i in &self.code[range] {
            i.run(regs, ctx);
        }
    }
}
