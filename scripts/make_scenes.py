#!/usr/bin/env python3
"""Writes the Cornell-box test scenes in photonmap's JSON scene IR (see src/scene/desc.rs).

    python3 scripts/make_scenes.py          # run from the repository root; needs only numpy

Outputs
    tests/data/scenes/cornell_diffuse.json   diffuse box, 128x128
    tests/data/scenes/cornell_spheres.json   the box plus a mirror and a glass sphere, 128x128
    src/scene/default_scene.json             cornell_spheres at 512x512 (the default scene)

The box follows Mitsuba's `cbox` proportions: walls on [-1,1]^3, open at +Z, camera at
(0,0,4) looking down -Z with +Y up (our camera convention: it looks down its local -Z), so the
identity rotation suffices and world +X is image right. Red wall at x=-1 (image left), green
wall at x=+1 (image right), white floor (y=-1), ceiling (y=+1) and back wall (z=-1).

A rectangular light of 0.5 x 0.4 sits just below the ceiling (y=0.99) and emits downwards.
Our rect light emits along its local -Z, so its transform maps local +Z to world +Y
(columns: local X -> world +X, local Y -> world -Z, local Z -> world +Y). With power P = 10 W
and area A = 0.2 its radiance is P/(pi A) = 15.92.

Spheres are UV spheres (48 segments x 32 rings = 2976 triangles) with per-vertex normals,
stored as a unit sphere in object space and placed by `transform` (uniform scale, then
translation), so the scenes also exercise mesh transforms.
"""
import json
import math
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

WHITE = [0.75, 0.75, 0.75]
RED = [0.63, 0.065, 0.05]
GREEN = [0.14, 0.45, 0.091]

# Camera: Mitsuba cbox, fov 39.3077 degrees across the (horizontal) larger side.
CAMERA_POS = (0.0, 0.0, 4.0)
FOV = math.radians(39.3077)

LIGHT_Y = 0.99
LIGHT_W, LIGHT_H = 0.5, 0.4
LIGHT_POWER = 10.0  # W; radiance = P / (pi * A) = 15.915

SPHERE_R = 0.35
MIRROR_CENTER = (-0.45, -1.0 + SPHERE_R, -0.35)
GLASS_CENTER = (0.45, -1.0 + SPHERE_R, 0.25)


def translate(t, s=1.0):
    return [
        [s, 0.0, 0.0, t[0]],
        [0.0, s, 0.0, t[1]],
        [0.0, 0.0, s, t[2]],
        [0.0, 0.0, 0.0, 1.0],
    ]


def quad(name, p0, p1, p2, p3, normal, material):
    """Quad p0,p1,p2,p3 (counter-clockwise seen from the side `normal` points to)."""
    pts = np.array([p0, p1, p2, p3], dtype=float)
    n = np.array(normal, dtype=float)
    # Check the winding agrees with the normal.
    g = np.cross(pts[1] - pts[0], pts[2] - pts[0])
    assert np.dot(g, n) > 0, name
    return {
        "name": name,
        "positions": pts.tolist(),
        "indices": [[0, 1, 2], [0, 2, 3]],
        "normals": [list(normal)] * 4,
        "material": material,
    }


def uv_sphere(segments=48, rings=32):
    """Unit UV sphere: poles on +-Y; returns positions, normals (equal), triangles (outward CCW)."""
    pos = [[0.0, 1.0, 0.0]]
    for i in range(1, rings):
        theta = math.pi * i / rings
        y = math.cos(theta)
        r = math.sin(theta)
        for j in range(segments):
            phi = 2.0 * math.pi * j / segments
            pos.append([r * math.cos(phi), y, -r * math.sin(phi)])
    pos.append([0.0, -1.0, 0.0])
    south = len(pos) - 1
    tris = []

    def ring(i, j):  # i in 1..rings-1
        return 1 + (i - 1) * segments + (j % segments)

    for j in range(segments):
        tris.append([0, ring(1, j), ring(1, j + 1)])
    for i in range(1, rings - 1):
        for j in range(segments):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j), ring(i + 1, j + 1)
            tris.append([a, c, d])
            tris.append([a, d, b])
    for j in range(segments):
        tris.append([ring(rings - 1, j), south, ring(rings - 1, j + 1)])
    P = np.array(pos)
    T = np.array(tris)
    # Every triangle must face outwards.
    g = np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]])
    c = P[T].mean(axis=1)
    assert (np.einsum("ij,ij->i", g, c) > 0).all()
    return P, T


def rounded(a, digits=6):
    return [[round(float(v), digits) for v in row] for row in a]


def sphere_mesh(name, center, material):
    P, T = uv_sphere()
    P = P / np.linalg.norm(P, axis=1, keepdims=True)
    return {
        "name": name,
        "positions": rounded(P),
        "indices": T.tolist(),
        "normals": rounded(P),
        "material": material,
        "transform": translate(center, SPHERE_R),
    }


def box_meshes():
    # Materials: 0 white, 1 red, 2 green. The box is open at +Z; normals face inwards.
    return [
        quad("floor", (-1, -1, 1), (1, -1, 1), (1, -1, -1), (-1, -1, -1), (0, 1, 0), 0),
        quad("ceiling", (-1, 1, 1), (-1, 1, -1), (1, 1, -1), (1, 1, 1), (0, -1, 0), 0),
        quad("back", (-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1), (0, 0, 1), 0),
        quad("left", (-1, -1, 1), (-1, -1, -1), (-1, 1, -1), (-1, 1, 1), (1, 0, 0), 1),
        quad("right", (1, -1, -1), (1, -1, 1), (1, 1, 1), (1, 1, -1), (-1, 0, 0), 2),
    ]


def scene(width, height, spheres):
    materials = [
        {"type": "diffuse", "name": "white", "color": WHITE},
        {"type": "diffuse", "name": "red", "color": RED},
        {"type": "diffuse", "name": "green", "color": GREEN},
    ]
    meshes = box_meshes()
    if spheres:
        materials.append({"type": "mirror", "name": "mirror", "color": [1.0, 1.0, 1.0]})
        materials.append({"type": "dielectric", "name": "glass", "ior": 1.5})
        meshes.append(sphere_mesh("mirror_sphere", MIRROR_CENTER, 3))
        meshes.append(sphere_mesh("glass_sphere", GLASS_CENTER, 4))
    light_tf = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, LIGHT_Y],
        [0.0, -1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]
    return {
        "camera": {"transform": translate(CAMERA_POS), "fov": round(FOV, 7)},
        "film": {"width": width, "height": height},
        "materials": materials,
        "meshes": meshes,
        "lights": [
            {
                "type": "rect",
                "name": "ceiling_light",
                "transform": light_tf,
                "width": LIGHT_W,
                "height": LIGHT_H,
                "power": LIGHT_POWER,
                "color": [1.0, 1.0, 1.0],
            }
        ],
    }


def dump(obj, path):
    """Compact JSON (the meshes make pretty-printing several times larger)."""
    text = json.dumps(obj, separators=(",", ":"))
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)
        f.write("\n")
    print(f"wrote {os.path.relpath(path, ROOT)} ({len(text) // 1024} KB)")


def main():
    dump(scene(128, 128, False), os.path.join(ROOT, "tests/data/scenes/cornell_diffuse.json"))
    dump(scene(128, 128, True), os.path.join(ROOT, "tests/data/scenes/cornell_spheres.json"))
    dump(scene(512, 512, True), os.path.join(ROOT, "src/scene/default_scene.json"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
