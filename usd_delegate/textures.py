"""Image textures: UsdUVTexture, MaterialX image nodes and dome-light files, read with
OpenImageIO (EXR, PNG, JPEG, TIFF, HDR). sRGB where the colour space says so (``auto``: 8-bit
images are sRGB): 8-bit images are passed encoded (IR ``encoding: srgb``, decoded by the core
after interpolation, as Cycles does), others decoded to linear here. A missing file is a
warning naming the prim and path."""

from __future__ import annotations

import os

import numpy as np

MAGENTA = [1.0, 0.0, 1.0]

_WRAP = {"repeat": "repeat", "periodic": "repeat", "clamp": "clamp", "mirror": "mirror",
         "black": "black", "constant": "black", "useMetadata": "repeat", "": "repeat"}


def srgb_to_linear(x: np.ndarray) -> np.ndarray:
    return np.where(x <= 0.04045, x / 12.92, ((x + 0.055) / 1.055) ** 2.4)


def resolve_asset(value, prim) -> str:
    """An asset path's resolved file name ('' if empty)."""
    if value is None:
        return ""
    path = getattr(value, "resolvedPath", "") or getattr(value, "path", "") or str(value)
    if path and not os.path.isabs(path):
        layer = prim.GetStage().GetRootLayer().realPath
        path = os.path.join(os.path.dirname(layer), path)
    return path


class TextureTable:
    """The IR's `textures` list, one entry per distinct (file, colour space, scale, bias, wrap)."""

    def __init__(self, diag) -> None:
        self.diag = diag
        self.textures: list[dict] = []
        self._index: dict = {}

    def add(self, prim, path: str, colorspace: str = "auto", wrap: str = "repeat",
            scale=(1, 1, 1, 1), bias=(0, 0, 0, 0)):
        """IR texture index, or None when the file cannot be read (warned)."""
        key = (path, colorspace, tuple(scale), tuple(bias), wrap)
        if key in self._index:
            return self._index[key]
        if not path or not os.path.isfile(path):
            self.diag.warn(prim, f"texture file not found: `{path}`; rendered magenta")
            self._index[key] = None
            return None
        try:
            data, encoding = read_image(path, colorspace)
        except Exception as e:
            self.diag.warn(prim, f"cannot read texture `{path}`: {e}; rendered magenta")
            self._index[key] = None
            return None
        h, w, c = data.shape
        sc = np.array(list(scale) + [1] * 4)[:c]
        bi = np.array(list(bias) + [0] * 4)[:c]
        if np.any(sc != 1) or np.any(bi != 0):
            # UsdUVTexture's scale and bias apply to the decoded value.
            data = _decoded(data, encoding) * sc + bi
            encoding = "linear"
        self.textures.append({
            "name": path, "width": int(w), "height": int(h), "channels": int(c),
            "data": data.astype(np.float32).reshape(-1), "wrap": _WRAP.get(wrap, "repeat"),
            "encoding": encoding,
        })
        self._index[key] = len(self.textures) - 1
        return self._index[key]


def _decoded(px: np.ndarray, encoding: str) -> np.ndarray:
    if encoding != "srgb":
        return px
    n = 3 if px.shape[2] >= 3 else 1
    px = px.copy()
    px[:, :, :n] = srgb_to_linear(px[:, :, :n])
    return px


def read_image(path: str, colorspace: str = "auto") -> tuple[np.ndarray, str]:
    """((h, w, c) float32 with c in 1, 3, 4; its encoding). An 8-bit sRGB image keeps its
    encoded values ("srgb": the core interpolates them and decodes after, as Cycles does);
    any other sRGB image is decoded here ("linear")."""
    import OpenImageIO as oiio

    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise OSError(buf.geterror())
    spec = buf.spec()
    px = buf.get_pixels(oiio.FLOAT)
    if px is None or buf.has_error:
        raise OSError(buf.geterror() or "no pixels")
    px = np.asarray(px, dtype=np.float32).reshape(spec.height, spec.width, spec.nchannels)
    c = spec.nchannels
    if c == 2:
        px = px[:, :, :1]
    elif c > 4:
        px = px[:, :, :4]
    cs = (colorspace or "auto").lower()
    file_cs = (spec.get_string_attribute("oiio:ColorSpace") or "").lower()
    if cs == "auto":
        srgb = spec.format.basetype == oiio.UINT8 or "srgb" in file_cs
    else:
        srgb = cs in ("srgb", "srgb_texture", "srgb_rec709_scene")
    if not srgb:
        return px, "linear"
    if spec.format.basetype == oiio.UINT8:
        return px, "srgb"
    return _decoded(px, "srgb"), "linear"
