#!/usr/bin/env python3
"""Side-by-side sRGB PNG of a photonmap EXR's beauty and terms.

Usage: python3 scripts/aov_sheet.py render.exr sheet.png [--exposure 1.0]
Needs numpy and OpenImageIO (pip install numpy openimageio).
"""
import argparse
import sys

import numpy as np
import OpenImageIO as oiio

TERMS = ["direct", "indirect", "caustic", "specular", "volume", "emission", "subsurface"]


def srgb(x):
    x = np.clip(np.nan_to_num(x), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("exr")
    ap.add_argument("png")
    ap.add_argument("--exposure", type=float, default=1.0)
    a = ap.parse_args()
    buf = oiio.ImageBuf(a.exr)
    spec = buf.spec()
    px = buf.get_pixels(oiio.FLOAT).reshape(spec.height, spec.width, spec.nchannels)
    names = list(spec.channelnames)

    def group(prefix):
        idx = [names.index(f"{prefix}{c}") for c in "RGB"]
        return px[:, :, idx]

    tiles = [("beauty", group(""))] + [(t, group(t + ".")) for t in TERMS if f"{t}.R" in names]
    row = np.concatenate([srgb(img * a.exposure) for _, img in tiles], axis=1)
    out = oiio.ImageBuf(oiio.ImageSpec(row.shape[1], row.shape[0], 3, oiio.UINT8))
    out.set_pixels(oiio.ROI(), np.ascontiguousarray((row * 255 + 0.5).astype(np.uint8)))
    if not out.write(a.png):
        sys.exit(f"cannot write {a.png}: {out.geterror()}")
    for name, img in tiles:
        print(f"{name:10s} mean {img.mean(axis=(0, 1))}")


if __name__ == "__main__":
    main()
