"""Images -> IR textures (float RGB(A), rows top to bottom; linear Rec.709, or sRGB-encoded
bytes that the core decodes after interpolation)."""

from __future__ import annotations

import numpy as np

# Colour spaces whose pixel values are already linear (or are data, used as they are).
_LINEAR = {"linear", "linear rec.709", "non-color", "raw", "linear rec.2020", "linear cie-xyz e",
           "linear cie-xyz d65", "acescg", "aces2065-1", "linear fileinfo", "xyz"}


def image_pixels(image, alpha: bool = False) -> tuple[np.ndarray, str] | None:
    """Blender's loaded pixels of ``image`` as a (H, W, C) float32 array, rows top to bottom,
    and their encoding: float images are linear in Blender ("linear"); byte images in an sRGB
    colour space keep their encoded values ("srgb": the core interpolates them and decodes
    after, as Cycles does with byte images)."""
    w, h = image.size[:2]
    if w == 0 or h == 0:
        return None
    ch = image.channels
    buf = np.empty(w * h * ch, dtype=np.float32)
    image.pixels.foreach_get(buf)
    px = buf.reshape(h, w, ch)[::-1]  # Blender's rows go bottom to top
    cs = image.colorspace_settings.name.lower()
    encoding = "srgb" if not image.is_float and cs not in _LINEAR else "linear"
    if ch == 4 and not alpha:
        px = px[..., :3]  # alpha only where a shading graph reads it
    elif ch == 2:
        px = px[..., :1]
    return np.ascontiguousarray(px, dtype=np.float32), encoding


_WRAP = {"REPEAT": "repeat", "EXTEND": "clamp", "CLIP": "black", "MIRROR": "mirror"}


class ImageCache:
    """Each Blender image becomes one IR texture, however many nodes use it."""

    def __init__(self, ir_textures: list, warn):
        self.textures = ir_textures
        self.warn = warn
        self.index: dict[tuple, int] = {}

    def texture(self, image, extension: str = "REPEAT", owner: str = "",
                alpha: bool = False) -> int | None:
        """The IR texture of ``image`` with ``extension``; with ``alpha``, RGBA."""
        if image is None:
            return None
        key = (image.name, extension, alpha)
        if key in self.index:
            return self.index[key]
        try:
            px, encoding = image_pixels(image, alpha) or (None, "linear")
        except Exception as e:  # unreadable file, packed data missing, ...
            px = None
            self.warn(f"image '{image.name}'{owner}: cannot read pixels ({e}); ignored")
        if px is None:
            self.warn(f"image '{image.name}'{owner}: no pixels (missing file?); ignored")
            self.index[key] = None
            return None
        h, w, c = px.shape
        self.textures.append({
            "name": image.name, "width": int(w), "height": int(h), "channels": int(c),
            "data": px.ravel(), "wrap": _WRAP.get(extension, "repeat"), "encoding": encoding,
        })
        self.index[key] = len(self.textures) - 1
        return self.index[key]
