#!/usr/bin/env python3
"""Writes the participating-media test scenes in photonmap's JSON scene IR (src/scene/desc.rs).

    python3 scripts/make_media_scenes.py    # run from the repository root; needs only numpy

Outputs (all 128x128; world +Y up, lengths in scene units)
    tests/data/scenes/fog_spot.json      fog box lit by a hard-edged spot light, with an opaque
                                         occluder inside the fog casting a volumetric shadow
    tests/data/scenes/fog_glass.json     glass sphere inside a fog box under a small shielded
                                         disk light: a volume caustic and a floor caustic
    tests/data/scenes/thick_sphere.json  sphere of dense scattering medium (albedo 0.95) above a
                                         floor, lit by a rect light and a point light
    tests/data/scenes/sss_sphere.json    sphere of an index-matched subsurface material under a
                                         constant environment (64x64)
    tests/data/scenes/sss_slab.json      slab of the same kind, turned to show three faces (64x64)

Common layout: a white diffuse floor (y = 0) and back wall (z = -2), camera at z = 5 looking
towards the origin. Medium boundaries are closed meshes with the `null` material and an
`interior_medium`; their triangles wind so that (p1-p0) x (p2-p0) points out of the volume
(checked below). The fog boxes stop 0.002 above the floor, so the floor is never inside a
medium and no two surfaces coincide.

fog_glass uses a disk light, not a spot light: light from a point (delta) source that reaches the
fog through glass can only be found by tracing from the light, so a path tracer (the Mitsuba
reference) would render the caustics as black. The disk (radius 0.12, 40 W, emitting down) sits
at the top of a black square tube (half-width 0.2, 0.6 long) that limits its light to a cone:
fully lit within about 7.6 degrees of the axis, penumbra out to 28 degrees; the glass sphere
(radius 0.35, 1.7 below the light) subtends 11.6 degrees. Its paraxial image of the lamp lies
about 0.76 below the sphere's centre (ball-lens focal length n r / 2(n-1) = 0.525), i.e. in the
fog above the floor.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_scenes import ROOT, dump, quad, rounded, translate, uv_sphere  # noqa: E402

WHITE = [0.75, 0.75, 0.75]
FOG = {"name": "fog", "sigma_a": [0.05, 0.05, 0.05], "sigma_s": [0.4, 0.4, 0.4], "g": 0.3}


def look_at(eye, target, up=(0.0, 1.0, 0.0)):
    """Camera-to-world for our camera (looks down its local -Z, +Y up)."""
    eye, target, up = (np.array(v, dtype=float) for v in (eye, target, up))
    z = eye - target
    z /= np.linalg.norm(z)
    x = np.cross(up, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    M = np.eye(4)
    M[:3, 0], M[:3, 1], M[:3, 2], M[:3, 3] = x, y, z, eye
    return rounded(M, 7)


def box_mesh(name, lo, hi, material, interior_medium=None):
    """Closed axis-aligned box, 8 vertices, 12 triangles with outward winding, flat shading."""
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    P = np.array([[(hi if (i >> k) & 1 else lo)[k] for k in range(3)] for i in range(8)])
    # Vertex i has x = hi if bit 0, y = hi if bit 1, z = hi if bit 2.
    faces = [
        (0, 4, 6, 2),  # -X
        (1, 3, 7, 5),  # +X
        (0, 1, 5, 4),  # -Y
        (2, 6, 7, 3),  # +Y
        (0, 2, 3, 1),  # -Z
        (4, 5, 7, 6),  # +Z
    ]
    T = []
    for a, b, c, d in faces:
        T += [[a, b, c], [a, c, d]]
    T = np.array(T)
    check_outward(name, P, T)
    mesh = {"name": name, "positions": rounded(P), "indices": T.tolist(), "material": material}
    if interior_medium is not None:
        mesh["interior_medium"] = interior_medium
    return mesh


def check_outward(name, P, T):
    """Every triangle's geometric normal points away from the (convex) mesh's centre."""
    g = np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]])
    c = P[T].mean(axis=1) - P.mean(axis=0)
    assert (np.einsum("ij,ij->i", g, c) > 0).all(), name


def sphere(name, center, radius, material, interior_medium=None):
    P, T = uv_sphere()
    P = P / np.linalg.norm(P, axis=1, keepdims=True)
    check_outward(name, P, T)
    mesh = {
        "name": name,
        "positions": rounded(P),
        "indices": T.tolist(),
        "normals": rounded(P),
        "material": material,
        "transform": translate(center, radius),
    }
    if interior_medium is not None:
        mesh["interior_medium"] = interior_medium
    return mesh


def room(material):
    """Floor (y = 0) and back wall (z = -2), both facing the camera side."""
    return [
        quad("floor", (-3, 0, 3), (3, 0, 3), (3, 0, -2), (-3, 0, -2), (0, 1, 0), material),
        quad("back", (-3, 0, -2), (3, 0, -2), (3, 4, -2), (-3, 4, -2), (0, 0, 1), material),
    ]


def normalized(v):
    v = np.array(v, dtype=float)
    return [round(float(x), 7) for x in v / np.linalg.norm(v)]


def camera(eye, target, fov):
    return {"transform": look_at(eye, target), "fov": fov}


def fog_spot():
    light_pos = np.array([0.3, 2.3, 0.0])
    direction = normalized(np.array([0.0, 0.0, 0.0]) - light_pos)
    return {
        "camera": camera((0.0, 1.3, 5.0), (0.0, 0.7, 0.0), 0.72),
        "film": {"width": 128, "height": 128},
        "materials": [
            {"type": "diffuse", "name": "white", "color": WHITE},
            {"type": "diffuse", "name": "occluder", "color": [0.5, 0.5, 0.5]},
            {"type": "null", "name": "fog_boundary"},
        ],
        "media": [FOG],
        "meshes": room(0) + [
            box_mesh("fog_box", (-1.2, 0.002, -1.2), (1.2, 1.6, 1.2), 2, interior_medium=0),
            box_mesh("occluder", (0.01, 0.9, -0.02), (0.25, 1.1, 0.22), 1),
        ],
        "lights": [{
            "type": "spot", "name": "spot", "position": light_pos.tolist(), "direction": direction,
            "power": 200.0, "color": [1.0, 1.0, 1.0], "cone_angle": 0.6, "blend": 0.0,
        }],
    }


def fog_glass():
    light_y, tube_len, tube_hw = 2.7, 0.6, 0.2
    lo, hi = light_y - tube_len, light_y
    h = tube_hw
    # Four black quads around the light, normals facing in (our diffuse reflects on both sides).
    tube = [
        quad("shade_-x", (-h, lo, h), (-h, lo, -h), (-h, hi, -h), (-h, hi, h), (1, 0, 0), 3),
        quad("shade_+x", (h, lo, -h), (h, lo, h), (h, hi, h), (h, hi, -h), (-1, 0, 0), 3),
        quad("shade_-z", (-h, lo, -h), (h, lo, -h), (h, hi, -h), (-h, hi, -h), (0, 0, 1), 3),
        quad("shade_+z", (h, lo, h), (-h, lo, h), (-h, hi, h), (h, hi, h), (0, 0, -1), 3),
    ]
    # Disk emits along its local -Z: local Z -> world +Y, local X -> +X, local Y -> -Z.
    disk_tf = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, light_y - 0.01],
        [0.0, -1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
    return {
        "camera": camera((0.0, 1.3, 5.0), (0.0, 0.85, 0.0), 0.72),
        "film": {"width": 128, "height": 128},
        "materials": [
            {"type": "diffuse", "name": "white", "color": WHITE},
            {"type": "dielectric", "name": "glass", "ior": 1.5},
            {"type": "null", "name": "fog_boundary"},
            {"type": "diffuse", "name": "black", "color": [0.0, 0.0, 0.0]},
        ],
        "media": [FOG],
        "meshes": room(0) + tube + [
            box_mesh("fog_box", (-1.2, 0.002, -1.2), (1.2, 1.7, 1.2), 2, interior_medium=0),
            sphere("glass_sphere", (0.0, 1.0, 0.0), 0.35, 1),
        ],
        "lights": [{
            "type": "disk", "name": "lamp", "transform": disk_tf, "radius": 0.12, "power": 40.0,
            "color": [1.0, 1.0, 1.0],
        }],
    }


def thick_sphere():
    sigma_t, albedo = 8.0, 0.95
    # Rect light 1 x 1 at y = 2.5, emitting down (local -Z -> world -Y).
    rect_tf = [
        [1.0, 0.0, 0.0, 0.9],
        [0.0, 0.0, 1.0, 2.5],
        [0.0, -1.0, 0.0, 0.6],
        [0.0, 0.0, 0.0, 1.0],
    ]
    return {
        "camera": camera((0.0, 1.2, 4.0), (0.0, 0.55, 0.0), 0.6),
        "film": {"width": 128, "height": 128},
        "materials": [
            {"type": "diffuse", "name": "white", "color": WHITE},
            {"type": "null", "name": "medium_boundary"},
        ],
        "media": [{
            "name": "thick",
            "sigma_a": [round(sigma_t * (1 - albedo), 6)] * 3,
            "sigma_s": [round(sigma_t * albedo, 6)] * 3,
            "g": 0.0,
        }],
        "meshes": room(0) + [sphere("thick_sphere", (0.0, 0.6, 0.0), 0.5, 1, interior_medium=0)],
        "lights": [
            {"type": "rect", "name": "key", "transform": rect_tf, "width": 1.0, "height": 1.0,
             "power": 40.0, "color": [1.0, 1.0, 1.0]},
            {"type": "point", "name": "fill", "position": [-1.6, 1.4, 1.8], "power": 25.0,
             "color": [1.0, 1.0, 1.0]},
        ],
    }


def subsurface_material(name, color, radius):
    """A Principled material whose subsurface walk Mitsuba renders exactly: roughness 0, IOR
    1.01 (the least the renderer takes), specular 0, weight 1 (scripts/make_references.py,
    `index_matched_subsurface`)."""
    return {"type": "principled", "name": name, "base_color": color, "roughness": 0.0,
            "ior": 1.01, "specular": 0.0,
            "subsurface": {"weight": 1.0, "radius": radius}}


def sss_sphere():
    """A subsurface sphere (radius 1) under a constant white environment: each pixel is the
    probability that a walk entering there leaves again, per channel."""
    return {
        "camera": camera((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), 0.6),
        "film": {"width": 64, "height": 64},
        "materials": [subsurface_material("wax", [0.85, 0.65, 0.45], [4.0, 2.0, 1.3])],
        "meshes": [sphere("sphere", (0.0, 0.0, 0.0), 1.0, 0)],
        "environment": {"color": [1.0, 1.0, 1.0], "strength": 1.0},
    }


def sss_slab():
    """A subsurface slab (2 x 1.4 x 0.3, flat-shaded, two triangles a face) turned to show
    three faces, under a constant white environment."""
    slab = box_mesh("slab", (-1.0, -0.7, -0.15), (1.0, 0.7, 0.15), 0)
    ay, ax = math.radians(35.0), math.radians(20.0)
    ry = np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]])
    rx = np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]])
    M = np.eye(4)
    M[:3, :3] = rx @ ry
    slab["transform"] = rounded(M, 7)
    return {
        "camera": camera((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), 0.6),
        "film": {"width": 64, "height": 64},
        "materials": [subsurface_material("jade", [0.9, 0.7, 0.5], [1.0, 0.6, 0.4])],
        "meshes": [slab],
        "environment": {"color": [1.0, 1.0, 1.0], "strength": 1.0},
    }


def main():
    for name, fn in (("fog_spot", fog_spot), ("fog_glass", fog_glass),
                     ("thick_sphere", thick_sphere), ("sss_sphere", sss_sphere),
                     ("sss_slab", sss_slab)):
        dump(fn(), os.path.join(ROOT, f"tests/data/scenes/{name}.json"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
