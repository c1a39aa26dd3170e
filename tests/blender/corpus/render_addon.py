"""Renders corpus scenes through the PhotonMap Blender add-on (bpy), as a user would: the
scene is built, PhotonMap made its engine, the settings put on ``scene.photonmap`` and
``bpy.ops.render.render()`` run; the core's output is taken where the engine hands it to
Blender (``passes.write_result``).

As a script (the bpy venv; installs the extension zip into a throw-away user folder):

    .venv-bpy/bin/python tests/blender/corpus/render_addon.py --zip EXT.zip --setting ci \
        --out DIR [--seeds 1 2] [--only SCENE ...]

writes ``DIR/<scene>_s<seed>.npz`` (``combined``, ``error``, ``stats`` JSON, ``warnings``).
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
MODULE = "bl_ext.user_default.photonmap"


def enable():
    """(Re-)enables the add-on (read_factory_settings resets the preferences)."""
    import addon_utils

    mod = addon_utils.enable(MODULE, default_set=True)
    if mod is None:
        raise RuntimeError(f"{MODULE} did not enable")
    return sys.modules[MODULE]


def apply_settings(sc, setting: dict, seed: int) -> None:
    pm = sc.photonmap
    pm.quality = setting.get("quality", "medium")  # fills the preset's fields
    for key, value in setting.items():
        if key != "quality":
            setattr(pm, key, value)
    pm.seed = seed


def render_scene(name: str, setting: dict, seed: int = 1, build=None) -> dict:
    """Our render of corpus scene ``name``: the core's output dict (``combined``, ``error``,
    terms, ``stats``) plus ``warnings`` (the engine's reports) and ``seconds``."""
    import bpy

    from corpus import scenes

    sc = (build or scenes.SCENES[name].build)()
    addon = enable()
    sc.render.engine = "PHOTONMAP"
    apply_settings(sc, setting, seed)
    captured: dict = {}
    reports: list = []
    engine_cls = addon.engine.PhotonMapRenderEngine
    write = addon.passes.write_result
    report = engine_cls._report

    def spy(engine, out, window, layer_name=""):
        captured["out"] = out
        write(engine, out, window, layer_name)

    addon.passes.write_result = spy
    engine_cls._report = lambda engine, kind, message: reports.append((kind, message))
    t = time.time()
    try:
        bpy.ops.render.render()
    finally:
        addon.passes.write_result = write
        engine_cls._report = report
    secs = time.time() - t
    errors = [m for k, m in reports if k == "ERROR"]
    if "out" not in captured:
        raise RuntimeError(f"{name}: the engine wrote no result; reports: {reports}")
    out = dict(captured["out"])
    out["warnings"] = [m for k, m in reports if k == "WARNING"]
    out["errors"] = errors
    out["seconds"] = secs
    return out


#: The corpus scenes' renders through the engine, by (scene, setting, seeds), kept for the pytest
#: session, so that the corpus test and the node sensitivity cases' controls of the same scene
#: share them (a render is deterministic for its seed and its IR).
_AS_EXPORTED: dict = {}


def render_seeds(name: str, setting: dict, seeds) -> list:
    """``name`` rendered through the engine once per seed (``render_scene``): each render's
    ``combined``, ``error``, ``seconds``, ``warnings`` and ``errors``. Kept for the session."""
    key = (name, json.dumps(setting, sort_keys=True), tuple(seeds))
    if key not in _AS_EXPORTED:
        outs = []
        for s in seeds:
            out = render_scene(name, setting, seed=s)
            outs.append({k: out[k] for k in ("combined", "error", "seconds", "warnings",
                                             "errors")})
        _AS_EXPORTED[key] = outs
    return _AS_EXPORTED[key]


def export_ir(name: str, build=None) -> tuple[dict, list]:
    """The add-on's IR of corpus scene ``name`` and its export warnings."""
    import bpy

    from corpus import scenes

    (build or scenes.SCENES[name].build)()
    addon = enable()
    res = addon.export.export_scene(bpy.context.evaluated_depsgraph_get())
    return res.ir, res.warnings


def save(path: str, out: dict) -> None:
    import numpy as np

    np.savez_compressed(path, combined=out["combined"], error=out["error"],
                        stats=json.dumps(out.get("stats", {})),
                        warnings=json.dumps(out.get("warnings", [])),
                        seconds=out.get("seconds", 0.0))


def install(zip_path: str) -> None:
    import bpy

    bpy.ops.wm.read_factory_settings(use_empty=True)
    res = bpy.ops.extensions.package_install_files(repo="user_default", filepath=zip_path,
                                                   enable_on_install=True)
    if res != {"FINISHED"}:
        raise RuntimeError(f"installing {zip_path}: {res}")


def main() -> None:
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--zip", required=True, help="the extension zip")
    ap.add_argument("--setting", default="ci")
    ap.add_argument("--out", required=True)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--only", nargs="*", default=None)
    a = ap.parse_args()
    os.environ["BLENDER_USER_RESOURCES"] = tempfile.mkdtemp(prefix="photonmap-blender-user-")
    sys.path.insert(0, os.path.dirname(HERE))
    from corpus import scenes
    from corpus.settings import settings

    install(a.zip)
    os.makedirs(a.out, exist_ok=True)
    for name in a.only or list(scenes.SCENES):
        setting = settings(a.setting, scenes.SCENES[name].tags)
        for seed in a.seeds:
            out = render_scene(name, setting, seed)
            save(os.path.join(a.out, f"{name}_s{seed}.npz"), out)
            print(f"{name} seed {seed}: {out['seconds']:.1f}s", flush=True)


if __name__ == "__main__":
    main()
