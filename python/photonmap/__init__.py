"""photonmap: a two-pass photon-mapping renderer (Jensen 2001), Python API.

Build a scene from numpy arrays and plain dicts (the dicts mirror the JSON scene IR documented
in the core's ``src/scene/desc.rs``), render it, and get one float32 image per term::

    import numpy as np, photonmap
    scene = photonmap.Scene.from_dict({
        "camera": {"fov": 0.7, "transform": [[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]},
        "film": {"width": 64, "height": 64},
        "materials": [{"type": "diffuse", "color": [0.8, 0.8, 0.8]}],
        "meshes": [{"positions": np.array([[-1,-1,0],[1,-1,0],[1,1,0]]), "indices": [[0,1,2]]}],
        "lights": [{"type": "point", "position": [0, 0, 2], "power": 100}],
    })
    out = photonmap.render(scene, quality="draft", seed=1)
    out["combined"].shape      # (64, 64, 3) float32; out["direct"], ... out["stats"]
"""

from __future__ import annotations

import json
import os
import threading
from typing import Any, Callable, Mapping

import numpy as np

from . import _core
from ._core import CancelToken, PhotonmapError, RenderCancelled, SceneError

__version__ = _core.__version__

#: The terms of the rendering equation, in output order (from the core's AOV list).
TERMS: tuple[str, ...] = tuple(_core.TERMS)
#: The same terms, capitalised as render-pass names (Blender).
PASS_NAMES: tuple[str, ...] = tuple(_core.PASS_NAMES)
#: The AOV that is not a term: each pixel's estimated standard error of ``combined``.
ERROR_AOV: str = _core.ERROR_AOV
#: Its render-pass name (Blender).
ERROR_PASS: str = _core.ERROR_PASS
#: Quality presets.
QUALITIES: tuple[str, ...] = tuple(_core.QUALITIES)
#: The terms that ``denoise=True`` denoises, each on its own (``emission`` stays as rendered).
DENOISED_TERMS: tuple[str, ...] = tuple(_core.DENOISED_TERMS)
#: Suffix of a term kept as rendered when the terms are denoised (``direct_noisy``).
NOISY_SUFFIX: str = _core.NOISY_SUFFIX

__all__ = [
    "TERMS",
    "PASS_NAMES",
    "QUALITIES",
    "ERROR_AOV",
    "ERROR_PASS",
    "DENOISED_TERMS",
    "NOISY_SUFFIX",
    "aov_specs",
    "cryptomatte_header",
    "Scene",
    "Renderer",
    "CancelToken",
    "render",
    "load_scene",
    "default_scene",
    "PhotonmapError",
    "SceneError",
    "RenderCancelled",
    "preset",
    "defaults",
    "settings_schema",
    "merge_partials",
    "tile_stats",
]

_MESH_ARRAYS = ("positions", "indices", "normals", "uvs", "material_indices")


def _as_array(value: Any, dtype, width: int, pointer: str, name: str) -> np.ndarray:
    """Any array-like (list, numpy array of any float/int type, buffer) as contiguous
    ``dtype`` of shape (n, width), or SceneError naming the field."""
    try:
        a = np.asarray(value)
    except Exception as e:  # ragged lists and the like
        raise SceneError(f"invalid scene at {pointer}{_obj(name)}: not an array ({e})") from None
    if a.size == 0:
        a = a.reshape(0, width) if width > 1 else a.reshape(0)
    if width > 1:
        if a.ndim == 1 and a.size % width == 0:
            a = a.reshape(-1, width)
        if a.ndim != 2 or a.shape[1] != width:
            raise SceneError(
                f"invalid scene at {pointer}{_obj(name)}: expected shape (n, {width}), got {a.shape}"
            )
    elif a.ndim != 1:
        raise SceneError(f"invalid scene at {pointer}{_obj(name)}: expected shape (n,), got {a.shape}")
    if dtype == np.uint32:
        if a.dtype.kind == "f":
            if not np.all(np.isfinite(a)) or np.any(a != np.round(a)):
                raise SceneError(f"invalid scene at {pointer}{_obj(name)}: indices must be integers")
        elif a.dtype.kind not in "iub":
            raise SceneError(f"invalid scene at {pointer}{_obj(name)}: expected integers, got {a.dtype}")
        if a.size and (a.min() < 0 or a.max() > 0xFFFFFFFF):
            bad = int(np.argmax((a < 0) | (a > 0xFFFFFFFF)))
            flat = np.unravel_index(bad, a.shape)
            where = "/".join(str(int(i)) for i in flat)
            raise SceneError(
                f"invalid scene at {pointer}/{where}{_obj(name)}: index {a.flat[bad]} out of range"
            )
    elif a.dtype.kind not in "fiub":
        raise SceneError(f"invalid scene at {pointer}{_obj(name)}: expected numbers, got {a.dtype}")
    return np.ascontiguousarray(a, dtype=np.dtype(dtype).newbyteorder("<"))


def _obj(name: str) -> str:
    return f" (`{name}`)" if name else ""


def _jsonable(value: Any) -> Any:
    """Dict/list values with numpy scalars and arrays turned into plain Python."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return value


def _medium(m: Any, i: int) -> Any:
    """A medium dict whose `density` may be a numpy array shaped (nz, ny, nx) (x fastest, as
    the IR), or a dict with such an array as `data`: flattened, with `resolution` filled in."""
    if not isinstance(m, Mapping) or m.get("density") is None:
        return m
    grid = m["density"]
    if isinstance(grid, np.ndarray):
        grid = {"data": grid}
    if not isinstance(grid, Mapping):
        raise SceneError(f"invalid scene at /media/{i}/density: expected an array or a dict")
    data = np.asarray(grid.get("data", []), dtype=np.float32)
    out = dict(grid)
    if data.ndim == 3 and "resolution" not in grid:
        nz, ny, nx = data.shape
        out["resolution"] = [nx, ny, nz]
    out["data"] = data.reshape(-1)
    return {**m, "density": out}


class Scene:
    """Constructors of the core's validated scene (``photonmap._core.Scene``)."""

    @staticmethod
    def from_dict(ir: Mapping[str, Any]) -> "_core.Scene":
        """A scene from a dict mirroring the JSON IR; mesh arrays may be numpy arrays of any
        float/int type (or lists), passed to the core as raw little-endian buffers."""
        if not isinstance(ir, Mapping):
            raise SceneError(f"invalid scene at /: expected a dict, got {type(ir).__name__}")
        rest = {k: v for k, v in ir.items() if k != "meshes"}
        if "media" in rest:
            rest["media"] = [_medium(m, i) for i, m in enumerate(rest["media"] or [])]
        meshes_in = ir.get("meshes", []) or []
        meshes, buffers = [], []
        for i, m in enumerate(meshes_in):
            if not isinstance(m, Mapping):
                raise SceneError(f"invalid scene at /meshes/{i}: expected a dict")
            name = str(m.get("name", ""))
            p = f"/meshes/{i}"
            for req in ("positions", "indices"):
                if req not in m:
                    raise SceneError(f"invalid scene at {p}/{req}{_obj(name)}: missing field `{req}`")
            pos = _as_array(m["positions"], np.float32, 3, f"{p}/positions", name)
            idx = _as_array(m["indices"], np.uint32, 3, f"{p}/indices", name)
            opt = {}
            for key, dt, w in (("normals", np.float32, 3), ("uvs", np.float32, 2),
                               ("material_indices", np.uint32, 1)):
                v = m.get(key)
                opt[key] = None if v is None else _as_array(v, dt, w, f"{p}/{key}", name).tobytes()
            meta = {k: _jsonable(v) for k, v in m.items() if k not in _MESH_ARRAYS}
            meta["positions"], meta["indices"] = [], []
            meshes.append(meta)
            buffers.append((pos.tobytes(), idx.tobytes(), opt["normals"], opt["uvs"],
                            opt["material_indices"]))
        doc = _jsonable(rest)
        doc["meshes"] = meshes
        try:
            text = json.dumps(doc, indent=1, allow_nan=True)
        except (TypeError, ValueError) as e:
            raise SceneError(f"invalid scene at /: {e}") from None
        return _core.Scene.from_parts(text, buffers)

    @staticmethod
    def from_json(text: str) -> "_core.Scene":
        return _core.Scene.from_json(text)

    @staticmethod
    def from_file(path: str | os.PathLike) -> "_core.Scene":
        return _core.Scene.from_file(os.fspath(path))

    @staticmethod
    def default() -> "_core.Scene":
        return _core.Scene.default()


def default_scene() -> "_core.Scene":
    """The embedded default scene."""
    return _core.Scene.default()


def load_scene(path: str | os.PathLike, **usd_options) -> "_core.Scene":
    """A scene from a .json IR file or a USD stage (options as ``usd_delegate.load_stage``)."""
    path = os.fspath(path)
    if path.lower().endswith((".usd", ".usda", ".usdc", ".usdz")):
        import usd_delegate

        result = usd_delegate.load_stage(path, **usd_options)
        return Scene.from_dict(result.ir)
    return _core.Scene.from_file(path)


def _to_scene(scene: Any) -> "_core.Scene":
    if isinstance(scene, _core.Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(scene)
    if isinstance(scene, (str, os.PathLike)):
        s = os.fspath(scene)
        if s.lstrip().startswith("{"):
            return _core.Scene.from_json(s)
        return load_scene(s)
    raise TypeError(f"expected a Scene, dict, JSON text or path, got {type(scene).__name__}")


def render(
    scene: Any,
    *,
    progress: Callable[[float, str], Any] | None = None,
    preview: Callable[[np.ndarray, int], Any] | None = None,
    cancel: CancelToken | None = None,
    pass_range: tuple[int, int] | None = None,
    **settings: Any,
) -> dict:
    """Renders ``scene`` (a Scene, an IR dict, JSON text, or a .json/.usd path).

    Returns ``{"combined": (H,W,3) float32, <term>: (H,W,3) float32 for each of TERMS,
    "alpha": (H,W) float32, "stats": dict}``; ``combined`` is the sum of the terms, and
    ``alpha`` its alpha: 1, less where camera rays see a transparent background (the scene's
    ``film.transparent``, Blender's Film > Transparent) or a Holdout. Beside the terms, not part of
    the sum, come the AOVs that ``out["aovs"]`` lists in order (``aov_specs``), each under
    its name as an (H,W,C) float32 array: ``out["error"]``, the estimated standard error of
    ``combined`` per pixel and channel, always; with ``denoising_data=True`` the guides
    ``out["albedo"]`` and ``out["normal"]``; with ``cryptomatte=`` the layers
    ``out["CryptoObject00"]``, ... (id, coverage, id, coverage), whose manifests are in
    ``out["cryptomatte"]`` (``{type name: [names]}``; ``cryptomatte_header`` makes the EXR
    metadata of them). With ``denoise=True`` (the extra ``photonmap[denoise]``) the terms of
    ``DENOISED_TERMS`` are denoised each on its own by Open Image Denoise with the guides,
    ``combined`` is their sum, the terms as rendered are kept as ``<term>_noisy``, and
    ``out["stats"]["denoise"]`` says what denoised them. See the README.

    ``settings`` are the render settings of ``settings_schema()``, each meaning what the
    command-line flag of the same name means (``quality="high"``, ``spp=64``,
    ``mode="sppm"``, ``memory_limit="8G"``, ...). ``None`` is a setting's default; a preset
    field not given takes the ``quality`` preset's value. An unknown keyword raises
    ``TypeError``, a bad value ``ValueError``, both naming the keyword.

    The GIL is released while rendering; ``progress(fraction, phase)`` is called from the
    calling thread; Ctrl-C or ``cancel.cancel()`` raise within ~50 ms (KeyboardInterrupt,
    RenderCancelled). ``time_budget`` plans photon counts and camera passes to fill it; the
    plan is in ``stats["time_budget"]``. ``preview(image, passes)``, called from the calling
    thread, receives the beauty so far of a progressive render (``progressive``,
    ``time_budget`` or ``mode="sppm"``): the core previews after passes 1, 2, 4, ... and at
    most every 0.25 s between, and the calling thread hands on the latest one every 50 ms, and
    the last one at the end. ``memory_limit`` stops the render up front, with ``ValueError``
    naming ``memory_limit`` and the estimate, when its photon maps and BVH would need more.

    With ``mode="pppm"``, ``pass_range=(a, b)`` renders passes a..b only (of ``spp``);
    ``out["partial"]`` then holds their partial sums (the bytes of a ``.ppart`` file), which
    ``merge_partials`` merges with the other blocks' into the image of all the passes, the
    same bits as one render of them. ``save_photon_maps=``/``load_photon_maps=`` save and
    load Jensen's photon maps and irradiance cache (``stats["photon_map_reuse"]``).
    """
    text = _settings_json(settings)
    if settings.get("denoise"):
        from . import denoise

        denoise.require()
    s = _to_scene(scene)

    def show(b: bytes, w: int, h: int, passes: int) -> None:
        preview(np.frombuffer(b, dtype="<f4").reshape(h, w, 3).copy(), passes)

    raw = _core.render(s, text, progress=progress,
                       preview=show if preview is not None else None, cancel=cancel,
                       pass_range=None if pass_range is None else tuple(pass_range))
    out = _images(raw)
    if settings.get("denoise"):
        from . import denoise

        denoise.apply(out)
    return out


def _images(raw: dict) -> dict:
    """The core's result as float32 (H, W, 3) arrays, stats as a dict."""
    h, w = raw["height"], raw["width"]

    def img(b: bytes) -> np.ndarray:
        return np.frombuffer(b, dtype="<f4").reshape(h, w, 3).astype(np.float32, copy=True)

    out: dict[str, Any] = {"combined": img(raw["combined"])}
    out["alpha"] = np.frombuffer(raw["alpha"], dtype="<f4").reshape(h, w).astype(
        np.float32, copy=True)
    for t in TERMS:
        out[t] = img(raw["terms"][t])
    specs = []
    for a in raw["aovs"]:
        data = a.pop("data")
        out[a["name"]] = np.frombuffer(data, dtype="<f4").reshape(
            h, w, len(a["channels"])).astype(np.float32, copy=True)
        specs.append(a)
    out["aovs"] = specs
    out["cryptomatte"] = json.loads(raw["cryptomatte"])
    out["stats"] = json.loads(raw["stats"])
    if "partial" in raw:
        out["partial"] = raw["partial"]
    return out


def merge_partials(partials) -> dict:
    """Merges the partial sums of blocks of pppm passes (``render(..., pass_range=...)``'s
    ``out["partial"]``, or the bytes of ``.ppart`` files), in any order, into the image of
    all of them: the dict ``render`` returns, ``partial`` the merged sums. Partials of
    different renders, a pass in two partials, or missing passes raise ValueError."""
    return _images(_core.merge_partials([bytes(p) for p in partials]))


def tile_stats(tiles, width: int, height: int, rounds=None) -> dict:
    """The stats of a Jensen frame of ``width`` x ``height`` rendered in tiles over the
    frame's photon maps (``photonmap render --cluster``), from its tiles' stats (dicts, or
    the JSON text ``_core.Job.tile_finish`` returns): the first tile's, with the sums of what
    the tiles counted (non-finite samples, camera-pass seconds, work) and, given each pixel's
    ``rounds`` of adaptive sampling (a (height, width) integer array, or its little-endian
    uint32 bytes as ``_core.Job.adaptive_rounds`` returns them), adaptive sampling's figures
    and the camera rays over the frame. The core computes them as for a frame rendered
    whole (``src/command/report.rs``)."""
    texts = [t if isinstance(t, str) else json.dumps(t) for t in tiles]
    if rounds is not None and not isinstance(rounds, (bytes, bytearray)):
        rounds = np.ascontiguousarray(rounds, dtype="<u4").tobytes()
    return json.loads(_core.tile_stats(texts, width, height,
                                       None if rounds is None else bytes(rounds)))


def aov_specs(light_groups: list[str] | tuple[str, ...] = (), **settings: Any) -> list[dict]:
    """The AOVs beside the terms that ``render(**settings)`` returns (and the command line
    writes) for a scene whose IR names the light groups ``light_groups`` (the core adds the
    group ``default``, for the emitters in none), in output order: for each its ``name`` (the
    result's key and the EXR layer), ``pass_name`` (Blender's), ``kind`` (``color``,
    ``vector`` or ``crypto``), ``channels`` (``R,G,B``; ``X,Y,Z``; ``R,G,B,A``), and
    ``chan_id``/``pass_type`` as Blender's ``register_pass`` takes them. The list is the
    core's (``src/render/aov.rs``)."""
    return _core.aov_specs(_settings_json(settings), list(light_groups))


def cryptomatte_header(manifests: Mapping[str, list[str]], prefix: str = "") -> dict[str, str]:
    """The EXR header attributes of Cryptomatte ``manifests`` (``out["cryptomatte"]``), each
    layer named ``prefix`` + type name (Blender: ``"ViewLayer."``): ``cryptomatte/<key>/name``,
    ``hash``, ``conversion`` and ``manifest``, as the Cryptomatte specification names them."""
    return dict(_core.cryptomatte_header(json.dumps(dict(manifests)), prefix))


def _settings_json(settings: Mapping[str, Any]) -> str:
    """The keywords as the JSON object the core reads; numpy scalars become numbers."""

    def plain(v: Any) -> Any:
        if isinstance(v, np.generic):
            return v.item()
        raise TypeError(f"setting value {v!r} of type {type(v).__name__} is not a number, "
                        "string or bool")

    for k, v in settings.items():
        if isinstance(v, (float, np.floating)) and not np.isfinite(v):
            raise ValueError(f"invalid render setting `{k}`: must be a finite number, got {v}")
    try:
        return json.dumps(dict(settings), default=plain)
    except TypeError as e:
        raise TypeError(f"render(): {e}") from None


def settings_schema() -> list[dict[str, Any]]:
    """The render settings, in order, as the core defines them: for each its ``name`` (the
    keyword), ``flag`` (the command-line flag), ``label``, ``doc``, ``type`` (``int``,
    ``float``, ``bool``, ``enum`` with ``choices``, or ``size``), ``default`` (a preset
    field's is the default preset's value), ``optional`` (``None`` is allowed), ``min``,
    ``max`` (``min_open``/``max_open`` exclude them), ``soft_max``, ``unit``, ``preset`` (a
    quality preset sets it), ``group``, and the ``mode`` or boolean setting (``requires``) it
    applies under. The Blender add-on builds its properties from it."""
    return json.loads(_core.settings_schema())


def preset(name: str) -> dict[str, Any]:
    """The settings a quality preset sets, named as the ``render`` keywords and CLI flags:
    ``spp``, ``photons``, ``caustic_photons``, ``volume_photons``, ``gather``, ``radius``
    (``None``: from the scene size), ``final_gather_rays``, ``irradiance_cache``,
    ``cache_tolerance``, ``max_specular_depth``. The numbers come from the core."""
    try:
        return json.loads(_core.preset(name))
    except ValueError as e:
        raise ValueError(str(e)) from None


def defaults() -> dict[str, Any]:
    """The defaults of the ``render`` keywords that no preset sets (``quality``, ``seed``,
    ``threads``, ``filter``, ``mode``, ``alpha``, ...), from ``settings_schema()``."""
    return {f["name"]: f["default"] for f in settings_schema() if not f["preset"]}


class Renderer:
    """A render that can be cancelled from another thread::

        r = photonmap.Renderer(scene, quality="high")
        threading.Timer(2.0, r.cancel).start()
        out = r.render()        # raises RenderCancelled if cancelled
    """

    def __init__(self, scene: Any, **settings: Any) -> None:
        self.scene = _to_scene(scene)
        self.settings = settings
        self.token = CancelToken()

    def render(self, progress: Callable[[float, str], Any] | None = None) -> dict:
        self.token.reset()
        return render(self.scene, progress=progress, cancel=self.token, **self.settings)

    def cancel(self) -> None:
        self.token.cancel()

    def render_async(self, progress=None) -> "threading.Thread":
        """Starts the render on a thread; the result (or exception) lands in ``self.result``."""

        def run():
            try:
                self.result = self.render(progress)
            except BaseException as e:  # handed to the caller
                self.result = e

        t = threading.Thread(target=run, daemon=True)
        t.start()
        return t
