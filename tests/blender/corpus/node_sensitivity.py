"""Small errors put into the shading graphs of node corpus scenes, as the add-on exports them,
which the comparison must see (no bpy here; tests/blender/test_node_sensitivity.py runs them).

Each case changes one node input of a graph material in the IR: a ColorRamp stop moved by
0.05, a Noise Texture's scale 5% off, a Bump's strength 10% off, a cut-out's alpha flipped and
the Vector Rotate angles 2% off; both signs where an error has a sign.

The Bump's strength is checked on nodes_bump_values, where the pixels show the bumped normal.
In a lit room it is not seen: on nodes_bump (distance 0.2) the comparison at "ci" passes it
(+10%: largest statistic 1.01 of its tolerance; -10%: 0.80), since the diffuse shading of a
small tilt changes by a fraction of the tilt's change. Nor is a Displacement's scale 10% off,
on nodes_displacement: both signs pass (+10%: no block beyond tolerance, pixels relMSE 2.95e-2
against 4.24e-2; -10%: 3.94e-2 against 5.51e-2); the pixels' noise floor there is set by a rare
bright blotch of the irradiance cache on the floor by the sphere (one seed of four: a record's
gather reads photons that arrive almost tangent to the floor, each weighed by its lobe's cosine
over the floor's).
"""

from __future__ import annotations


def _nodes(ir, material, kind):
    (m,) = [m for m in ir["materials"] if m.get("name") == material]
    return [n for n in m["nodes"] if n["type"] == kind]


def _ramp_stops(material, delta):
    def modify(ir):
        for n in _nodes(ir, material, "color_ramp"):
            for stop in n["params"]["stops"]:
                stop[0] = min(1.0, max(0.0, stop[0] + delta))
        return ir
    return modify


def _input_scaled(material, kind, socket, f, default):
    def modify(ir):
        for n in _nodes(ir, material, kind):
            v = n.setdefault("inputs", {}).get(socket, default)
            n["inputs"][socket] = f * v
        return ir
    return modify


def _alpha_flipped(material):
    """The Principled's Alpha through an Invert: solid where there were holes."""
    def modify(ir):
        (m,) = [m for m in ir["materials"] if m.get("name") == material]
        for n in [n for n in m["nodes"] if n["type"] == "principled"]:
            m["nodes"].append({"type": "invert", "inputs": {"color": n["inputs"]["alpha"]}})
            n["inputs"]["alpha"] = {"node": len(m["nodes"]) - 1, "output": "color"}
        return ir
    return modify


#: case -> (scene, the error put in).
CASES = {
    "ramp_stops_0.05_later": ("nodes_wood", _ramp_stops("Wood", 0.05)),
    "ramp_stops_0.05_earlier": ("nodes_wood", _ramp_stops("Wood", -0.05)),
    "noise_scale_5pct_larger": ("nodes_noise_values", _input_scaled(
        "NoiseValues", "noise_texture", "scale", 1.05, 5.0)),
    "noise_scale_5pct_smaller": ("nodes_noise_values", _input_scaled(
        "NoiseValues", "noise_texture", "scale", 0.95, 5.0)),
    "bump_strength_10pct_larger": ("nodes_bump_values", _input_scaled(
        "BumpValues", "bump", "strength", 1.1, 1.0)),
    "bump_strength_10pct_smaller": ("nodes_bump_values", _input_scaled(
        "BumpValues", "bump", "strength", 0.9, 1.0)),
    "alpha_flipped": ("nodes_leaf_alpha", _alpha_flipped("Leaf")),
    "rotate_angle_2pct_larger": ("nodes_vector_rotate_values", _input_scaled(
        "VectorRotateValues", "vector_rotate", "angle", 1.02, 0.0)),
    "rotate_angle_2pct_smaller": ("nodes_vector_rotate_values", _input_scaled(
        "VectorRotateValues", "vector_rotate", "angle", 0.98, 0.0)),
}
