"""Renders the corpus' committed USD stages (Blender's own USD export) through the Python
package: ``usd_delegate.load_stage`` (the importer of ``photonmap render``) then
``photonmap.render``. No bpy.

As a script (the package's venv):

    python tests/blender/corpus/render_usd.py --setting ci --out DIR [--seeds 1 2] [--only S ...]

writes ``DIR/<scene>_s<seed>.npz`` as render_addon.py does.
"""

from __future__ import annotations

import json
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def load_ir(name: str) -> tuple[dict, object]:
    """The IR of ``name``'s stage at the corpus' resolution, and the import result."""
    import usd_delegate

    from corpus import refs

    w, h = refs.resolution()
    res = usd_delegate.load_stage(refs.usd_path(name), width=w)
    ir = res.ir
    film = ir["film"]
    if (film["width"], film["height"]) != (w, h):
        raise ValueError(f"{name}: the stage's camera gives a {film['width']}x{film['height']} "
                         f"film, the references are {w}x{h}")
    return ir, res


def render_ir(ir: dict, setting: dict, seed: int = 1) -> dict:
    import photonmap

    t = time.time()
    out = photonmap.render(photonmap.Scene.from_dict(ir), seed=seed, **setting)
    out["seconds"] = time.time() - t
    return out


def render_stage(name: str, setting: dict, seed: int = 1) -> dict:
    ir, res = load_ir(name)
    out = render_ir(ir, setting, seed)
    out["warnings"] = [f"{p}: {m}" for p, m in res.diagnostics.warnings]
    return out


#: (scene, setting, seeds) -> (renders, import warnings): the stage renders as read, kept for the
#: pytest session, so that the corpus test and the sensitivity cases' controls of the same
#: scene share them (a render is deterministic for its seed).
_AS_READ: dict = {}


def render_seeds(name: str, setting: dict, seeds) -> tuple[list, list]:
    """``name``'s stage as read, rendered once per seed: each render's ``combined``,
    ``error`` and ``seconds``, and the import's warnings. Kept for the session."""
    key = (name, json.dumps(setting, sort_keys=True), tuple(seeds))
    if key not in _AS_READ:
        ir, res = load_ir(name)
        outs = []
        for s in seeds:
            out = render_ir(ir, setting, s)
            outs.append({k: out[k] for k in ("combined", "error", "seconds")})
        _AS_READ[key] = (outs, [f"{p}: {m}" for p, m in res.diagnostics.warnings])
    return _AS_READ[key]


def main() -> None:
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--setting", default="ci")
    ap.add_argument("--out", required=True)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--only", nargs="*", default=None)
    a = ap.parse_args()
    sys.path.insert(0, os.path.dirname(HERE))
    from corpus import refs
    from corpus.render_addon import save
    from corpus.settings import settings

    os.makedirs(a.out, exist_ok=True)
    for name in a.only or refs.usd_names():
        setting = settings(a.setting, refs.tags(name))
        for seed in a.seeds:
            out = render_stage(name, setting, seed)
            save(os.path.join(a.out, f"{name}_s{seed}.npz"), out)
            print(f"{name} seed {seed}: {out['seconds']:.1f}s", flush=True)


if __name__ == "__main__":
    main()
