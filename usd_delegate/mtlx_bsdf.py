"""MaterialX ``ND_surface`` with a single pbrlib BSDF or EDF -> an IR material.

Blender's USD exporter writes its non-Principled shader nodes this way (Diffuse, Glossy,
Glass and Emission BSDF nodes), and MaterialX documents built by hand often do too.

| pbrlib node on ``ND_surface`` | IR material |
|---|---|
| ``bsdf``: ``ND_oren_nayar_diffuse_bsdf`` (color x weight) | `diffuse` (roughness > 0 read as Lambert, warned) |
| ``bsdf``: ``ND_conductor_bsdf`` (ior/extinction, or from ``ND_artistic_ior``'s reflectivity) | `glossy` with its normal-incidence reflectance, multiscatter GGX |
| ``bsdf``: ``ND_dielectric_bsdf`` (ior, roughness, tint; scatter_mode RT) | `dielectric`, multiscatter GGX |
| ``edf``: ``ND_uniform_edf`` (color), no ``bsdf`` | `emission` |

Anisotropic roughness (a float2 with different components) is read as its mean, warned.
Mixed, added or layered BSDFs (``GRAPH_ONLY``), an ``edf`` beside a ``bsdf`` and computed
inputs make a shading graph (materials.py, shading_graph.py); other nodes are warned and render
grey diffuse; ``opacity`` below 1 is warned and ignored.
"""

from __future__ import annotations

GREY = [0.18, 0.18, 0.18]
#: pbrlib nodes read here as one flat material.
FLAT = ("ND_oren_nayar_diffuse_bsdf", "ND_conductor_bsdf", "ND_dielectric_bsdf",
        "ND_uniform_edf")
#: Nodes only a shading graph expresses (shading_graph.py).
GRAPH_ONLY = ("ND_mix_bsdf", "ND_add_bsdf", "ND_mix_edf", "ND_add_edf", "ND_translucent_bsdf",
              "ND_burley_diffuse_bsdf", "ND_layer_bsdf")


def _roughness(table, shader, diag):
    inp = shader.GetInput("roughness")
    v = inp.Get(table.time) if inp else None
    if v is None:
        return 0.0
    try:
        a, b = float(v[0]), float(v[1])
    except TypeError:
        a = b = float(v)
    if abs(a - b) > 1e-6:
        diag.warn(shader.GetPrim(), f"anisotropic roughness ({a:g}, {b:g}) read as its mean")
    return min(1.0, max(0.0, 0.5 * (a + b)))


def _value(table, shader, name, default):
    inp = shader.GetInput(name)
    v = inp.Get(table.time) if inp else None
    return default if v is None else v


def _conductor_f0(table, shader):
    """Normal-incidence reflectance of a conductor_bsdf: from ND_artistic_ior's reflectivity
    when its ior comes from one, else from the complex IOR n + ik."""
    src = table._source(shader, "ior")
    if src is not None and src[0].GetIdAttr().Get() == "ND_artistic_ior":
        art = src[0]
        refl = [float(c) for c in _value(table, art, "reflectivity", (0.944, 0.776, 0.373))]
        edge = [float(c) for c in _value(table, art, "edge_color", (0.998, 0.981, 0.751))]
        if any(abs(r - e) > 1e-3 for r, e in zip(refl, edge)):
            table.diag.warn(art.GetPrim(), "edge_color differs from reflectivity: the edge tint "
                                           "is not modelled (reflectivity used)")
        return [min(1.0, max(0.0, c)) for c in refl]
    n = [float(c) for c in _value(table, shader, "ior", (0.271, 0.677, 1.316))]
    k = [float(c) for c in _value(table, shader, "extinction", (3.609, 2.625, 2.292))]
    return [((a - 1) ** 2 + b * b) / ((a + 1) ** 2 + b * b) for a, b in zip(n, k)]


def read_surface(table, material, surface) -> dict:
    """The IR material for ``surface`` (an ``ND_surface`` shader) of ``material``."""
    diag = table.diag
    name = str(material.GetPath())
    grey = {"type": "diffuse", "name": name, "color": list(GREY)}
    op = _value(table, surface, "opacity", 1.0)
    if op is not None and float(op) < 1.0:
        diag.warn(surface.GetPrim(), f"opacity {float(op):g} is not supported; opaque")
    bsdf = table._source(surface, "bsdf")
    edf = table._source(surface, "edf")
    if bsdf is None and edf is None:
        diag.warn(surface.GetPrim(), "ND_surface with neither bsdf nor edf connected; black")
        return {"type": "diffuse", "name": name, "color": [0.0, 0.0, 0.0]}
    if bsdf is None:
        e = edf[0]
        if e.GetIdAttr().Get() != "ND_uniform_edf":
            diag.warn(e.GetPrim(), f"EDF `{e.GetIdAttr().Get()}` is not supported; grey diffuse used")
            return grey
        return {"type": "emission", "name": name,
                "color": table.color(e, "color", {"color": (1.0, 1.0, 1.0)}), "strength": 1.0}
    if edf is not None:
        diag.warn(edf[0].GetPrim(), "an EDF beside a BSDF is not supported; the emission is ignored")
    s = bsdf[0]
    sid = str(s.GetIdAttr().Get() or "")
    if sid == "ND_oren_nayar_diffuse_bsdf":
        weight = float(_value(table, s, "weight", 1.0))
        r = _roughness(table, s, diag)
        if r > 0:
            diag.warn(s.GetPrim(), f"Oren-Nayar roughness {r:g} is read as Lambert")
        return {"type": "diffuse", "name": name,
                "color": table.color(s, "color", {"color": (0.18, 0.18, 0.18)}, scale=weight)}
    if sid == "ND_conductor_bsdf":
        weight = float(_value(table, s, "weight", 1.0))
        f0 = _conductor_f0(table, s)
        return {"type": "glossy", "name": name, "color": [weight * c for c in f0],
                "roughness": _roughness(table, s, diag), "multiscatter": True}
    if sid == "ND_dielectric_bsdf":
        mode = str(_value(table, s, "scatter_mode", "R"))
        if mode != "RT":
            diag.warn(s.GetPrim(), f"scatter_mode `{mode}` is read as RT (reflection and "
                                   f"transmission)")
        tint = table.color(s, "tint", {"tint": (1.0, 1.0, 1.0)})
        if isinstance(tint, dict):
            diag.warn(s.GetPrim(), "a texture on `tint` is not supported; white")
            tint = [1.0, 1.0, 1.0]
        return {"type": "dielectric", "name": name,
                "ior": max(1.0, float(_value(table, s, "ior", 1.5))),
                "roughness": _roughness(table, s, diag), "color": tint, "multiscatter": True}
    diag.warn(s.GetPrim(), f"BSDF `{sid}` is not supported; grey diffuse used")
    return grey
