"""Denoising with Intel Open Image Denoise, through its Python binding ``pyoidn`` (the
optional extra ``photonmap[denoise]``).

The noisy terms (``DENOISED_TERMS``: direct, indirect, caustic, specular, volume,
subsurface) are denoised each on its own, by OIDN's ``RT`` filter in HDR mode, guided by the
render's ``albedo`` and ``normal`` (prefiltered by OIDN: they carry a little noise of their own, from
glass and antialiasing). ``emission`` (emitters and the background seen directly) is kept as
rendered. The beauty is then the sum of the terms, as always, so a composite of the passes
still adds up exactly; the terms as rendered are kept as ``<term>_noisy``. A term that is zero
everywhere stays zero.

The caustic term keeps its local means: the denoised caustic is scaled, per channel, by the
ratio of the noisy and the denoised image averaged over 5x5 pixels. Its noise is the caustic
map's, blotches of the photons' scale that the network does not remove but shifts: on the
spheres' Cornell box, plain denoising raised the error of 4x4-pixel blocks in the caustic by
24% at `medium` and 54% at `high` (mean of 4 seeds); with the local means kept it is within
the raw render's (BENCHMARKS.md, "Compositing passes"), and the network's removal of the
pixel-scale noise stays.
"""

from __future__ import annotations

import importlib.metadata
import time
from typing import Mapping

import numpy as np

from ._core import DENOISED_TERMS, NOISY_SUFFIX, PhotonmapError

__all__ = ["DenoiseUnavailable", "require", "info", "denoise_terms", "apply"]

MISSING = ("denoising needs Open Image Denoise's Python binding `pyoidn`, which is not "
           "installed: pip install 'photonmap[denoise]'")


class DenoiseUnavailable(PhotonmapError):
    """``denoise=True`` without the ``pyoidn`` package (``pip install 'photonmap[denoise]'``)."""


def require():
    """The ``pyoidn`` module, or ``DenoiseUnavailable`` naming the package to install."""
    try:
        import pyoidn
    except ImportError as e:
        raise DenoiseUnavailable(f"{MISSING} ({e})") from None
    return pyoidn


def info() -> dict[str, str]:
    """What denoises: the filter, OIDN's version and the binding's (recorded in the stats and
    in the EXR metadata)."""
    pyoidn = require()
    try:
        binding = importlib.metadata.version("pyoidn")
    except importlib.metadata.PackageNotFoundError:
        binding = "unknown"
    return {
        "filter": "Open Image Denoise RT (hdr, albedo and normal guides, prefiltered); "
                  "caustic: local 5x5 means kept",
        "version": str(getattr(pyoidn.version, "oidn_version", "unknown")),
        "binding": f"pyoidn {binding}",
        "terms": ",".join(DENOISED_TERMS),
    }


def _image(a: np.ndarray, name: str) -> np.ndarray:
    a = np.ascontiguousarray(a, dtype=np.float32)
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"{name}: expected an (H, W, 3) image, got shape {a.shape}")
    return a


#: The terms whose local means the denoised image keeps (see the module's documentation),
#: and the half-width of the box they are taken over, in pixels.
KEEP_LOCAL_MEANS = ("caustic",)
LOCAL_MEAN_RADIUS = 2


def box_mean(img: np.ndarray, r: int) -> np.ndarray:
    """The mean over the (2r+1)^2 box around each pixel (edges repeated), per channel."""
    k = 2 * r + 1
    pad = np.pad(img.astype(np.float64), ((r, r), (r, r), (0, 0)), mode="edge")
    c = np.pad(np.cumsum(np.cumsum(pad, 0), 1), ((1, 0), (1, 0), (0, 0)))
    h, w = img.shape[:2]
    s = c[k:k + h, k:k + w] - c[:h, k:k + w] - c[k:k + h, :w] + c[:h, :w]
    return (s / (k * k)).astype(np.float32)


def keep_local_means(denoised: np.ndarray, noisy: np.ndarray,
                     r: int = LOCAL_MEAN_RADIUS) -> np.ndarray:
    """``denoised`` scaled so that its means over (2r+1)^2 boxes are ``noisy``'s (the scale
    kept within [1/2, 2])."""
    gn, gd = box_mean(noisy, r), box_mean(denoised, r)
    eps = np.float32(1e-4) * (gn.mean(axis=(0, 1), keepdims=True) + np.float32(1e-12))
    return denoised * np.clip((gn + eps) / (gd + eps), 0.5, 2.0)


def denoise_terms(terms: Mapping[str, np.ndarray], albedo: np.ndarray,
                  normal: np.ndarray) -> dict[str, np.ndarray]:
    """Each of ``DENOISED_TERMS`` in ``terms``, denoised on its own with the guides (those of
    ``KEEP_LOCAL_MEANS`` then keep their local means); a term that is zero everywhere stays
    zero. Values come out finite and non-negative."""
    pyoidn = require()
    alb = np.clip(_image(albedo, "albedo"), 0.0, 1.0)
    nrm = np.clip(np.nan_to_num(_image(normal, "normal")), -1.0, 1.0)
    out = {}
    for t in DENOISED_TERMS:
        img = _image(terms[t], t)
        if not img.any():
            out[t] = img.copy()
            continue
        d = np.nan_to_num(np.asarray(pyoidn.denoise(img, alb, nrm, hdr=True, clean_aux=False),
                                     dtype=np.float32))
        d = np.maximum(d, 0.0)
        if t in KEEP_LOCAL_MEANS:
            d = keep_local_means(d, img)
        out[t] = np.maximum(d, 0.0).astype(np.float32)
    return out


def apply(out: dict) -> dict:
    """Denoises the result of ``photonmap.render`` in place (its ``<term>_noisy`` layers hold
    the terms as rendered): the denoised terms replace the terms, ``combined`` is their sum,
    and ``stats["denoise"]`` records the filter, its version and the seconds taken."""
    t0 = time.perf_counter()
    den = denoise_terms({t: out[t + NOISY_SUFFIX] for t in DENOISED_TERMS},
                        out["albedo"], out["normal"])
    out.update(den)
    from . import TERMS

    combined = np.zeros_like(out["combined"])
    for t in TERMS:
        combined += out[t]
    out["combined"] = combined
    out["stats"]["denoise"] = dict(info(), seconds=time.perf_counter() - t0)
    return out


class CliDenoiser:
    """The ``photonmap`` command's denoiser, which the core calls between the render and the
    writing of the files: ``check()`` before rendering, then ``(width, height, terms, albedo,
    normal)`` with float32 RGB bytes, returning the denoised terms' bytes and ``info()``."""

    def check(self) -> None:
        require()

    def __call__(self, width: int, height: int, terms: Mapping[str, bytes], albedo: bytes,
                 normal: bytes):
        def img(b: bytes) -> np.ndarray:
            return np.frombuffer(b, dtype="<f4").reshape(height, width, 3)

        den = denoise_terms({k: img(v) for k, v in terms.items()}, img(albedo), img(normal))
        return ({k: v.astype("<f4").tobytes() for k, v in den.items()}, info())
