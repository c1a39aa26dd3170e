#!/usr/bin/env python3
"""Renders the Mitsuba 3 reference images in tests/data/references/ from our JSON scenes.

Setup (Debian 12, Python 3.11):

    pip install mitsuba==3.9.* numpy openimageio
    apt-get update && apt-get install -y libllvm19        # for the fast llvm_ad_rgb variant
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so

Run from the repository root:

    python3 scripts/make_references.py                  # every reference, full sample counts
    python3 scripts/make_references.py cornell_diffuse_direct --spp 256   # one, quick
    python3 scripts/make_references.py --variant scalar_rgb ...            # no LLVM needed, ~3x slower

Each reference is rendered as B independent batches, each as k passes of at most 256 spp
(batch b uses seeds b*k .. b*k+k-1, so no two passes share a seed). We write
    <name>.exr         the mean of the batches, float32 RGB
    <name>.stderr.exr  the per-pixel standard error of that mean: std(batches, ddof=1)/sqrt(B)
    <name>.json        spp, batches, variant, seconds, mean pixel value, relMSE noise floor
The relMSE noise floor is mean over pixels and channels of stderr^2 / (mean^2 + 1e-2): the
relMSE an exact renderer would score against this reference.

The scene is translated from our IR (src/scene/desc.rs), never written by hand; see
`translate()` for the rules and tests/data/references/README.md for the list.

References
    cornell_diffuse_direct           Mitsuba `path`, max_depth=2: emission + direct light
    cornell_spheres_direct_specular  `direct_specular` below: our direct + specular + emission
    cornell_diffuse_full             Mitsuba `path`, max_depth=-1, rr_depth=5: all light
    cornell_spheres_full             Mitsuba `path`, max_depth=-1, rr_depth=5: all light
    fog_spot_single                  Mitsuba `volpath`, max_depth=2: emission, direct light on
                                     surfaces and single scattering in media
    fog_spot_full                    Mitsuba `volpath`, max_depth=-1, rr_depth=64: all light
    fog_glass_full                   Mitsuba `volpath`, max_depth=-1, rr_depth=64: all light
    thick_sphere_full                Mitsuba `volpath`, max_depth=-1, rr_depth=64: all light

Mitsuba counts depth in scattering events along the camera path, surface and medium alike (null
surfaces, i.e. medium boundaries, do not count). With max_depth=2: depth 1 is what the camera
ray meets (an emitter seen directly, possibly through null boundaries, attenuated by the media
on the way); at the first real event, a surface bounce or a scattering in a medium, next-event
estimation to the lights (shadow rays pass null boundaries and are attenuated by transmittance)
and the MIS-weighted emitter hit of the sampled direction form depth 2. So max_depth=2 is
emission + direct light on surfaces + single scattering in media, with transmittance on every
segment; no light that has scattered twice.

The `direct_specular` integrator computes exactly the sum of our `direct`, `specular` and
`emission` terms, i.e. everything except `indirect` and `caustic`:
  * From the camera, follow delta (perfectly specular) BSDF bounces: mirror reflection, and
    dielectric reflection or refraction chosen by sampling the BSDF (Fresnel), for at most
    8 specular bounces. The emission of every emitter hit on this chain (the camera ray's hit
    included) is added with weight 1.
  * At the first surface whose BSDF is not purely delta, add its emission and its direct
    light by next-event estimation with multiple importance sampling (power heuristic):
    an emitter sample with a shadow ray, plus a BSDF sample that counts only if the ray hits
    an emitter directly (no further bounce). Then the path ends.
  * Any surface blocks the shadow ray, glass included, and a BSDF-sampled ray that hits glass
    contributes nothing: light reaching a diffuse point through glass or via a mirror is a
    caustic, another term.
  * A chain that is still specular after 8 bounces contributes nothing more.
  * Dielectric radiance scaling (1/eta^2 on entering) is Mitsuba's; it cancels for light
    that leaves the glass again, which is all light in these scenes.
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT_DIR = os.path.join(ROOT, "tests", "data", "references")
LLVM19 = "/usr/lib/x86_64-linux-gnu/libLLVM-19.so"
if "DRJIT_LIBLLVM_PATH" not in os.environ and os.path.exists(LLVM19):
    os.environ["DRJIT_LIBLLVM_PATH"] = LLVM19

import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

SPP_FOG_SPOT_SINGLE = 16384
SPP_FOG_SPOT_FULL = 8192
SPP_FOG_GLASS_FULL = 8192
SPP_THICK_SPHERE_FULL = 8192
SPP_SSS = 8192

# name -> (scene, integrator dict, total spp, batches)
REFERENCES = {
    "cornell_diffuse_direct": (
        "tests/data/scenes/cornell_diffuse.json",
        {"type": "path", "max_depth": 2},
        65536,
        16,
    ),
    "cornell_spheres_direct_specular": (
        "tests/data/scenes/cornell_spheres.json",
        {"type": "direct_specular", "max_specular_depth": 8},
        65536,
        16,
    ),
    "cornell_diffuse_full": (
        "tests/data/scenes/cornell_diffuse.json",
        {"type": "path", "max_depth": -1, "rr_depth": 5},
        16384,
        16,
    ),
    "cornell_spheres_full": (
        "tests/data/scenes/cornell_spheres.json",
        {"type": "path", "max_depth": -1, "rr_depth": 5},
        16384,
        16,
    ),
    # Participating media (scripts/make_media_scenes.py).
    "fog_spot_single": (
        "tests/data/scenes/fog_spot.json",
        {"type": "volpath", "max_depth": 2},
        SPP_FOG_SPOT_SINGLE,
        16,
    ),
    "fog_spot_full": (
        "tests/data/scenes/fog_spot.json",
        {"type": "volpath", "max_depth": -1, "rr_depth": 64},
        SPP_FOG_SPOT_FULL,
        16,
    ),
    "fog_glass_full": (
        "tests/data/scenes/fog_glass.json",
        {"type": "volpath", "max_depth": -1, "rr_depth": 64},
        SPP_FOG_GLASS_FULL,
        16,
    ),
    "thick_sphere_full": (
        "tests/data/scenes/thick_sphere.json",
        {"type": "volpath", "max_depth": -1, "rr_depth": 64},
        SPP_THICK_SPHERE_FULL,
        16,
    ),
    # Subsurface scattering, index-matched (see index_matched_subsurface).
    "sss_sphere_full": (
        "tests/data/scenes/sss_sphere.json",
        {"type": "volpath", "max_depth": -1, "rr_depth": 100000},
        SPP_SSS,
        16,
    ),
    "sss_slab_full": (
        "tests/data/scenes/sss_slab.json",
        {"type": "volpath", "max_depth": -1, "rr_depth": 100000},
        SPP_SSS,
        16,
    ),
}

# Largest number of samples per pixel in one mi.render call (bounds memory).
MAX_SPP_PER_PASS = 256


# ----------------------------------------------------------------------------------------
# IR -> Mitsuba
# ----------------------------------------------------------------------------------------


class Unsupported(Exception):
    pass


def mat(m):
    a = np.array(m, dtype=np.float64)
    assert a.shape == (4, 4)
    return a  # rows; column-vector convention (p' = M p), as Mitsuba's Transform4f


def rgb(c):
    return {"type": "rgb", "value": [float(v) for v in c]}


def color_value(c, where):
    if isinstance(c, dict):
        raise Unsupported(f"{where}: textures are not translated")
    return [float(v) for v in c]


def bsdf_of(m, where):
    """Our material -> (Mitsuba BSDF dict, emitted radiance or None)."""
    t = m["type"]
    if t == "diffuse":
        col = color_value(m.get("color", [0.8, 0.8, 0.8]), where + "/color")
        # Our Lambert surface reflects on both sides (as Blender's); Mitsuba's is one-sided.
        return {"type": "twosided", "material": {"type": "diffuse", "reflectance": rgb(col)}}, None
    if t == "mirror":
        return {
            "type": "conductor",
            "material": "none",
            "specular_reflectance": rgb(m.get("color", [1, 1, 1])),
        }, None
    if t == "conductor":
        r = float(m.get("roughness", 0.0))
        d = {"eta": rgb(m["eta"]), "k": rgb(m["k"])}
        if r == 0.0:
            return dict(type="conductor", **d), None
        return dict(type="roughconductor", distribution="ggx", alpha=r * r, **d), None
    if t == "dielectric":
        r = float(m.get("roughness", 0.0))
        d = {
            "int_ior": float(m.get("ior", 1.5)),
            "ext_ior": 1.0,  # Mitsuba's default is air (1.000277); ours is vacuum
            "specular_transmittance": rgb(m.get("color", [1, 1, 1])),
        }
        if r == 0.0:
            return dict(type="dielectric", **d), None
        return dict(type="roughdielectric", distribution="ggx", alpha=r * r, **d), None
    if t == "emission":
        col = color_value(m.get("color", [1, 1, 1]), where + "/color")
        s = float(m.get("strength", 1.0))
        return {"type": "diffuse", "reflectance": rgb([0, 0, 0])}, [c * s for c in col]
    if t == "null":
        # An invisible medium boundary: Mitsuba's `null` BSDF (rays pass, media switch).
        return {"type": "null"}, None
    if t == "principled" and m.get("subsurface") is not None:
        # Index-matched subsurface (see subsurface_medium): the surface lets light in and out.
        index_matched_subsurface(m, where)
        return {"type": "null"}, None
    raise Unsupported(f"{where}: material type {t!r} has no exact Mitsuba equivalent here")


def make_mesh(name, P, N, F, bsdf, radiance, interior=None, exterior=None):
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    if radiance is not None:
        props["emitter"] = mi.load_dict({"type": "area", "radiance": rgb(radiance)})
    if interior is not None:
        props["interior"] = interior
    if exterior is not None:
        props["exterior"] = exterior
    mesh = mi.Mesh(name, len(P), len(F), props=props, has_vertex_normals=N is not None)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(np.ravel(P).astype(np.float32))
    params["faces"] = mi.UInt32(np.ravel(F).astype(np.uint32))
    if N is not None:
        params["vertex_normals"] = mi.Float(np.ravel(N).astype(np.float32))
    params.update()
    return mesh


def mesh_placements(ir):
    """Meshes (and instances) in world space: list of (mesh index, name, P, N, F)."""
    meshes = ir.get("meshes", [])
    instances = ir.get("instances", [])
    prototypes = {inst["mesh"] for inst in instances}
    placements = [(i, np.eye(4), m.get("name") or f"mesh{i}") for i, m in enumerate(meshes)
                  if i not in prototypes]
    for j, inst in enumerate(instances):
        placements.append((inst["mesh"], mat(inst.get("transform", np.eye(4))),
                           inst.get("name") or f"instance{j}"))
    out = []
    for i, outer, name in placements:
        m = meshes[i]
        M = outer @ mat(m.get("transform", np.eye(4)))
        P = np.array(m["positions"], dtype=np.float64)
        P = (np.c_[P, np.ones(len(P))] @ M.T)[:, :3]
        N = None
        if m.get("normals") is not None:
            N = np.array(m["normals"], dtype=np.float64) @ np.linalg.inv(M[:3, :3])  # (M^-T n)
            N /= np.linalg.norm(N, axis=1, keepdims=True)
        F = np.array(m["indices"], dtype=np.int64)
        if np.linalg.det(M[:3, :3]) < 0:
            F = F[:, ::-1]  # keep the geometric normal on the same side as the shading normal
        out.append((i, name, P, N, F))
    return out


# ----------------------------------------------------------------------------------------
# Media
# ----------------------------------------------------------------------------------------


def medium_object(md):
    """Our homogeneous medium -> Mitsuba `homogeneous`: sigma_t = sigma_a + sigma_s and
    albedo = sigma_s / sigma_t per RGB channel, HG phase function with our g.

    Mitsuba parses an `rgb` sigma_t as a reflectance, which must lie in [0, 1]; so sigma_t is
    passed as scale * (sigma_t / scale) with scale = the largest channel of sigma_t."""
    sa = np.array(md["sigma_a"], dtype=np.float64)
    ss = np.array(md["sigma_s"], dtype=np.float64)
    st = sa + ss
    albedo = np.where(st > 0, ss / np.where(st > 0, st, 1), 0.0)
    scale = float(st.max()) if st.max() > 0 else 1.0
    return mi.load_dict({
        "type": "homogeneous",
        "sigma_t": rgb(st / scale),
        "albedo": rgb(albedo),
        "scale": scale,
        "phase": {"type": "hg", "g": float(md.get("g", 0.0))},
    })


def chiang_single_scattering_albedo(albedo, g):
    """Cycles' fit of the single-scattering albedo whose multiple scattering returns `albedo`
    (Chiang, Kutz & Burley 2016; `subsurface_random_walk_remap`), as the renderer uses it."""
    g2, g3, g4, g5, g6, g7 = g ** 2, g ** 3, g ** 4, g ** 5, g ** 6, g ** 7
    a = (1.8260523782 - 1.28451056436 * g - 1.79904629312 * g2 + 9.19393289202 * g3
         - 22.8215585862 * g4 + 32.0234874259 * g5 - 23.6264803333 * g6 + 7.21067002658 * g7)
    b = 4.98511194385 + 0.127355959438 * math.exp(
        31.1491581433 * g - 201.847017512 * g2 + 841.576016723 * g3 - 2018.09288505 * g4
        + 2731.71560286 * g5 - 1935.41424244 * g6 + 559.009054474 * g7)
    c = (1.09686102424 - 0.394704063468 * g + 1.05258115941 * g2 - 8.83963712726 * g3
         + 28.8643230661 * g4 - 46.8802913581 * g5 + 38.5402837518 * g6 - 12.7181042538 * g7)
    d = (0.496310210422 + 0.360146581622 * g - 2.15139309747 * g2 + 17.8896899217 * g3
         - 55.2984010333 * g4 + 82.065982243 * g5 - 58.5106008578 * g6 + 15.8478295021 * g7)
    e = 4.23190299701 + 0.00310603949088 * math.exp(
        76.7316253952 * g - 594.356773233 * g2 + 2448.8834203 * g3 - 5576.68528998 * g4
        + 7116.60171912 * g5 - 4763.54467887 * g6 + 1303.5318055 * g7)
    f = (2.40602999408 - 2.51814844609 * g + 9.18494908356 * g2 - 79.2191708682 * g3
         + 259.082868209 * g4 - 403.613804597 * g5 + 302.85712436 * g6 - 87.4370473567 * g7)
    albedo = min(max(albedo, 0.0), 1.0)
    blend = albedo ** 0.25
    alpha = ((1 - blend) * a * math.atan(b * albedo) ** c
             + blend * d * math.atan(e * albedo) ** f)
    return min(max(alpha, 0.0), 0.999999)


def index_matched_subsurface(m, where):
    """Checks that a Principled material with a subsurface part is one whose walk Mitsuba's
    `volpath` renders exactly, and returns its interior medium (our IR's homogeneous medium).

    Our walk (Cycles' Random Walk) enters through a GGX interface of the material's IOR and
    roughness, scatters in a homogeneous medium of extinction 4 pi / radius and the
    single-scattering albedo of Chiang et al.'s fit, and leaves through a white Lambertian
    surface. With roughness 0, IOR 1.01 (the least the renderer takes), specular 0 and weight 1,
    the entry is a straight refraction (a 1% bend) with no reflection, and the walk's weight is
    the medium's transmission: Mitsuba's medium behind a `null` surface. The exits differ
    (Lambertian against straight on), so the two agree only where the light reaching the
    surface is the same from every direction: a scene of one such object under a constant
    environment (`translate` checks that)."""
    sub = m["subsurface"]
    checks = {
        "weight": (float(sub.get("weight", 0.0)), 1.0),
        "roughness": (float(m.get("roughness", 0.5)), 0.0),
        "specular": (float(m.get("specular", 1.0)), 0.0),
        "metallic": (float(m.get("metallic", 0.0)), 0.0),
        "transmission": (float(m.get("transmission", 0.0)), 0.0),
    }
    for k, (v, want) in checks.items():
        if v != want:
            raise Unsupported(f"{where}: subsurface is translated with {k} {want} only, not {v}")
    ior = float(sub.get("ior", m.get("ior", 1.5)))
    if ior > 1.01:
        raise Unsupported(f"{where}: subsurface is translated with IOR 1.01 at most, not {ior}")
    if sub.get("method", "random_walk") != "random_walk":
        raise Unsupported(f"{where}: subsurface method {sub.get('method')!r} is not translated")
    g = min(max(float(sub.get("anisotropy", 0.0)), 0.0), 0.9)
    color = sub.get("color") or m.get("base_color", [0.8, 0.8, 0.8])
    color = color_value(color, where + "/subsurface/color")
    radius = [float(r) for r in sub["radius"]]
    sigma_t = [4 * math.pi / (r * (1 - g)) for r in radius]
    alpha = [max(chiang_single_scattering_albedo(c, g), 0.2) for c in color]
    if any(chiang_single_scattering_albedo(c, g) < 0.2 for c in color):
        raise Unsupported(f"{where}: subsurface colours darker than the albedo fit's 0.2 floor "
                          "are not translated")
    return {"sigma_a": [st * (1 - a) for st, a in zip(sigma_t, alpha)],
            "sigma_s": [st * a for st, a in zip(sigma_t, alpha)], "g": g}


def subsurface_as_media(ir):
    """A copy of `ir` where each mesh of an index-matched subsurface material has that material's
    medium inside (`index_matched_subsurface`), for a scene that is one such object under a
    constant environment and nothing else."""
    mats = ir.get("materials", [])
    sub = {i: index_matched_subsurface(m, f"/materials/{i}") for i, m in enumerate(mats)
           if m["type"] == "principled" and m.get("subsurface") is not None}
    if not sub:
        return ir
    meshes = ir.get("meshes", [])
    if (len(meshes) != 1 or ir.get("instances") or ir.get("lights") or ir.get("media")
            or ir.get("environment") is None or ir["environment"].get("texture") is not None):
        raise Unsupported("a subsurface material is translated only in a scene of one mesh "
                          "under a constant environment, with no lights or media")
    ir = json.loads(json.dumps(ir))
    mesh = ir["meshes"][0]
    if mesh.get("material") not in sub:
        raise Unsupported("/meshes/0: the subsurface scene's mesh has another material")
    ir["media"] = [sub[mesh["material"]]]
    mesh["interior_medium"] = 0
    return ir


def points_inside(P, F, Q):
    """Parity test: which points Q (n x 3) lie inside the closed triangle mesh (P, F)."""
    d = np.array([0.5773502692, 0.5773502691, 0.5773502693])  # not along any axis or face
    d = d + np.array([1e-3, -2e-3, 3e-3])
    d /= np.linalg.norm(d)
    v0, v1, v2 = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    e1, e2 = v1 - v0, v2 - v0
    h = np.cross(d, e2)
    a = np.einsum("ij,ij->i", e1, h)
    ok = np.abs(a) > 1e-12
    f = np.where(ok, 1.0 / np.where(ok, a, 1.0), 0.0)
    inside = np.zeros(len(Q), dtype=bool)
    for k, q in enumerate(Q):
        s = q - v0
        u = f * np.einsum("ij,ij->i", s, h)
        qv = np.cross(s, e1)
        v = f * (qv @ d)
        t = f * np.einsum("ij,ij->i", e2, qv)
        hits = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
        inside[k] = bool(np.count_nonzero(hits) & 1)
    return inside


def transmits(m):
    """Whether light can pass into the inside of a surface with material m."""
    t = m["type"]
    return t == "dielectric" or (t == "principled" and float(m.get("transmission", 0.0)) > 0)


def media_assignment(ir, placements):
    """Per placement (interior, exterior) medium indices into ir["media"] (None = vacuum), and
    the camera's medium.

    Rules (our IR: the medium along a ray is that of the innermost enclosing mesh medium, else the
    world medium). Mitsuba instead switches media at each crossing to the crossed shape's
    `interior` or `exterior`, so each shape that a ray can cross gets both:
      * a mesh with `interior_medium`: interior = that medium;
      * a mesh without one whose material transmits (dielectric): interior = vacuum (clear
        glass; the medium around it does not continue inside);
      * exterior = the medium of the innermost medium mesh that contains the whole mesh (every
        vertex inside by a ray-parity test), else `world_medium`;
      * opaque meshes without `interior_medium` get no media: Mitsuba keeps the ray's current
        medium when it reflects off them, which is right on whichever side they are;
      * a medium or glass mesh that partly overlaps a medium mesh is refused (Mitsuba has no
        "entered last wins" stack).
    """
    mats = ir.get("materials", [])
    meshes = ir.get("meshes", [])
    world = ir.get("world_medium")
    media_meshes = [k for k, (i, *_rest) in enumerate(placements)
                    if meshes[i].get("interior_medium") is not None]
    volume = {}
    for k in media_meshes:
        P = placements[k][2]
        volume[k] = float(np.prod(P.max(axis=0) - P.min(axis=0)))

    def enclosing(Q, skip):
        best = None
        for k in media_meshes:
            if k == skip:
                continue
            _, name, P, _, F = placements[k]
            inside = points_inside(P, F, Q)
            if inside.all():
                if best is None or volume[k] < volume[best]:
                    best = k
            elif inside.any():
                raise Unsupported(f"a mesh partly overlaps the medium mesh {name!r}")
        return None if best is None else meshes[placements[best][0]]["interior_medium"]

    out = []
    for k, (i, name, P, _, F) in enumerate(placements):
        m = meshes[i]
        ids = m.get("material_indices") or [m.get("material", 0)]
        has_medium = m.get("interior_medium") is not None
        crossable = has_medium or any(transmits(mats[j]) for j in set(ids))
        if not crossable:
            out.append((None, None, False))
            continue
        outer = enclosing(P, k)
        out.append((m.get("interior_medium"), world if outer is None else outer, True))
    cam = mat(ir.get("camera", {}).get("transform", np.eye(4)))[:3, 3]
    cam_outer = enclosing(cam[None, :], None)
    return out, world if cam_outer is None else cam_outer


def mesh_objects(ir, mats, media):
    """Meshes (and instances) with their transforms applied, split per material, with their
    media (see media_assignment); also returns the camera's medium index."""
    meshes = ir.get("meshes", [])
    placements = mesh_placements(ir)
    assignment, cam_medium = media_assignment(ir, placements)
    out = {}
    for k, (i, name, P, N, F) in enumerate(placements):
        m = meshes[i]
        interior, exterior, crossable = assignment[k]
        per_tri = m.get("material_indices")
        mat_ids = np.array(per_tri) if per_tri is not None else np.full(len(F), m.get("material", 0))
        for mid in np.unique(mat_ids):
            sel = F[mat_ids == mid]
            used = np.unique(sel)
            remap = np.full(len(P), -1)
            remap[used] = np.arange(len(used))
            bsdf, radiance = mats[int(mid)]
            key = f"{k:03d}_{name}_{mid}"
            out[key] = make_mesh(
                key, P[used], None if N is None else N[used], remap[sel], bsdf, radiance,
                interior=media[interior] if crossable and interior is not None else None,
                exterior=media[exterior] if crossable and exterior is not None else None)
    return out, cam_medium


def world_area_scale(M):
    """Area scale of the local XY plane under M."""
    return float(np.linalg.norm(np.cross(M[:3, 0], M[:3, 1])))


def light_objects(ir):
    out = {}
    # Our lights are not surfaces: they reflect nothing and rays pass through them (Cycles
    # draws lights this way). Mitsuba's `null` BSDF lets paths through while the shape's
    # emitter stays visible.
    black = {"type": "null"}
    for i, l in enumerate(ir.get("lights", [])):
        t = l["type"]
        col = np.array(l.get("color", [1, 1, 1]), dtype=np.float64)
        where = f"/lights/{i}"
        if t == "point":
            r = float(l.get("radius", 0.0))
            if r == 0.0:
                out[f"light{i}"] = {"type": "point", "position": [float(v) for v in l["position"]],
                                    "intensity": rgb(col * l["power"] / (4 * math.pi))}
                continue
            t = "sphere"  # a point light with a radius is a sphere light
        if t == "sphere":
            r = float(l["radius"])
            out[f"light{i}"] = {
                "type": "sphere", "center": [float(v) for v in l["position"]], "radius": r,
                "bsdf": black,
                "emitter": {"type": "area",
                            "radiance": rgb(col * l["power"] / (4 * math.pi ** 2 * r * r))},
            }
        elif t in ("rect", "disk"):
            if l.get("two_sided", False):
                raise Unsupported(f"{where}: two-sided area lights are not translated")
            M = mat(l.get("transform", np.eye(4)))
            if t == "rect":
                sx, sy = 0.5 * l["width"], 0.5 * l["height"]  # Mitsuba's rectangle is [-1,1]^2
                area = l["width"] * l["height"]
            else:
                sx = sy = float(l["radius"])  # Mitsuba's disk has radius 1
                area = math.pi * sx * sx
            area *= world_area_scale(M)
            # Our light emits along local -Z, Mitsuba's along +Z: rotate by pi about X
            # (y -> -y, z -> -z), then scale the unit shape, then our transform.
            T = M @ np.diag([sx, -sy, -1.0, 1.0])
            out[f"light{i}"] = {
                "type": "rectangle" if t == "rect" else "disk",
                "to_world": mi.ScalarTransform4f(T),
                "bsdf": black,
                "emitter": {"type": "area", "radiance": rgb(col * l["power"] / (math.pi * area))},
            }
        elif t == "distant":
            if float(l.get("angle", 0.0)) != 0.0:
                raise Unsupported(f"{where}: distant lights with an angle are not translated")
            out[f"light{i}"] = {"type": "directional",
                                "direction": [float(v) for v in l["direction"]],
                                "irradiance": rgb(col * l["irradiance"])}
        elif t == "spot":
            if float(l.get("blend", 0.0)) != 0.0:
                raise Unsupported(f"{where}: spot lights with blend > 0 are not translated "
                                  "(Blender's smoothstep blend differs from Mitsuba's linear "
                                  "falloff in angle); use blend 0, a hard cone")
            if float(l.get("radius", 0.0)) != 0.0:
                raise Unsupported(f"{where}: spot lights with a radius are not translated")
            pos = np.array(l["position"], dtype=np.float64)
            d = np.array(l["direction"], dtype=np.float64)
            d /= np.linalg.norm(d)
            up = [0.0, 1.0, 0.0] if abs(d[1]) < 0.9 else [1.0, 0.0, 0.0]  # any; the cone is round
            half = math.degrees(0.5 * float(l["cone_angle"]))
            out[f"light{i}"] = {
                "type": "spot",
                "to_world": mi.ScalarTransform4f().look_at(origin=pos.tolist(),
                                                           target=(pos + d).tolist(), up=up),
                "intensity": rgb(col * l["power"] / (4 * math.pi)),
                "cutoff_angle": half,
                "beam_width": half,  # full intensity up to the cutoff: a hard edge (blend 0)
            }
        else:
            raise Unsupported(f"{where}: light type {t!r} is not translated")
    return out


def camera_object(ir, spp, medium=None):
    cam = ir.get("camera", {})
    film = ir.get("film", {"width": 256, "height": 256})
    w, h = int(film["width"]), int(film["height"])
    fit = cam.get("sensor_fit", "auto")
    horizontal = fit == "horizontal" or (fit == "auto" and w >= h)
    fov = cam.get("fov")
    if fov is None:
        # Blender's rule: the fitted side of the sensor over the focal length.
        if horizontal:
            sensor = cam.get("sensor_width", 36.0)
        else:
            sensor = cam.get("sensor_height") or cam.get("sensor_width", 36.0)
        fov = 2.0 * math.atan(0.5 * sensor / cam.get("focal_length", 50.0))
    if any(float(s) != 0.0 for s in cam.get("shift", [0, 0])):
        raise Unsupported("/camera/shift: lens shift is not translated")
    if float(cam.get("fstop") or 0.0) != 0.0:
        raise Unsupported("/camera/fstop: depth of field is not translated")
    C = mat(cam.get("transform", np.eye(4)))
    origin = C[:3, 3]
    forward = -C[:3, 2] / np.linalg.norm(C[:3, 2])  # our camera looks down its local -Z
    up = C[:3, 1] / np.linalg.norm(C[:3, 1])        # with local +Y up
    # Mitsuba's camera looks down +Z; look_at puts +Y up and keeps the image unmirrored.
    to_world = mi.ScalarTransform4f().look_at(origin=origin.tolist(),
                                              target=(origin + forward).tolist(),
                                              up=up.tolist())
    near = max(float(cam.get("near", 1e-3)), 1e-4)
    far = min(float(cam.get("far", 1e30)), 1e7)
    cam_dict = {
        "type": "perspective",
        "fov": math.degrees(fov),
        "fov_axis": "x" if horizontal else "y",
        "near_clip": near,
        "far_clip": far,
        "to_world": to_world,
        "sampler": {"type": "independent", "sample_count": spp},
        "film": {
            "type": "hdrfilm", "width": w, "height": h, "pixel_format": "rgb",
            "component_format": "float32",
            "rfilter": {"type": "box"},  # 1-pixel box: a pixel is the mean of its samples
        },
    }
    if medium is not None:
        cam_dict["medium"] = medium
    return cam_dict


def translate(ir, spp):
    """Our scene IR (a dict from JSON) -> a Mitsuba scene dict.

    Rules: matrices are used as they stand (both are column-vector convention); mesh vertices
    are moved to world space here, normals by the inverse transpose. Area lights become
    Mitsuba shapes with an `area` emitter of radiance P/(pi A) * color, A the world-space area,
    and a `null` BSDF (our lights reflect nothing and occlude nothing); point lights have
    intensity P/(4 pi).
    """
    if ir.get("textures"):
        raise Unsupported("/textures: textures are not translated")
    ir = subsurface_as_media(ir)
    mats = [bsdf_of(m, f"/materials/{i}") for i, m in enumerate(ir.get("materials", []))]
    media = [medium_object(md) for md in ir.get("media", [])]
    shapes, cam_medium = mesh_objects(ir, mats, media)
    scene = {"type": "scene",
             "camera": camera_object(ir, spp, None if cam_medium is None else media[cam_medium])}
    scene.update(shapes)
    scene.update(light_objects(ir))
    env = ir.get("environment")
    if env is not None:
        if env.get("texture") is not None:
            raise Unsupported("/environment/texture: environment textures are not translated")
        scene["environment"] = {
            "type": "constant",
            "radiance": rgb(np.array(env.get("color", [1, 1, 1])) * env.get("strength", 1.0)),
        }
    return scene


# ----------------------------------------------------------------------------------------
# direct + specular + emission
# ----------------------------------------------------------------------------------------


def mis_weight(a, b):
    """Power heuristic."""
    a2, b2 = dr.square(a), dr.square(b)
    return dr.detach(dr.select(a2 > 0, a2 / (a2 + b2), 0))


def register_direct_specular():
    # Defined after mi.set_variant(), which mi.SamplingIntegrator depends on. Module-level
    # helpers only: @dr.syntax rewrites `sample` and loses closure variables.
    class DirectSpecular(mi.SamplingIntegrator):
        """Our `direct + specular + emission` terms; the definition is in the module docstring."""

        def __init__(self, props):
            super().__init__(props)
            self.max_specular_depth = props.get("max_specular_depth", 8)

        @dr.syntax
        def sample(self, scene, sampler, ray, medium=None, active=True):
            ctx = mi.BSDFContext()
            ray = mi.Ray3f(ray)
            L = mi.Spectrum(0)
            beta = mi.Spectrum(1)
            depth = mi.UInt32(0)  # specular bounces so far
            active = mi.Bool(active)
            valid = mi.Bool(False)
            while active:
                si = scene.ray_intersect(ray, ray_flags=mi.RayFlags.All, coherent=depth == 0,
                                         active=active)
                valid |= (depth == 0) & si.is_valid()
                # Emission seen from the camera or through delta bounces: weight 1.
                L += beta * si.emitter(scene, active).eval(si, active)
                hit = active & si.is_valid()
                bsdf = si.bsdf(ray)
                flags = bsdf.flags()
                delta_only = (mi.has_flag(flags, mi.BSDFFlags.Delta)
                              & ~mi.has_flag(flags, mi.BSDFFlags.Smooth))
                shade = hit & ~delta_only  # first non-delta surface: direct light, then stop

                # Emitter sampling.
                ds, em_weight = scene.sample_emitter_direction(si, sampler.next_2d(shade), True,
                                                               shade)
                em_ok = shade & (ds.pdf != 0)
                wo = si.to_local(ds.d)
                f_em, pdf_em = bsdf.eval_pdf(ctx, si, wo, em_ok)
                w_em = dr.select(ds.delta, 1.0, mis_weight(ds.pdf, pdf_em))
                L += dr.select(em_ok, beta * f_em * em_weight * w_em, 0)

                # BSDF sampling (also the specular continuation).
                bs, bsdf_w = bsdf.sample(ctx, si, sampler.next_1d(hit), sampler.next_2d(hit), hit)
                ray_next = si.spawn_ray(si.to_world(bs.wo))
                bs_ok = shade & (bs.pdf > 0)
                si_b = scene.ray_intersect(ray_next, ray_flags=mi.RayFlags.All, coherent=False,
                                           active=bs_ok)
                emitter_b = si_b.emitter(scene, bs_ok)
                ds_b = mi.DirectionSample3f(scene, si_b, si)
                sampled_delta = mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta)
                pdf_light = scene.pdf_emitter_direction(si, ds_b, bs_ok & ~sampled_delta)
                w_b = dr.select(sampled_delta, 1.0, mis_weight(bs.pdf, pdf_light))
                L += dr.select(bs_ok, beta * bsdf_w * emitter_b.eval(si_b, bs_ok) * w_b, 0)

                # Continue along delta chains only.
                cont = hit & delta_only & (bs.pdf > 0) & (depth < self.max_specular_depth)
                beta *= dr.select(cont, bsdf_w, 0)
                cont &= dr.max(beta) > 0
                ray = dr.select(cont, ray_next, ray)
                depth += 1
                active = cont
            return L, valid, []

        def aov_names(self):
            return []

        def to_string(self):
            return f"DirectSpecular[max_specular_depth={self.max_specular_depth}]"

    mi.register_integrator("direct_specular", lambda props: DirectSpecular(props))


# ----------------------------------------------------------------------------------------
# Rendering in batches
# ----------------------------------------------------------------------------------------


def write_exr(path, img):
    import OpenImageIO as oiio

    img = np.ascontiguousarray(img, dtype=np.float32)
    spec = oiio.ImageSpec(img.shape[1], img.shape[0], 3, oiio.FLOAT)
    spec.channelnames = ("R", "G", "B")
    spec.attribute("compression", "zip")
    out = oiio.ImageOutput.create(path)
    if out is None or not out.open(path, spec):
        raise RuntimeError(f"cannot write {path}: {oiio.geterror()}")
    out.write_image(img)
    out.close()


def render_reference(name, spp_total, batches, variant, out_dir):
    scene_path, integrator, _, _ = REFERENCES[name]
    with open(os.path.join(ROOT, scene_path)) as f:
        ir = json.load(f)
    spp_batch = max(1, spp_total // batches)
    passes = max(1, math.ceil(spp_batch / MAX_SPP_PER_PASS))
    spp_pass = math.ceil(spp_batch / passes)
    spp_batch = spp_pass * passes
    scene = mi.load_dict(translate(ir, spp_pass))
    integ = mi.load_dict(integrator)
    t0 = time.time()
    imgs = []
    for b in range(batches):
        acc = None
        for p in range(passes):
            img = np.array(mi.render(scene, integrator=integ, spp=spp_pass,
                                     seed=b * passes + p), dtype=np.float64)
            acc = img if acc is None else acc + img
        imgs.append(acc / passes)
        print(f"  {name}: batch {b + 1}/{batches} ({time.time() - t0:.0f} s)", flush=True)
    seconds = time.time() - t0
    stack = np.stack(imgs)
    mean = stack.mean(axis=0)
    stderr = stack.std(axis=0, ddof=1) / math.sqrt(batches)
    floor = float(np.mean(stderr ** 2 / (mean ** 2 + 1e-2)))
    os.makedirs(out_dir, exist_ok=True)
    write_exr(os.path.join(out_dir, f"{name}.exr"), mean)
    write_exr(os.path.join(out_dir, f"{name}.stderr.exr"), stderr)
    meta = {
        "name": name,
        "scene": scene_path,
        "integrator": integrator,
        "renderer": f"Mitsuba {mi.__version__}",
        "variant": variant,
        "spp": spp_batch * batches,
        "batches": batches,
        "spp_per_batch": spp_batch,
        "seeds": f"batch b renders {passes} passes of {spp_pass} spp with seeds "
                 f"b*{passes} .. b*{passes}+{passes - 1}",
        "width": int(mean.shape[1]),
        "height": int(mean.shape[0]),
        "seconds": round(seconds, 1),
        "mean_pixel_value": float(mean.mean()),
        "mean_pixel_rgb": [float(v) for v in mean.reshape(-1, 3).mean(axis=0)],
        "relmse_noise_floor": floor,
        "relmse_definition": "mean over pixels and channels of stderr^2 / (mean^2 + 1e-2)",
        "command": f"python3 scripts/make_references.py {name} --spp {spp_batch * batches} "
                   f"--batches {batches} --variant {variant}",
    }
    with open(os.path.join(out_dir, f"{name}.json"), "w") as f:
        json.dump(meta, f, indent=2)
        f.write("\n")
    print(f"{name}: {meta['spp']} spp in {seconds:.0f} s, mean {meta['mean_pixel_value']:.4f}, "
          f"relMSE floor {floor:.3g}", flush=True)
    return meta


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("names", nargs="*", help=f"references to render (default all: "
                                             f"{', '.join(REFERENCES)})")
    ap.add_argument("--spp", type=int, help="total samples per pixel (default: per reference)")
    ap.add_argument("--batches", type=int, help="independent batches (default: per reference)")
    ap.add_argument("--variant", default="llvm_ad_rgb", help="Mitsuba variant")
    ap.add_argument("--out", default=OUT_DIR, help="output directory")
    args = ap.parse_args()
    mi.set_variant(args.variant)
    register_direct_specular()
    for name in args.names or list(REFERENCES):
        if name not in REFERENCES:
            ap.error(f"unknown reference {name!r}")
        _, _, spp, batches = REFERENCES[name]
        render_reference(name, args.spp or spp, args.batches or batches, args.variant, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
