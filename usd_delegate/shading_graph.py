"""UsdShade networks -> IR shading graphs (``{"type": "graph", ...}``), for materials the flat
IR materials cannot express (textures through UsdTransform2d, normal maps, opacity as coverage,
mixed BSDFs, MaterialX node graphs).

A value is a constant (a float, or a list of 3 floats) or a link ``{"node": i, "output": o}``.
Operations on constants are folded here, so constant sub-networks emit no nodes. Node types the
core does not list in ``photonmap._core.GRAPH_NODES`` are never emitted: the node that needed
one is warned and its consumer's input keeps its value.

| USD / MaterialX node | graph nodes |
|---|---|
| ``UsdUVTexture`` (file, wrapS, scale, bias, sourceColorSpace, fallback; rgb, r, g, b, a) | `image_texture` (scale and bias baked into the texture), `separate_xyz` for r, g, b |
| ``UsdPrimvarReader_float2`` | the mesh UV for ``st``; another varname, that primvar per vertex (an `attribute`) |
| ``UsdPrimvarReader_float/float3/float4/normal/point/vector`` | `attribute` of the varname (the mesh's primvar per vertex; `fac`, the mean, for `_float`); int and string readers warned, their ``fallback`` |
| ``UsdTransform2d`` | `mapping` (POINT: scale, then rotation in degrees, then translation) |
| ``ND_image_*``, ``ND_tiledimage_*``, ``ND_gltf_image_*`` | `image_texture` (tiled: `mapping` with uvtiling, -uvoffset) |
| ``ND_texcoord_*``, ``ND_geompropvalue_vector2`` of ``st`` | the mesh UV (another geomprop: that primvar per vertex) |
| ``ND_geompropvalue_*`` (float, color, vector) | `attribute` of the geomprop (the mesh's primvar per vertex) |
| ``ND_constant_*``, ``ND_convert_*``, ``ND_dot_*`` | the value itself |
| ``ND_add/subtract/multiply/divide_*`` | `math` (floats) or `vector_math` |
| ``ND_floor/ceil/round/absval/sign/sin/cos/tan/asin/acos/sqrt/exp/ln_*``, ``ND_power/max/min_*``, ``ND_atan2_*``, ``ND_invert_*`` | `math` (floats) or `vector_math` (per component as `math` where it has no such operation) |
| ``ND_modulo_*`` (floored, as GLSL's mod) | `math` FLOORED_MODULO, `vector_math` WRAP with min 0 |
| ``ND_clamp_*`` | `clamp` (MINMAX) for floats, `vector_math` MAXIMUM then MINIMUM |
| ``ND_remap_*`` | `map_range` (LINEAR, unclamped) |
| ``ND_extract_*`` | `separate_xyz` (an image's alpha for index 3) |
| ``ND_magnitude/distance/crossproduct_vector3`` | `vector_math` LENGTH, DISTANCE, CROSS_PRODUCT |
| ``ND_mix_<float,color3,vector3>`` | `mix` (MIX, factor unclamped): bg + mix x (fg - bg) |
| ``ND_ifequal/ifgreater/ifgreatereq_*`` | `math` COMPARE / GREATER_THAN / LESS_THAN into `mix` |
| ``ND_dotproduct_vector3``, ``ND_normalize_vector3`` | `vector_math` DOT_PRODUCT, NORMALIZE |
| ``ND_position_vector3`` | `tex_coord` object (space `object`, `model`) or `geometry` position (`world`) |
| ``ND_rotate3d_vector3`` | `vector_rotate` (AXIS_ANGLE inverted, as MaterialX's GLSL rotates; ``amount`` in degrees, as RADIANS `math`) |
| ``ND_separate2/3/4_*``, ``ND_combine2/3_*`` | `separate_xyz`, `combine_xyz` (an image's alpha for ``outa``) |
| ``ND_normalmap*`` | `normal_map` (TANGENT or OBJECT; scale as strength, warned when not 1) |
| ``ND_normal_vector3`` | the geometry's normal |
| ``ND_mix_bsdf``/``ND_mix_edf``, ``ND_add_bsdf``/``ND_add_edf`` | `mix_shader` (fac = mix, shader1 = bg), `add_shader` |
| ``ND_layer_bsdf`` stack of Blender's Principled BSDF (its exporter's BSDF for a Principled in a Mix or Add Shader: coat over thin film over metal/specular/transmission/sheen/diffuse) | `principled` (Base Color from the transmission lobe's tint; Roughness from ``ND_roughness_anisotropy``; Specular IOR Level = the specular lobe's weight) |
| ``ND_oren_nayar_diffuse_bsdf``, ``ND_burley_diffuse_bsdf`` | `diffuse` (color x weight) |
| ``ND_dielectric_bsdf`` | `glass` (tint x weight); scatter_mode `T`: `refraction` (Blender's Refraction BSDF); `R` warned |
| ``ND_conductor_bsdf`` | `glossy` (normal-incidence reflectance x weight; constant ior only) |
| ``ND_translucent_bsdf``, ``ND_uniform_edf`` | `translucent`, `emission` (none when black) |
| ``ND_surface`` | its bsdf `add_shader` its edf; opacity as a `mix_shader` with `transparent` |
| ``ND_open_pbr_surface``, ``ND_standard_surface``, ``(ND_)UsdPreviewSurface`` | `principled` |

Warned with the node's prim path and ``info:id``, its consumer keeping its input's value:
``ND_noise*``/``ND_fractal*``/``ND_cellnoise*``/``ND_worley*`` (MaterialX noises are not Cycles'
noises), ``ND_heighttonormal_vector3`` (the height's gradient per unit of texture coordinate, where
Cycles' Bump takes it per unit of surface length: a normalmap of it gives the surface's own
normal), any other ``ND_layer_bsdf`` (no general layering), ``ND_tangent``,
``ND_position``, and any other node.
"""

from __future__ import annotations

import json
import math

_AVAILABLE = None


def available_nodes() -> frozenset:
    """The graph node types the core compiles (empty when the core cannot be imported)."""
    global _AVAILABLE
    if _AVAILABLE is None:
        try:
            from photonmap import _core

            _AVAILABLE = frozenset(json.loads(_core.GRAPH_NODES))
        except Exception:
            _AVAILABLE = frozenset()
    return _AVAILABLE


class Untranslatable(Exception):
    """A node that cannot be translated; the message says why."""


def is_link(v) -> bool:
    return isinstance(v, dict)


def const(v):
    """A USD value as a graph constant: a float, or a list of 3 floats (vector2 -> (u, v, 0),
    color4 -> its rgb); None for anything else."""
    if v is None or isinstance(v, str):
        return None
    if isinstance(v, bool):
        return float(v)
    if isinstance(v, (int, float)):
        return float(v)
    try:
        c = [float(x) for x in v]
    except (TypeError, ValueError):
        return None
    if len(c) == 1:
        return c[0]
    if len(c) == 2:
        return [c[0], c[1], 0.0]
    return c[:3]


def _vec(v):
    return list(v) if isinstance(v, list) else [float(v)] * 3


def _safe_pow(a, b):
    """Cycles' safe_powf."""
    if a < 0.0 and b != float(int(b)):
        return 0.0
    if b == 0.0:
        return 1.0
    if a == 0.0:
        return 0.0
    return a ** b


def _floored_mod(a, b):
    return a - math.floor(a / b) * b if b != 0.0 else 0.0


#: Cycles' Math node operations on constants (x, y, z: its three values).
_MATH = {
    "ADD": lambda x, y, z: x + y, "SUBTRACT": lambda x, y, z: x - y,
    "MULTIPLY": lambda x, y, z: x * y,
    "RADIANS": lambda x, y, z: math.radians(x),
    "DIVIDE": lambda x, y, z: x / y if y != 0 else 0.0,
    "GREATER_THAN": lambda x, y, z: 1.0 if x > y else 0.0,
    "LESS_THAN": lambda x, y, z: 1.0 if x < y else 0.0,
    "COMPARE": lambda x, y, z: 1.0 if abs(x - y) <= max(z, 1e-5) else 0.0,
    "MULTIPLY_ADD": lambda x, y, z: x * y + z,
    "FLOOR": lambda x, y, z: float(math.floor(x)), "CEIL": lambda x, y, z: float(math.ceil(x)),
    "ROUND": lambda x, y, z: float(math.floor(x + 0.5)),
    "ABSOLUTE": lambda x, y, z: abs(x),
    "SIGN": lambda x, y, z: 0.0 if x == 0 else math.copysign(1.0, x),
    "FLOORED_MODULO": lambda x, y, z: _floored_mod(x, y),
    "POWER": lambda x, y, z: _safe_pow(x, y),
    "MAXIMUM": lambda x, y, z: x if x > y else y, "MINIMUM": lambda x, y, z: x if x < y else y,
    "SINE": lambda x, y, z: math.sin(x), "COSINE": lambda x, y, z: math.cos(x),
    "TANGENT": lambda x, y, z: math.tan(x),
    "ARCSINE": lambda x, y, z: math.asin(min(1.0, max(-1.0, x))),
    "ARCCOSINE": lambda x, y, z: math.acos(min(1.0, max(-1.0, x))),
    "ARCTAN2": lambda x, y, z: 0.0 if x == 0 and y == 0 else math.atan2(x, y),
    "SQRT": lambda x, y, z: math.sqrt(x) if x > 0 else 0.0,
    "EXPONENT": lambda x, y, z: math.exp(x),
    "LOGARITHM": lambda x, y, z: (math.log(x) / math.log(y)
                                  if x > 0 and y > 0 and y != 1 else 0.0),
}
#: Vector Math operations that act per component as the Math operation of the same name.
_VMATH_PER_COMPONENT = ("ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "FLOOR", "CEIL",
                        "ABSOLUTE", "SIGN", "POWER", "MAXIMUM", "MINIMUM", "SINE", "COSINE",
                        "TANGENT")


def _scalar(v):
    """A constant read as a float (a colour or vector: its mean, as the core reads a vector)."""
    return sum(v) / 3.0 if isinstance(v, list) else float(v)


def _rgba(v):
    """A reader's fallback (a number or 2-4 numbers) as RGBA, or None."""
    if v is None:
        return None
    try:
        c = [float(x) for x in v]
    except TypeError:
        c = [float(v)] * 3
    c = (c + [0.0, 0.0, 0.0])[:3] + [c[3] if len(c) > 3 else 1.0]
    return c if all(math.isfinite(x) for x in c) else None


class Graph:
    """An IR graph under construction."""

    def __init__(self, name: str, available=None) -> None:
        self.name = name
        self.available = available_nodes() if available is None else available
        self.nodes: list[dict] = []
        self._separated: dict = {}

    def add(self, kind: str, inputs=None, params=None, name: str = "") -> int:
        if kind not in self.available:
            raise Untranslatable(f"the renderer has no `{kind}` graph node")
        node = {"type": kind}
        if name:
            node["name"] = name
        ins = {k: v for k, v in (inputs or {}).items() if v is not None}
        if ins:
            node["inputs"] = ins
        if params:
            node["params"] = params
        self.nodes.append(node)
        return len(self.nodes) - 1

    def out(self, kind, output, inputs=None, params=None, name="") -> dict:
        return {"node": self.add(kind, inputs, params, name), "output": output}

    def material(self, surface: dict) -> dict:
        return {"type": "graph", "name": self.name, "nodes": self.nodes, "surface": surface}

    # -- value operations (folded on constants) ----------------------------------------

    def math(self, op: str, a, b=0.0, c=0.0):
        if not any(is_link(x) for x in (a, b, c)):
            f = _MATH.get(op)
            if f is not None:
                return f(_scalar(a), _scalar(b), _scalar(c))
        return self.out("math", "value", {"value": a, "value_001": b, "value_002": c},
                        {"operation": op, "use_clamp": False})

    def vmath(self, op: str, a, b=None, c=None):
        if not any(is_link(x) for x in (a, b, c)):
            x = _vec(a)
            y = _vec(b if b is not None else 0.0)
            z = _vec(c if c is not None else 0.0)
            if op == "DOT_PRODUCT":
                return sum(p * q for p, q in zip(x, y))
            if op == "NORMALIZE":
                n = math.sqrt(sum(p * p for p in x))
                return [p / n for p in x] if n > 0 else [0.0, 0.0, 0.0]
            if op in ("LENGTH", "DISTANCE"):
                d = x if op == "LENGTH" else [p - q for p, q in zip(x, y)]
                return math.sqrt(sum(p * p for p in d))
            if op == "CROSS_PRODUCT":
                return [x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2],
                        x[0] * y[1] - x[1] * y[0]]
            if op == "WRAP":  # wrap(a, max b, min c)
                return [_floored_mod(p - r, q - r) + r for p, q, r in zip(x, y, z)]
            f = _MATH.get(op) if op in _VMATH_PER_COMPONENT else None
            if f is not None:
                return [f(p, q, r) for p, q, r in zip(x, y, z)]
        ins = {"vector": a, "vector_001": b, "vector_002": c}
        output = "value" if op in ("DOT_PRODUCT", "LENGTH", "DISTANCE") else "vector"
        return self.out("vector_math", output, ins, {"operation": op})

    def scale(self, a, w):
        """a x w for a colour a and a float w."""
        if not is_link(w) and _scalar(w) == 1.0:
            return a
        return self.vmath("MULTIPLY", a, w)

    def mix(self, data_type: str, factor, a, b):
        """a + factor x (b - a), factor unclamped."""
        if not is_link(factor):
            f = _scalar(factor)
            if f == 0.0:
                return a
            if f == 1.0:
                return b
            if not is_link(a) and not is_link(b):
                if data_type == "FLOAT":
                    return _scalar(a) + f * (_scalar(b) - _scalar(a))
                return [p + f * (q - p) for p, q in zip(_vec(a), _vec(b))]
        return self.out("mix", "result", {"factor": factor, "a": a, "b": b},
                        {"data_type": data_type, "blend_type": "MIX", "clamp_factor": False,
                         "clamp_result": False})

    def separate(self, v, axis: int):
        if not is_link(v):
            return _vec(v)[axis]
        key = (v["node"], v["output"])
        if key not in self._separated:  # one separate_xyz per vector
            self._separated[key] = self.add("separate_xyz", {"vector": v})
        return {"node": self._separated[key], "output": "xyz"[axis]}

    def combine(self, x, y, z=0.0):
        if not any(is_link(t) for t in (x, y, z)):
            return [_scalar(x), _scalar(y), _scalar(z)]
        return self.out("combine_xyz", "vector", {"x": x, "y": y, "z": z})

    def mapping(self, v, location, rotation, scale):
        if location == [0.0] * 3 and rotation == [0.0] * 3 and scale == [1.0] * 3:
            return v
        return self.out("mapping", "vector", {"vector": v, "location": location,
                                              "rotation": rotation, "scale": scale},
                        {"vector_type": "POINT"})

    def uv(self):
        return self.out("tex_coord", "uv")

    def attribute(self, name: str, output: str, fallback=None):
        """The mesh primvar ``name`` read per vertex (the core's Attribute node); ``fallback``
        (RGBA) where a mesh lacks it."""
        params = {"name": name}
        if fallback is not None:
            params["fallback"] = fallback
        return self.out("attribute", output, params=params)


# -- the translator -------------------------------------------------------------------------

PREVIEW_IDS = ("UsdPreviewSurface", "ND_UsdPreviewSurface_surfaceshader")
#: Names under which a reader means the mesh's UV set (``primvars:st``, which Blender writes
#: for the active UV map); other names read the primvar of that name.
UV_SET_NAMES = ("", "st", "UVMap", "uv")
OPENPBR = "ND_open_pbr_surface_surfaceshader"
STANDARD = "ND_standard_surface_surfaceshader"
_IMAGE = ("ND_image_", "ND_tiledimage_", "ND_gltf_image_", "ND_gltf_colorimage")
_WRAP = {"periodic": "repeat", "clamp": "clamp", "mirror": "mirror", "constant": "black"}
_MTLX_CS = {"srgb_texture": "sRGB", "lin_rec709": "raw", "raw": "raw"}
#: MaterialX operators by node name (the id without ``ND_`` and its type suffix), longest first.
_OPS = sorted(["constant", "convert", "dot", "add", "subtract", "multiply", "divide", "mix",
               "ifequal", "ifgreater", "ifgreatereq", "dotproduct", "normalize", "rotate3d", "position",
               "separate2",
               "separate3", "separate4", "combine2", "combine3", "normalmap", "normal",
               "texcoord", "geompropvalue", "mix_bsdf", "mix_edf", "add_bsdf", "add_edf",
               "oren_nayar_diffuse_bsdf", "burley_diffuse_bsdf", "dielectric_bsdf",
               "conductor_bsdf", "translucent_bsdf", "uniform_edf", "surface",
               "floor", "ceil", "round", "absval", "sign", "sin", "cos", "tan", "asin", "acos",
               "sqrt", "exp", "ln", "modulo", "power", "max", "min", "atan2", "clamp",
               "invert", "remap", "extract", "magnitude", "distance", "crossproduct",
               "layer_bsdf", "heighttonormal"],
              key=len, reverse=True)
#: MaterialX unary operators (input ``in``) -> Cycles Math operation.
_UNARY = {"floor": "FLOOR", "ceil": "CEIL", "round": "ROUND", "absval": "ABSOLUTE",
          "sign": "SIGN", "sin": "SINE", "cos": "COSINE", "tan": "TANGENT", "asin": "ARCSINE",
          "acos": "ARCCOSINE", "sqrt": "SQRT", "exp": "EXPONENT", "ln": "LOGARITHM"}
#: MaterialX binary operators (in1, in2) -> (Cycles Math operation, in2's default). MaterialX's modulo is floored (GLSL mod), Cycles' MODULO truncated: floats use
#: FLOORED_MODULO, vectors WRAP with min 0 (the same function).
_BINARY = {"modulo": ("FLOORED_MODULO", 1.0), "power": ("POWER", 1.0), "max": ("MAXIMUM", 0.0),
           "min": ("MINIMUM", 0.0)}
_NOISES = ("ND_noise", "ND_fractal", "ND_cellnoise", "ND_worley", "ND_unifiednoise")
GREY = [0.18, 0.18, 0.18]


def shader_id(shader) -> str:
    sid = shader.GetIdAttr().Get() if shader else None
    return str(sid or "")


def _op_of(sid: str):
    """(operator, type suffix) of a MaterialX ``ND_`` id, or (None, "")."""
    if not sid.startswith("ND_"):
        return None, ""
    rest = sid[3:]
    for op in _OPS:
        if rest == op:
            return op, ""
        if rest.startswith(op + "_"):
            return op, rest[len(op) + 1:]
    return None, ""


def _data_type(suffix: str) -> str:
    t = suffix.split("_")[0].rstrip("FA")
    if t.startswith("float"):
        return "FLOAT"
    if t.startswith("color"):
        return "RGBA"
    return "VECTOR"


#: MaterialX image filtertype -> the graph's interpolation (Cycles' names).
_FILTERS = {"closest": "Closest", "linear": "Linear", "cubic": "Cubic"}


class Translator:
    """Translates one UsdShade material's surface network into a Graph."""

    def __init__(self, table, name: str, available=None) -> None:
        self.table = table
        self.diag = table.diag
        self.time = table.time
        self.g = Graph(name, available)
        self._memo: dict = {}
        self._images: dict = {}
        #: The material's displacement (a world-space offset), applied as a bump.
        self.displacement = None

    # -- inputs ------------------------------------------------------------------------

    def authored(self, shader, name):
        inp = shader.GetInput(name)
        return inp.Get(self.time) if inp else None

    def constant(self, shader, name, default):
        c = const(self.authored(shader, name))
        return default if c is None else c

    def source(self, shader, name):
        """(shader, output name) connected to an input, through NodeGraph outputs."""
        from .materials import _follow

        inp = shader.GetInput(name)
        if not inp or not inp.HasConnectedSource():
            return None
        for src in inp.GetConnectedSources()[0]:
            s = _follow(src.source, src.sourceName, 0)
            if s:
                return s, str(src.sourceName)
        return None

    def input(self, shader, name, default):
        """The input's value: its connected node's output when that translates, else its
        authored value, else ``default``."""
        src = self.source(shader, name)
        if src is not None:
            v = self.output(src[0], src[1])
            if v is not None:
                return v
        return self.constant(shader, name, default)

    def connected(self, shader, name) -> bool:
        return self.source(shader, name) is not None

    def output(self, shader, out):
        """A node's output as a value; None (warned) when the node cannot be translated."""
        key = (str(shader.GetPath()), out)
        if key in self._memo:
            return self._memo[key]
        self._memo[key] = None  # a cycle reads as untranslatable
        try:
            v = self._translate(shader, out)
        except Untranslatable as e:
            sid = shader_id(shader)
            self.diag.warn(shader.GetPrim(), f"node `{sid}` cannot be translated ({e}); its "
                                             f"consumer's input value is used")
            v = None
        self._memo[key] = v
        return v

    # -- nodes -------------------------------------------------------------------------

    def _translate(self, s, out):
        sid = shader_id(s)
        if sid == "UsdUVTexture":
            return self._uv_texture(s, out)
        if sid == "UsdPrimvarReader_float2":
            name = str(self.authored(s, "varname") or "")
            if name in UV_SET_NAMES:
                return self.g.uv()
            # Another UV set: the mesh's primvar of that name, per vertex.
            self.table.attribute_names.add(name)
            return self.g.attribute(name, "vector", _rgba(self.authored(s, "fallback")))
        if sid.startswith("UsdPrimvarReader_"):
            name = str(self.authored(s, "varname") or "")
            if sid == "UsdPrimvarReader_int" or sid == "UsdPrimvarReader_string":
                fb = const(self.authored(s, "fallback"))
                self.diag.warn(s.GetPrim(), f"`{sid}` is not supported; "
                                            + ("its fallback is used" if fb is not None
                                               else "its consumer's input value is used"))
                return fb
            # A mesh without the primvar reads the reader's fallback (zero without one).
            self.table.attribute_names.add(name)
            fb = self.authored(s, "fallback")
            return self.g.attribute(name, "fac" if sid == "UsdPrimvarReader_float" else "color",
                                    _rgba(fb))
        if sid == "UsdTransform2d":
            return self._transform2d(s)
        if sid in PREVIEW_IDS:
            return self.preview(s)
        if sid in (OPENPBR, STANDARD):
            return self.pbr(s)
        if sid.startswith(_IMAGE):
            return self._image(s, out)
        if sid.startswith(_NOISES):
            raise Untranslatable("MaterialX noise differs from Cycles' noise")
        if sid in ("ND_hsvadjust_color3", "ND_hsvadjust_color4"):
            return self._hsvadjust(s)
        op, suffix = _op_of(sid)
        if op is None:
            raise Untranslatable("unsupported node")
        if op in _UNARY:
            return self._unary(s, suffix, _UNARY[op])
        if op in _BINARY and op != "power":
            return self._binary_op(s, suffix, op)
        return getattr(self, "_nd_" + op)(s, out, suffix)

    # UsdPreviewSurface helpers

    def _uv_texture(self, s, out):
        from .textures import MAGENTA, resolve_asset

        prim = s.GetPrim()
        key = str(s.GetPath())
        if key not in self._images:
            path = resolve_asset(self.authored(s, "file"), prim)
            cs = self.authored(s, "sourceColorSpace")
            cs = str(cs) if cs else "auto"
            wrap = str(self.authored(s, "wrapS") or "useMetadata")
            wrap_t = self.authored(s, "wrapT")
            if wrap_t and str(wrap_t) != wrap:
                self.diag.warn(prim, "wrapT differs from wrapS: wrapS is used for both")
            sc = self.authored(s, "scale")
            bi = self.authored(s, "bias")
            scale = tuple(sc) if sc is not None else (1, 1, 1, 1)
            bias = tuple(bi) if bi is not None else (0, 0, 0, 0)
            idx = self.table.textures.add(prim, path, cs, wrap, scale, bias)
            node = None
            if idx is not None:
                vec = self.input(s, "st", None) if self.connected(s, "st") else None
                node = self.g.add("image_texture", {"vector": vec}, {"texture": idx},
                                  name=prim.GetName())
            self._images[key] = node
        node = self._images[key]
        if node is None:  # missing file: the fallback (magenta when not authored)
            fb = self.authored(s, "fallback")
            fb = [float(c) for c in fb] if fb is not None else list(MAGENTA) + [1.0]
            return {"rgb": fb[:3], "r": fb[0], "g": fb[1], "b": fb[2],
                    "a": fb[3] if len(fb) > 3 else 1.0}.get(out, fb[:3])
        color = {"node": node, "output": "color"}
        if out == "a":
            return {"node": node, "output": "alpha"}
        if out in ("r", "g", "b"):
            return self.g.separate(color, "rgb".index(out))
        return color

    def _transform2d(self, s):
        v = self.input(s, "in", None) if self.connected(s, "in") else None
        if v is None:
            v = self.g.uv()
        rot = float(self.authored(s, "rotation") or 0.0)
        sc = const(self.authored(s, "scale")) or [1.0, 1.0, 0.0]
        tr = const(self.authored(s, "translation")) or [0.0, 0.0, 0.0]
        return self.g.mapping(v, [tr[0], tr[1], 0.0], [0.0, 0.0, math.radians(rot)],
                              [sc[0], sc[1], 1.0])

    # MaterialX images

    def _image(self, s, out):
        from .textures import MAGENTA, resolve_asset

        prim = s.GetPrim()
        sid = shader_id(s)
        key = str(s.GetPath())
        if key not in self._images:
            f = s.GetInput("file")
            path = resolve_asset(f.Get(self.time) if f else None, prim)
            cs = (f.GetAttr().GetColorSpace() if f else "") or "auto"
            cs = _MTLX_CS.get(cs, cs)
            ua = str(self.authored(s, "uaddressmode") or "periodic")
            va = self.authored(s, "vaddressmode")
            if va and str(va) != ua:
                self.diag.warn(prim, "vaddressmode differs from uaddressmode: uaddressmode is "
                                     "used for both")
            idx = self.table.textures.add(prim, path, cs, _WRAP.get(ua, "repeat"))
            node = None
            if idx is not None:
                vec = self.input(s, "texcoord", None) if self.connected(s, "texcoord") else None
                if sid.startswith("ND_tiledimage_"):
                    tiling = const(self.authored(s, "uvtiling")) or [1.0, 1.0, 0.0]
                    offset = const(self.authored(s, "uvoffset")) or [0.0, 0.0, 0.0]
                    vec = self.g.mapping(vec if vec is not None else self.g.uv(),
                                         [-offset[0], -offset[1], 0.0], [0.0] * 3,
                                         [tiling[0], tiling[1], 1.0])
                filt = str(self.authored(s, "filtertype") or "linear")
                interp = _FILTERS.get(filt)
                if interp is None:
                    self.diag.warn(prim, f"filtertype `{filt}` is not a MaterialX filter; "
                                         f"read as linear")
                    interp = "Linear"
                node = self.g.add("image_texture", {"vector": vec},
                                  {"texture": idx, "interpolation": interp},
                                  name=prim.GetName())
            self._images[key] = node
        node = self._images[key]
        if node is None:
            d = const(self.authored(s, "default"))
            return d if d is not None else list(MAGENTA)
        color = {"node": node, "output": "color"}
        if sid.endswith("_float"):
            return self.g.separate(color, 0)
        return color

    def _hsvadjust(self, s):
        """MaterialX hsvadjust (hue + amount.x in turns, saturation and value times amount.y
        and amount.z), which is the Hue/Saturation/Value node at hue 0.5 + amount.x."""
        amount = self.input(s, "amount", [0.0, 1.0, 1.0])
        color = self.input(s, "in", [0.0, 0.0, 0.0])
        return self.g.out("hue_saturation", "color", {
            "hue": self.g.math("ADD", self.g.separate(amount, 0), 0.5),
            "saturation": self.g.separate(amount, 1),
            "value": self.g.separate(amount, 2),
            "fac": 1.0,
            "color": color,
        })

    def image_alpha(self, s):
        """The alpha of an image node's colour4 output, or None."""
        sid = shader_id(s)
        if not (sid.startswith(_IMAGE) and sid.endswith("color4")) and sid != "UsdUVTexture":
            return None
        self.output(s, "out")
        node = self._images.get(str(s.GetPath()))
        return {"node": node, "output": "alpha"} if node is not None else 1.0

    # MaterialX standard library

    def _nd_constant(self, s, out, t):
        return self.constant(s, "value", 0.0)

    def _nd_convert(self, s, out, t):
        return self.input(s, "in", 0.0)

    _nd_dot = _nd_convert

    def _binary(self, s, t, op):
        a = self.input(s, "in1", 0.0)
        b = self.input(s, "in2", 1.0 if op in ("MULTIPLY", "DIVIDE") else 0.0)
        if _data_type(t) == "FLOAT":
            return self.g.math(op, a, b)
        return self.g.vmath(op, a, b)

    def _nd_add(self, s, out, t):
        return self._binary(s, t, "ADD")

    def _nd_subtract(self, s, out, t):
        return self._binary(s, t, "SUBTRACT")

    def _nd_multiply(self, s, out, t):
        return self._binary(s, t, "MULTIPLY")

    def _nd_divide(self, s, out, t):
        return self._binary(s, t, "DIVIDE")

    def _per_component(self, op, t, a, b=0.0, c=0.0):
        """Math ``op`` on floats; on vectors and colours the Vector Math operation of the same
        function where there is one, else Math per component."""
        if _data_type(t) == "FLOAT":
            return self.g.math(op, a, b, c)
        if op == "FLOORED_MODULO":
            return self.g.vmath("WRAP", a, b, 0.0)
        if op in _VMATH_PER_COMPONENT:
            return self.g.vmath(op, a, b, c)

        def part(v, i):
            return self.g.separate(v, i) if is_link(v) or isinstance(v, list) else v

        return self.g.combine(*(self.g.math(op, part(a, i), part(b, i), part(c, i))
                                for i in range(3)))

    def _unary(self, s, t, op):
        a = self.input(s, "in", 0.0)
        return self._per_component(op, t, a, math.e if op == "LOGARITHM" else 0.0)

    def _binary_op(self, s, t, name):
        op, default = _BINARY[name]
        return self._per_component(op, t, self.input(s, "in1", 0.0),
                                   self.input(s, "in2", default))

    def _nd_power(self, s, out, t):
        b = self.input(s, "in2", 1.0)
        if not is_link(b) and isinstance(b, float) and b == 1.0:
            return self.input(s, "in1", 0.0)  # x^1 = x, as Cycles' safe power gives it
        return self._binary_op(s, t, "power")

    def _nd_atan2(self, s, out, t):  # atan2(iny, inx); MaterialX 1.38: in1, in2
        names = ("iny", "inx") if s.GetInput("iny") or s.GetInput("inx") else ("in1", "in2")
        y = self.input(s, names[0], 0.0)
        x = self.input(s, names[1], 1.0)
        return self._per_component("ARCTAN2", t, y, x)

    def _nd_clamp(self, s, out, t):
        v = self.input(s, "in", 0.0)
        lo = self.input(s, "low", 0.0)
        hi = self.input(s, "high", 1.0)
        if _data_type(t) == "FLOAT":
            if not any(is_link(x) for x in (v, lo, hi)):
                return min(max(_scalar(v), _scalar(lo)), _scalar(hi))
            return self.g.out("clamp", "result", {"value": v, "min": lo, "max": hi},
                              {"clamp_type": "MINMAX"})
        return self.g.vmath("MINIMUM", self.g.vmath("MAXIMUM", v, lo), hi)

    def _nd_invert(self, s, out, t):  # amount - in
        return self._per_component("SUBTRACT", t, self.input(s, "amount", 1.0),
                                   self.input(s, "in", 0.0))

    def _nd_remap(self, s, out, t):
        """outlow + (in - inlow) x (outhigh - outlow) / (inhigh - inlow), unclamped: Map Range
        (Linear, no clamp)."""
        v = self.input(s, "in", 0.0)
        bounds = [self.input(s, n, d) for n, d in
                  (("inlow", 0.0), ("inhigh", 1.0), ("outlow", 0.0), ("outhigh", 1.0))]
        if _data_type(t) == "FLOAT":
            if not any(is_link(x) for x in [v] + bounds):
                a, b, c, d = (_scalar(x) for x in bounds)
                f = (_scalar(v) - a) / (b - a) if b != a else 0.0
                return c + f * (d - c)
            names = ("from_min", "from_max", "to_min", "to_max")
            return self.g.out("map_range", "result", {"value": v, **dict(zip(names, bounds))},
                              {"data_type": "FLOAT", "interpolation_type": "LINEAR",
                               "clamp": False})
        names = ("from_min_float3", "from_max_float3", "to_min_float3", "to_max_float3")
        ins = {n: (x if is_link(x) else _vec(x)) for n, x in zip(names, bounds)}
        return self.g.out("map_range", "vector", {"vector": v, **ins},
                          {"data_type": "FLOAT_VECTOR", "interpolation_type": "LINEAR",
                           "clamp": False})

    def _nd_extract(self, s, out, t):
        index = int(self.authored(s, "index") or 0)
        return self._separate(s, ("outx", "outy", "outz", "outw")[index] if 0 <= index < 4
                              else f"index {index}")

    def _nd_magnitude(self, s, out, t):
        return self.g.vmath("LENGTH", self.input(s, "in", [0.0] * 3))

    def _nd_distance(self, s, out, t):
        return self.g.vmath("DISTANCE", self.input(s, "in1", [0.0] * 3),
                            self.input(s, "in2", [0.0] * 3))

    def _nd_crossproduct(self, s, out, t):
        return self.g.vmath("CROSS_PRODUCT", self.input(s, "in1", [0.0] * 3),
                            self.input(s, "in2", [0.0] * 3))

    def _nd_heighttonormal(self, s, out, t):
        raise Untranslatable(
            "it takes the height's gradient per unit of texture coordinate (screen-space "
            "differences), where Cycles' Bump takes it per unit of surface length: the two "
            "agree only where the UV map has unit scale")

    def _nd_mix(self, s, out, t):
        fg = self.input(s, "fg", 0.0)
        bg = self.input(s, "bg", 0.0)
        return self.g.mix(_data_type(t), self.input(s, "mix", 0.0), bg, fg)

    def _if(self, s, t, op, swap):
        c = self.g.math(op, self.input(s, "value1", 1.0 if op == "COMPARE" else 0.0),
                        self.input(s, "value2", 0.0))
        in1 = self.input(s, "in1", 0.0)
        in2 = self.input(s, "in2", 0.0)
        a, b = (in1, in2) if swap else (in2, in1)
        return self.g.mix(_data_type(t), c, a, b)

    def _nd_ifequal(self, s, out, t):
        if t.endswith("B") or "boolean" in t:
            raise Untranslatable("boolean comparison")
        return self._if(s, t, "COMPARE", False)

    def _nd_ifgreater(self, s, out, t):
        return self._if(s, t, "GREATER_THAN", False)

    def _nd_ifgreatereq(self, s, out, t):  # value1 >= value2 = not (value1 < value2)
        return self._if(s, t, "LESS_THAN", True)

    def _nd_dotproduct(self, s, out, t):
        return self.g.vmath("DOT_PRODUCT", self.input(s, "in1", [0.0] * 3),
                            self.input(s, "in2", [0.0] * 3))

    def _nd_position(self, s, out, t):
        space = str(self.authored(s, "space") or "object")
        if space == "world":
            return self.g.out("geometry", "position")
        return self.g.out("tex_coord", "object")

    def _nd_rotate3d(self, s, out, t):
        """A rotation by ``amount`` degrees about ``axis``, as MaterialX's reference
        implementation rotates (``mx_rotate_vector3.glsl``: clockwise, looking down the axis;
        Blender's exporter writes Cycles' rotations for it with the axis negated): the Vector
        Rotate node about that axis, inverted, any of its inputs computed."""
        v = self.input(s, "in", [0.0, 0.0, 0.0])
        amount, axis = self.input(s, "amount", 0.0), self.input(s, "axis", [0.0, 1.0, 0.0])
        if not is_link(amount) and _scalar(amount) == 0.0:
            return v
        angle = self.g.math("RADIANS", amount)
        return self.g.out("vector_rotate", "vector",
                          {"vector": v, "axis": axis, "angle": angle},
                          {"rotation_type": "AXIS_ANGLE", "invert": True})

    def _nd_normalize(self, s, out, t):
        return self.g.vmath("NORMALIZE", self.input(s, "in", [0.0, 0.0, 1.0]))

    def _separate(self, s, out):
        axis = {"outr": 0, "outx": 0, "outg": 1, "outy": 1, "outb": 2, "outz": 2}.get(out)
        if out in ("outa", "outw"):
            src = self.source(s, "in")
            a = self.image_alpha(src[0]) if src is not None else None
            if a is not None:
                return a
            if src is None:
                v = self.authored(s, "in")
                return float(v[3]) if v is not None and len(v) > 3 else 1.0
            raise Untranslatable(f"`{out}` of a computed colour4/vector4")
        if axis is None:
            raise Untranslatable(f"unknown output `{out}`")
        return self.g.separate(self.input(s, "in", [0.0] * 3), axis)

    def _nd_separate2(self, s, out, t):
        return self._separate(s, out)

    _nd_separate3 = _nd_separate4 = _nd_separate2

    def _nd_combine2(self, s, out, t):
        return self.g.combine(self.input(s, "in1", 0.0), self.input(s, "in2", 0.0))

    def _nd_combine3(self, s, out, t):
        return self.g.combine(self.input(s, "in1", 0.0), self.input(s, "in2", 0.0),
                              self.input(s, "in3", 0.0))

    def _nd_normalmap(self, s, out, t):
        space = str(self.authored(s, "space") or "tangent")
        if space not in ("tangent", "object"):
            raise Untranslatable(f"space `{space}`")
        src = self.source(s, "in")
        if src is not None and self.output(src[0], src[1]) is None:
            return None  # its input is warned: the surface's own normal
        strength = self.input(s, "scale", 1.0)
        if is_link(strength) or _scalar(strength) != 1.0:
            self.diag.warn(s.GetPrim(), "normalmap scale read as the normal map's strength "
                                        "(exact only at 1)")
        if isinstance(strength, list):
            strength = strength[0]
        if self.connected(s, "normal") or self.connected(s, "tangent"):
            self.diag.warn(s.GetPrim(), "normalmap's normal and tangent inputs are ignored: "
                                        "the surface's are used")
        return self.g.out("normal_map", "normal",
                          {"color": self.input(s, "in", [0.5, 0.5, 1.0]), "strength": strength},
                          {"space": space.upper()})

    def _nd_normal(self, s, out, t):
        if str(self.authored(s, "space") or "object") != "world":
            raise Untranslatable("a normal in object space")
        return self.g.out("geometry", "normal")

    def _nd_texcoord(self, s, out, t):
        if int(self.authored(s, "index") or 0) != 0:
            self.diag.warn(s.GetPrim(), "texcoord index other than 0 read as the mesh's UV set")
        return self.g.uv()

    def _nd_geompropvalue(self, s, out, t):
        name = str(self.authored(s, "geomprop") or "")
        if not t.startswith("vector2"):
            if t.startswith(("integer", "boolean", "string", "filename")):
                raise Untranslatable(f"geomprop of type `{t}`")
            self.table.attribute_names.add(name)
            return self.g.attribute(name, "fac" if t.startswith("float") else "color")
        if name in UV_SET_NAMES:
            return self.g.uv()
        self.table.attribute_names.add(name)
        return self.g.attribute(name, "vector")

    # closures

    def closure(self, shader, name):
        """A closure input: its node's closure, or None (nothing)."""
        src = self.source(shader, name)
        if src is None:
            return None
        return self.output(src[0], src[1])

    def _grey(self):
        return self.g.out("diffuse", "bsdf", {"color": list(GREY)})

    def _nd_mix_bsdf(self, s, out, t):
        bg, fg = self.closure(s, "bg"), self.closure(s, "fg")
        if bg is None and fg is None:
            return None
        return self.g.out("mix_shader", "shader",
                          {"fac": self.input(s, "mix", 0.0), "shader1": bg, "shader2": fg})

    _nd_mix_edf = _nd_mix_bsdf

    def _nd_add_bsdf(self, s, out, t):
        a, b = self.closure(s, "in1"), self.closure(s, "in2")
        if a is None or b is None:
            return b if a is None else a
        return self.g.out("add_shader", "shader", {"shader1": a, "shader2": b})

    _nd_add_edf = _nd_add_bsdf

    def _normal_in(self, s, name):
        return self.input(s, name, None) if self.connected(s, name) else None

    def _roughness(self, s):
        v = self.input(s, "roughness", 0.0)
        if is_link(v):
            return self.g.separate(v, 0)
        if isinstance(v, list):
            if abs(v[0] - v[1]) > 1e-6:
                self.diag.warn(s.GetPrim(), f"anisotropic roughness ({v[0]:g}, {v[1]:g}) read "
                                            f"as its mean")
            return 0.5 * (v[0] + v[1])
        return v

    def _nd_oren_nayar_diffuse_bsdf(self, s, out, t):
        color = self.g.scale(self.input(s, "color", list(GREY)), self.input(s, "weight", 1.0))
        return self.g.out("diffuse", "bsdf", {"color": color, "roughness": self._roughness(s),
                                              "normal": self._normal_in(s, "normal")})

    _nd_burley_diffuse_bsdf = _nd_oren_nayar_diffuse_bsdf

    def _nd_translucent_bsdf(self, s, out, t):
        color = self.g.scale(self.input(s, "color", [1.0] * 3), self.input(s, "weight", 1.0))
        return self.g.out("translucent", "bsdf", {"color": color,
                                                  "normal": self._normal_in(s, "normal")})

    def _nd_dielectric_bsdf(self, s, out, t):
        mode = str(self.authored(s, "scatter_mode") or "R")
        if mode == "T":
            # Transmission alone: Blender writes its Refraction BSDF so.
            color = self.g.scale(self.input(s, "tint", [1.0] * 3), self.input(s, "weight", 1.0))
            return self.g.out("refraction", "bsdf", {
                "color": color, "roughness": self._roughness(s),
                "ior": self.input(s, "ior", 1.5), "normal": self._normal_in(s, "normal")})
        if mode != "RT":
            self.diag.warn(s.GetPrim(), f"scatter_mode `{mode}` is read as RT (reflection and "
                                        f"transmission)")
        color = self.g.scale(self.input(s, "tint", [1.0] * 3), self.input(s, "weight", 1.0))
        return self.g.out("glass", "bsdf", {"color": color, "roughness": self._roughness(s),
                                            "ior": self.input(s, "ior", 1.5),
                                            "normal": self._normal_in(s, "normal")})

    def _nd_conductor_bsdf(self, s, out, t):
        from .mtlx_bsdf import _conductor_f0

        for name in ("ior", "extinction"):
            src = self.source(s, name)
            if src is not None and shader_id(src[0]) != "ND_artistic_ior":
                raise Untranslatable(f"a computed `{name}`")
        color = self.g.scale(_conductor_f0(self.table, s), self.input(s, "weight", 1.0))
        return self.g.out("glossy", "bsdf", {"color": color, "roughness": self._roughness(s),
                                             "normal": self._normal_in(s, "normal")})

    def _nd_uniform_edf(self, s, out, t):
        color = self.input(s, "color", [1.0] * 3)
        if not is_link(color) and not any(c > 0 for c in _vec(color)):
            return None  # black: no emission
        return self.g.out("emission", "emission", {"color": color, "strength": 1.0})

    # Blender's Principled BSDF, as its exporter writes it where a BSDF is expected (in a Mix
    # or Add Shader): ND_layer_bsdf(top: coat dielectric_bsdf, base: ND_multiply_bsdfC(
    #   in1: layer(top: thin film, base: mix_bsdf(mix: Metallic,
    #     bg: layer(top: specular dielectric_bsdf (weight: Specular IOR Level, ior: IOR),
    #       base: mix_bsdf(mix: Transmission Weight, fg: transmission dielectric_bsdf (tint:
    #         Base Color), bg: layer(top: sheen_bsdf, base: mix_bsdf(mix: Subsurface Weight,
    #           bg: oren_nayar_diffuse_bsdf, fg: subsurface_bsdf)))),
    #     fg: conductor_bsdf)),
    #   in2: the coat's attenuation, mix(1, Coat Tint, Coat Weight)))

    def _node(self, s, name, *ids):
        """The node connected to input ``name`` when its id starts with one of ``ids``."""
        src = self.source(s, name)
        if src is None or not shader_id(src[0]).startswith(ids):
            return None
        return src[0]

    def _blender_principled(self, layer):
        """The pbrlib nodes of a Blender Principled BSDF whose top layer is ``layer``, by
        role; None when the network has another structure."""
        n = {"coat": self._node(layer, "top", "ND_dielectric_bsdf")}
        base = self._node(layer, "base", "ND_multiply_bsdf", "ND_layer_bsdf")
        if base is not None and shader_id(base).startswith("ND_multiply_bsdf"):
            base = self._node(base, "in1", "ND_layer_bsdf")
        n["thin_film"] = base
        steps = [("thin_film", "base", "metal_mix", "ND_mix_bsdf"),
                 ("metal_mix", "fg", "metal", "ND_conductor_bsdf"),
                 ("metal_mix", "bg", "specular_layer", "ND_layer_bsdf"),
                 ("specular_layer", "top", "specular", "ND_dielectric_bsdf"),
                 ("specular_layer", "base", "transmission_mix", "ND_mix_bsdf"),
                 ("transmission_mix", "fg", "transmission", "ND_dielectric_bsdf"),
                 ("transmission_mix", "bg", "sheen_layer", "ND_layer_bsdf"),
                 ("sheen_layer", "top", "sheen", "ND_sheen_bsdf"),
                 ("sheen_layer", "base", "subsurface_mix", "ND_mix_bsdf"),
                 ("subsurface_mix", "bg", "diffuse", "ND_oren_nayar_diffuse_bsdf")]
        for parent, name, role, sid in steps:
            node = n.get(parent)
            n[role] = self._node(node, name, sid) if node is not None else None
        return n if all(v is not None for v in n.values()) else None

    def _blender_roughness(self, bsdf):
        """A Principled lobe's roughness: the ``roughness`` of the ND_roughness_anisotropy
        feeding it (Blender's Roughness), else the lobe's own."""
        ra = self._node(bsdf, "roughness", "ND_roughness_anisotropy")
        if ra is None:
            return self._roughness(bsdf)
        aniso = self.input(ra, "anisotropy", 0.0)
        if is_link(aniso) or _scalar(aniso) != 0.0:
            self.diag.warn(ra.GetPrim(), "anisotropy is not supported; isotropic roughness")
        return self.input(ra, "roughness", 0.5)

    def _nd_layer_bsdf(self, s, out, t):
        n = self._blender_principled(s)
        if n is None:
            raise Untranslatable("a layering other than Blender's Principled BSDF (the "
                                 "renderer layers BSDFs only as the Principled BSDF does)")
        prim = s.GetPrim()
        spec, diffuse, coat, sheen = n["specular"], n["diffuse"], n["coat"], n["sheen"]
        tint = self.input(spec, "tint", [1.0] * 3)
        if is_link(tint) or any(abs(c - 1.0) > 1e-6 for c in _vec(tint)):
            self.diag.warn(spec.GetPrim(), "Specular Tint is not supported; white")
        dr = self.input(diffuse, "roughness", 0.0)
        if is_link(dr) or _scalar(dr) != 0.0:
            self.diag.warn(diffuse.GetPrim(), "Diffuse Roughness is not supported; Lambert")
        if self.connected(n["thin_film"], "top"):
            self.diag.warn(n["thin_film"].GetPrim(), "thin film is not supported; ignored")
        sub = self.input(n["subsurface_mix"], "mix", 0.0)
        if is_link(sub) or _scalar(sub) > 0:
            self.diag.warn(prim, "subsurface scattering in a node graph is read as its "
                                 "weight only (radius and colour ignored)")
        sheen_w = self.input(sheen, "weight", 0.0)
        if is_link(sheen_w) or _scalar(sheen_w) > 0:
            for name, d in (("color", [1.0] * 3), ("roughness", 0.5)):
                v = self.input(sheen, name, d)
                if is_link(v) or _vec(v) != _vec(d):
                    self.diag.warn(sheen.GetPrim(), f"sheen `{name}` is not supported; ignored")
        return self.g.out("principled", "bsdf", {
            "base_color": self.input(n["transmission"], "tint", [0.8] * 3),
            "metallic": self.input(n["metal_mix"], "mix", 0.0),
            "roughness": self._blender_roughness(spec),
            "ior": self.input(spec, "ior", 1.5),
            "specular_ior_level": self.input(spec, "weight", 0.5),
            "transmission_weight": self.input(n["transmission_mix"], "mix", 0.0),
            "subsurface_weight": sub,
            "sheen_weight": sheen_w,
            "coat_weight": self.input(coat, "weight", 0.0),
            "coat_roughness": self._blender_roughness(coat),
            "coat_ior": self.input(coat, "ior", 1.5),
            "coat_tint": self.input(coat, "tint", [1.0] * 3),
            "normal": self._normal_in(spec, "normal"),
            "coat_normal": self._normal_in(coat, "normal"),
        }, name=prim.GetName())

    def _nd_surface(self, s, out, t):
        bsdf = self.closure(s, "bsdf")
        edf = self.closure(s, "edf")
        shader = bsdf if edf is None else (edf if bsdf is None else self.g.out(
            "add_shader", "shader", {"shader1": bsdf, "shader2": edf}))
        if shader is None:
            shader = self.g.out("diffuse", "bsdf", {"color": [0.0, 0.0, 0.0]})
        opacity = self.input(s, "opacity", 1.0)
        if is_link(opacity) or _scalar(opacity) < 1.0:
            shader = self.g.out("mix_shader", "shader",
                                {"fac": opacity, "shader2": shader,
                                 "shader1": self.g.out("transparent", "bsdf",
                                                       {"color": [1.0, 1.0, 1.0]})})
        return shader

    # surface shaders -> principled

    def preview(self, s):
        from .materials import _PREVIEW_DEFAULTS as d

        prim = s.GetPrim()
        if int(self.constant(s, "useSpecularWorkflow", 0.0)):
            self.diag.warn(prim, "useSpecularWorkflow: approximated by the metallic workflow "
                                 "(specularColor ignored)")
        if _scalar(self.constant(s, "clearcoat", 0.0)) > 0:
            self.diag.warn(prim, "`clearcoat` is not supported; ignored")
        if self.connected(s, "occlusion"):
            self.diag.warn(prim, "`occlusion` input is not supported; ignored")
        if self.connected(s, "displacement"):
            # Along the normal, as Blender's importer reads it (a Displacement node of scale 1
            # in object space); the surface is not moved: it bumps the shading normal.
            self.displacement = self.g.out("displacement", "displacement", {
                "height": self.input(s, "displacement", 0.0), "scale": 1.0})
        opacity = self.input(s, "opacity", d["opacity"])
        threshold = _scalar(self.constant(s, "opacityThreshold", 0.0))
        if threshold > 0:  # a cut-out: opaque where opacity >= threshold
            try:
                alpha = self.g.math("SUBTRACT", 1.0, self.g.math("LESS_THAN", opacity, threshold))
            except Untranslatable as e:
                self.diag.warn(prim, f"opacityThreshold cannot be applied ({e}): opacity read "
                                     f"as partial coverage")
                alpha = opacity
        else:
            alpha = opacity
        emission = self.input(s, "emissiveColor", list(d["emissiveColor"]))
        normal = None
        if self.connected(s, "normal"):
            n = self.input(s, "normal", None)
            if is_link(n):  # a tangent-space normal in [-1, 1] -> normal_map's colour
                color = self.g.mapping(n, [0.5] * 3, [0.0] * 3, [0.5] * 3)
                normal = self.g.out("normal_map", "normal", {"color": color, "strength": 1.0},
                                    {"space": "TANGENT"})
        return self.g.out("principled", "bsdf", {
            "base_color": self.input(s, "diffuseColor", list(d["diffuseColor"])),
            "metallic": self.input(s, "metallic", d["metallic"]),
            "roughness": self.input(s, "roughness", d["roughness"]),
            "ior": self.input(s, "ior", d["ior"]),
            "alpha": alpha,
            "emission_color": emission,
            "emission_strength": 1.0 if is_link(emission) or any(c > 0 for c in _vec(emission)) else 0.0,
            "normal": normal,
        }, name=prim.GetName())

    def pbr(self, s):
        prim = s.GetPrim()
        openpbr = shader_id(s) == OPENPBR
        from .materials import _OPENPBR_DEFAULTS, _STANDARD_DEFAULTS

        d = _OPENPBR_DEFAULTS if openpbr else _STANDARD_DEFAULTS
        if openpbr:
            names = dict(bc="base_color", bw="base_weight", met="base_metalness",
                         rough="specular_roughness", ior="specular_ior", spec="specular_weight",
                         trans="transmission_weight", ec="emission_color",
                         el="emission_luminance", cw="coat_weight", cr="coat_roughness",
                         ci="coat_ior", cc="coat_color", op="geometry_opacity",
                         n="geometry_normal", cn="geometry_coat_normal",
                         sub="subsurface_weight")
            unsupported = ("fuzz_weight", "thin_film_weight")
        else:
            names = dict(bc="base_color", bw="base", met="metalness",
                         rough="specular_roughness", ior="specular_IOR", spec="specular",
                         trans="transmission", ec="emission_color", el="emission",
                         cw="coat", cr="coat_roughness", ci="coat_IOR", cc="coat_color",
                         op="opacity", n="normal", cn="coat_normal", sub="subsurface")
            unsupported = ("sheen", "thin_film_thickness")
        for name in unsupported:
            if _scalar(self.constant(s, name, 0.0)) > 0 or self.connected(s, name):
                self.diag.warn(prim, f"`{name}` is not supported; ignored")

        def v(key, default):
            name = names[key]
            dv = const(d.get(name))
            x = self.input(s, name, default if dv is None else dv)
            if key in ("bc", "cc", "ec") or is_link(x):
                return x
            return _scalar(x)  # a float socket (standard_surface's opacity is a colour)

        sub = v("sub", 0.0)
        if is_link(sub) or _scalar(sub) > 0:
            self.diag.warn(prim, "subsurface scattering in a node graph is read as its "
                                 "weight only (radius and colour ignored)")
        spec = v("spec", 1.0)
        return self.g.out("principled", "bsdf", {
            "base_color": self.g.scale(v("bc", [0.8] * 3), v("bw", 1.0)),
            "metallic": v("met", 0.0),
            "roughness": v("rough", 0.3),
            "ior": v("ior", 1.5),
            "specular_ior_level": self.g.math("MULTIPLY", spec, 0.5),
            "transmission_weight": v("trans", 0.0),
            "coat_weight": v("cw", 0.0),
            "coat_roughness": v("cr", 0.0),
            "coat_ior": v("ci", 1.5),
            "coat_tint": v("cc", [1.0] * 3),
            "emission_color": v("ec", [1.0] * 3),
            "emission_strength": v("el", 0.0),
            "alpha": v("op", 1.0),
            "subsurface_weight": sub,
            "normal": self._normal_in(s, names["n"]),
            "coat_normal": self._normal_in(s, names["cn"]),
        }, name=prim.GetName())


def emits(material: dict) -> bool:
    """Whether a graph material may emit light."""
    for n in material.get("nodes", ()):
        if n["type"] == "emission":
            return True
        if n["type"] == "principled":
            st = n.get("inputs", {}).get("emission_strength", 0.0)
            if is_link(st) or _scalar(st) > 0:
                return True
    return False


def translate(table, material, surface) -> dict:
    """The IR graph material of ``material`` whose surface shader is ``surface``."""
    name = str(material.GetPath())
    t = Translator(table, name)
    try:
        closure = t.output(surface, "surface")
    except Untranslatable:
        closure = None
    if closure is None or not is_link(closure):
        table.diag.warn(surface.GetPrim(), f"surface `{shader_id(surface)}` cannot be "
                                           f"translated; grey diffuse used")
        return {"type": "diffuse", "name": name, "color": list(GREY)}
    m = t.g.material(closure)
    if is_link(t.displacement):
        m["displacement"] = t.displacement
    return m
