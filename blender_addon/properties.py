"""Settings under ``scene.photonmap``, built at registration from the core's schema
(``photonmap.settings_schema()``): one property per render setting, with the core's name,
label, description, default and range. A preset field starts at the default preset's value,
and choosing a quality fills the preset fields from ``photonmap.preset``.

An optional setting that no preset fills (``radius``, ``time_budget``, ``memory_limit``, ...)
shows 0 or an empty field for "not set", which the engine sends as ``None`` (the core's
default)."""

from __future__ import annotations

import bpy
import photonmap
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

#: The core's settings, in order.
SCHEMA: list[dict] = photonmap.settings_schema()
#: The fields a quality preset fills.
PRESET_FIELDS = tuple(f["name"] for f in SCHEMA if f["preset"])
#: Blender's int properties are 32-bit.
_INT_MAX = 2**31 - 1


def _apply_preset(self, _context):
    for key, value in photonmap.preset(self.quality).items():
        setattr(self, key, value if value is not None else 0)


def _update_passes(_self, context):
    """A setting of the passes changed: Blender asks the engine for its passes again."""
    layer = getattr(context, "view_layer", None)
    if layer is not None:
        layer.update_render_passes()


def _unset_means_none(f: dict) -> bool:
    """True when 0 or "" stands for "not set": an optional number, size or path."""
    return f["optional"] and f["type"] in ("int", "float", "size", "path")


def _limits(f: dict, integer: bool) -> dict:
    """min, max and soft_max of a numeric property. An excluded bound stays the limit (the
    core names the setting when it is hit); an unset value of 0 lowers the minimum to 0."""
    conv = int if integer else float
    kw = {}
    if f["min"] is not None:
        kw["min"] = conv(0 if _unset_means_none(f) and not f["preset"] else f["min"])
    if f["max"] is not None:
        kw["max"] = conv(f["max"])
    if f["soft_max"] is not None:
        kw["soft_max"] = conv(f["soft_max"])
    if integer:
        kw["max"] = min(kw.get("max", _INT_MAX), _INT_MAX)
    return kw


def _property(f: dict):
    """The bpy property of one schema field."""
    common = {"name": f["label"], "description": f["doc"]}
    if f["group"] == "passes":
        common["update"] = _update_passes
    kind, default = f["type"], f["default"]
    if kind == "enum":
        items = [(c["name"], c["label"], c["doc"]) for c in f["choices"]]
        extra = {"update": _apply_preset} if f["name"] == "quality" else {}
        return EnumProperty(items=items, default=default, **common, **extra)
    if kind == "bool":
        return BoolProperty(default=bool(default), **common)
    if kind == "int":
        return IntProperty(default=int(default or 0), **_limits(f, True), **common)
    if kind == "float":
        subtype = "DISTANCE" if f["unit"] == "distance" else "NONE"
        return FloatProperty(default=float(default or 0.0), subtype=subtype,
                             **_limits(f, False), **common)
    if kind == "size":
        return StringProperty(default="" if default is None else str(default), **common)
    if kind == "path":
        return StringProperty(default="" if default is None else str(default),
                              subtype="FILE_PATH", **common)
    raise TypeError(f"setting {f['name']}: no Blender property for type {kind!r}")


PhotonMapSettings = type(
    "PhotonMapSettings",
    (bpy.types.PropertyGroup,),
    {"__annotations__": {f["name"]: _property(f) for f in SCHEMA},
     "__doc__": "PhotonMap's render settings (the core's schema)"},
)


def render_settings(s) -> dict:
    """Keyword arguments of ``photonmap.render`` for these settings: every schema field, by
    its name; an unset optional one as ``None``."""
    out = {}
    for f in SCHEMA:
        v = getattr(s, f["name"])
        if isinstance(v, str) and f["type"] != "enum":
            v = v.strip()
        if _unset_means_none(f) and not v:
            v = None
        elif f["type"] == "path":
            v = bpy.path.abspath(v)  # Blender's "//" is relative to the .blend file
        out[f["name"]] = v
    return out


def register():
    bpy.utils.register_class(PhotonMapSettings)
    bpy.types.Scene.photonmap = bpy.props.PointerProperty(type=PhotonMapSettings)


def unregister():
    del bpy.types.Scene.photonmap
    bpy.utils.unregister_class(PhotonMapSettings)
