"""Render passes: ``Combined``, one pass per term of the core (``photonmap.PASS_NAMES``,
read from the core's AOV list; never written out here), and ``Error``, each pixel's
estimated standard error of the beauty (``photonmap.ERROR_PASS``; not part of the sum)."""

from __future__ import annotations

import numpy as np
import photonmap

PASS_NAMES: tuple[str, ...] = photonmap.PASS_NAMES
#: IR term (lower case, the keys of ``photonmap.render``'s output) of each pass.
TERM_OF_PASS = dict(zip(photonmap.PASS_NAMES, photonmap.TERMS))
TERM_OF_PASS[photonmap.ERROR_PASS] = photonmap.ERROR_AOV


def register_passes(engine, scene, view_layer) -> None:
    engine.register_pass(scene, view_layer, "Combined", 4, "RGBA", "COLOR")
    for name in (*PASS_NAMES, photonmap.ERROR_PASS):
        engine.register_pass(scene, view_layer, name, 3, "RGB", "COLOR")


def _rows_bottom_up(img: np.ndarray, channels: int) -> np.ndarray:
    """(H, W, 3) rows top to bottom -> (H*W, channels) rows bottom to top, as Blender's."""
    h, w = img.shape[:2]
    flipped = img[::-1]
    if channels == 4:
        out = np.ones((h, w, 4), dtype=np.float32)
        out[..., :3] = flipped
    else:
        out = np.ascontiguousarray(flipped, dtype=np.float32)
    return out.reshape(h * w, channels)


def write_result(engine, out: dict, window, layer_name: str = "") -> None:
    """Writes the render ``out`` (photonmap.render's dict) into Blender's render result. With a
    render border, Blender's result is the border region alone, so ``out`` (rendered for
    exactly that window) starts at its corner."""
    result = engine.begin_result(0, 0, window.w, window.h, layer=layer_name)
    if result is None:
        raise RuntimeError(f"Blender gave no render result of {window.w}x{window.h}")
    try:
        layer = result.layers[0]
        for p in layer.passes:
            if p.name == "Combined":
                p.rect = _rows_bottom_up(out["combined"], p.channels)
            elif p.name in TERM_OF_PASS:
                p.rect = _rows_bottom_up(out[TERM_OF_PASS[p.name]], p.channels)
    finally:
        engine.end_result(result)
