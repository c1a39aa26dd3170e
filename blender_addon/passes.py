"""Render passes: ``Combined``, one pass per term of the core (``photonmap.PASS_NAMES``), and
the passes beside the terms, not part of the sum, as the core lists them
(``photonmap.aov_specs``): ``Error`` always, what the settings ask for (``Denoising Albedo``
and ``Denoising Normal``, ``Noisy <Term>``, ``CryptoObject00`` ...), and one
``Combined_<group>`` per light group of the view layer (they sum to ``Combined``). No pass
list is written out here."""

from __future__ import annotations

import numpy as np
import photonmap

from .properties import render_settings

PASS_NAMES: tuple[str, ...] = photonmap.PASS_NAMES
#: IR term (lower case, the keys of ``photonmap.render``'s output) of each term's pass.
TERM_OF_PASS = dict(zip(photonmap.PASS_NAMES, photonmap.TERMS))


def light_groups(view_layer) -> list[str]:
    """The view layer's light groups (the IR's; the core adds ``default``)."""
    return [g.name for g in getattr(view_layer, "lightgroups", None) or []]


def aov_specs(scene, view_layer=None) -> list[dict]:
    """The passes beside the terms that a render of ``scene`` writes (``photonmap.aov_specs``
    for its settings and the view layer's light groups: ``Combined_<group>``, Cycles' names)."""
    settings = render_settings(scene.photonmap) if scene is not None else {}
    return photonmap.aov_specs(light_groups(view_layer), **settings)


def register_passes(engine, scene, view_layer) -> None:
    engine.register_pass(scene, view_layer, "Combined", 4, "RGBA", "COLOR")
    for name in PASS_NAMES:
        engine.register_pass(scene, view_layer, name, 3, "RGB", "COLOR")
    for a in aov_specs(scene, view_layer):
        engine.register_pass(scene, view_layer, a["pass_name"], len(a["channels"]),
                             a["chan_id"], a["pass_type"])


def _rows_bottom_up(img: np.ndarray, channels: int) -> np.ndarray:
    """(H, W, C) rows top to bottom -> (H*W, channels) rows bottom to top, as Blender's (a
    3-channel image given 4 channels gets alpha 1)."""
    h, w = img.shape[:2]
    flipped = img[::-1]
    if channels == 4 and img.shape[2] == 3:
        out = np.ones((h, w, 4), dtype=np.float32)
        out[..., :3] = flipped
    else:
        out = np.ascontiguousarray(flipped, dtype=np.float32)
    return out.reshape(h * w, channels)


def _with_alpha(out: dict) -> np.ndarray:
    """The beauty as (H, W, 4): ``combined`` and its alpha (Film > Transparent, Holdout)."""
    rgb = out["combined"]
    alpha = out.get("alpha")
    if alpha is None:
        return rgb
    return np.concatenate([rgb, alpha[..., None]], axis=2).astype(np.float32, copy=False)


def write_result(engine, out: dict, window, layer_name: str = "") -> None:
    """Writes the render ``out`` (photonmap.render's dict) into Blender's render result. With a
    render border, Blender's result is the border region alone, so ``out`` (rendered for
    exactly that window) starts at its corner. Cryptomatte manifests go into the result's
    metadata, keyed for the view layer as Blender's Cryptomatte node reads them."""
    result = engine.begin_result(0, 0, window.w, window.h, layer=layer_name)
    if result is None:
        raise RuntimeError(f"Blender gave no render result of {window.w}x{window.h}")
    key_of_pass = dict(TERM_OF_PASS)
    key_of_pass.update({a["pass_name"]: a["name"] for a in out.get("aovs", [])})
    try:
        layer = result.layers[0]
        for p in layer.passes:
            if p.name == "Combined":
                p.rect = _rows_bottom_up(_with_alpha(out), p.channels)
            elif p.name in key_of_pass and key_of_pass[p.name] in out:
                p.rect = _rows_bottom_up(out[key_of_pass[p.name]], p.channels)
        if out.get("cryptomatte"):
            prefix = f"{layer.name}." if layer.name else ""
            header = photonmap.cryptomatte_header(out["cryptomatte"], prefix)
            for k, v in header.items():
                result.stamp_data_add_field(k, v)
    finally:
        engine.end_result(result)
