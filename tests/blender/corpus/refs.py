"""The committed corpus: its manifest, references and USD stages (needs OpenImageIO; no bpy).

``PHOTONMAP_CORPUS_REFS`` points at another folder of references (as make_references.py
writes them) instead of ``refs/``.
"""

from __future__ import annotations

import json
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REFS = os.environ.get("PHOTONMAP_CORPUS_REFS") or os.path.join(HERE, "refs")
USD = os.path.join(HERE, "usd")


def manifest() -> dict:
    with open(os.path.join(REFS, "manifest.json")) as f:
        return json.load(f)


def resolution() -> tuple[int, int]:
    w, h = manifest()["resolution"]
    return int(w), int(h)


def names() -> list[str]:
    """Every scene of the manifest, in its order."""
    return list(manifest()["scenes"])


def usd_names() -> list[str]:
    """Scenes with a committed USD stage."""
    return [n for n, rec in manifest()["scenes"].items()
            if rec.get("usd") and os.path.exists(usd_path(n))]


def tags(name: str) -> tuple:
    return tuple(manifest()["scenes"][name].get("tags", ()))


def usd_path(name: str) -> str:
    return os.path.join(USD, f"{name}.usda")


def read_rgb(path: str) -> np.ndarray:
    """(H, W, 3) float32, top row first."""
    import OpenImageIO as oiio

    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise OSError(f"{path}: {buf.geterror()}")
    return np.ascontiguousarray(buf.get_pixels(oiio.FLOAT)[..., :3])


def load(name: str) -> tuple[np.ndarray, np.ndarray]:
    """The two seeds of ``name``'s Cycles reference."""
    return tuple(read_rgb(os.path.join(REFS, f"{name}_s{s}.exr")) for s in (1, 2))
