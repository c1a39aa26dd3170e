"""UsdShade materials -> IR materials: flat `principled` ones where they say it all, shading
graphs (shading_graph.py) where they do not.

Read-only: bindings are computed with ``UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()``
(never ``Apply``). When a material carries both, the MaterialX network (OpenPBR,
standard_surface, ND_surface or ND_UsdPreviewSurface, on ``outputs:mtlx:surface``) is preferred
over UsdPreviewSurface: Blender's exporter writes glass only there.

| UsdPreviewSurface | OpenPBR (`ND_open_pbr_surface_surfaceshader`) | standard_surface | IR `principled` |
|---|---|---|---|
| diffuseColor | base_color x base_weight | base_color x base | base_color |
| metallic | base_metalness | metalness | metallic |
| roughness | specular_roughness | specular_roughness | roughness |
| ior | specular_ior | specular_IOR | ior |
| (1) | specular_weight | specular | specular (graph: specular_ior_level = weight / 2) |
| — | transmission_weight | transmission | transmission |
| opacity (coverage; opacityThreshold > 0: a cut-out, opacity >= threshold) | geometry_opacity | opacity | graph: alpha (coverage, not transmission) |
| normal (tangent space, e.g. a UsdUVTexture with scale 2, bias -1) | geometry_normal | normal | graph: normal (`normal_map`, TANGENT) |
| — | coat_weight, coat_roughness, coat_ior, coat_color, geometry_coat_normal | (coat warned) | coat_weight, coat_roughness, coat_ior, coat_tint, graph: coat_normal |
| emissiveColor, strength 1 | emission_color, emission_luminance | emission_color, emission | emission_color, emission_strength |
| — | subsurface_weight | subsurface | subsurface.weight |
| — | subsurface_color | subsurface_color | subsurface.color |
| — | subsurface_radius x subsurface_radius_scale | subsurface_radius x subsurface_scale | subsurface.radius (stage units) |
| — | subsurface_scatter_anisotropy | subsurface_anisotropy | subsurface.anisotropy |

A flat material is written when every input read is a constant or an image read at the mesh's
UV (UsdUVTexture with its scale and bias baked into the texture, ``ND_image_*``), with opacity
1 and no normal input; otherwise the surface is translated into a shading graph
(shading_graph.py, whose table lists the USD and MaterialX nodes read: UsdUVTexture,
UsdPrimvarReader_float2 (``st``, or another UV set read per vertex), UsdTransform2d, the MaterialX standard library Blender writes, mixed
and added BSDFs, the layered BSDFs Blender writes for a Principled BSDF in a Mix Shader), and in
a graph subsurface scattering is read as its weight only (warned).

A connected ``displacement`` bumps the shading normal (the surface is not moved).

Warned: useSpecularWorkflow = 1 (approximated, specularColor ignored), clearcoat,
occlusion, fuzz/sheen and thin-film; int and string UsdPrimvarReaders (their
fallback); wrapT differing from wrapS; missing texture files (the
UsdUVTexture's fallback, else magenta); every node that cannot be translated (named by prim
path and ``info:id``; its consumer keeps its input's value). UsdPreviewSurface has no
subsurface.

A MaterialX ``ND_surface`` over one pbrlib BSDF or EDF (Blender's Diffuse, Glossy, Glass and
Emission nodes) with constant or image inputs is read by mtlx_bsdf.py; mixed or added BSDFs,
a BSDF beside an EDF, opacity and computed inputs make a graph.
"""

from __future__ import annotations

from pxr import Sdf, UsdShade

from . import mtlx_bsdf, shading_graph
from .textures import MAGENTA, resolve_asset

OPENPBR = "ND_open_pbr_surface_surfaceshader"
STANDARD = "ND_standard_surface_surfaceshader"
PREVIEW = "UsdPreviewSurface"
MTLX_PREVIEW = "ND_UsdPreviewSurface_surfaceshader"
#: MaterialX's surface from one pbrlib BSDF or EDF (mtlx_bsdf.py).
SURFACE = "ND_surface"

_PREVIEW_DEFAULTS = {"diffuseColor": (0.18, 0.18, 0.18), "metallic": 0.0, "roughness": 0.5,
                     "ior": 1.5, "opacity": 1.0, "emissiveColor": (0, 0, 0),
                     "useSpecularWorkflow": 0, "clearcoat": 0.0}
_OPENPBR_DEFAULTS = {"base_color": (0.8, 0.8, 0.8), "base_weight": 1.0, "base_metalness": 0.0,
                     "specular_roughness": 0.3, "specular_ior": 1.5, "specular_weight": 1.0,
                     "transmission_weight": 0.0, "emission_color": (1, 1, 1),
                     "emission_luminance": 0.0, "coat_weight": 0.0, "coat_roughness": 0.0,
                     "coat_ior": 1.6, "coat_color": (1, 1, 1),
                     "subsurface_weight": 0.0, "subsurface_color": (0.8, 0.8, 0.8),
                     "subsurface_radius": 1.0, "subsurface_radius_scale": (1.0, 0.5, 0.25),
                     "subsurface_scatter_anisotropy": 0.0,
                     "fuzz_weight": 0.0, "thin_film_weight": 0.0}
_STANDARD_DEFAULTS = {"base_color": (1, 1, 1), "base": 0.8, "metalness": 0.0,
                      "specular_roughness": 0.2, "specular_IOR": 1.5, "specular": 1.0,
                      "transmission": 0.0, "emission_color": (1, 1, 1), "emission": 0.0,
                      "coat": 0.0, "subsurface": 0.0, "subsurface_color": (1, 1, 1),
                      "subsurface_radius": (1, 1, 1), "subsurface_scale": 1.0,
                      "subsurface_anisotropy": 0.0, "sheen": 0.0, "thin_film_thickness": 0.0}
_MTLX_IMAGE = ("ND_image_", "ND_tiledimage_", "ND_gltf_image_")
_MTLX_WRAP = {"periodic": "repeat", "clamp": "clamp", "mirror": "mirror", "constant": "black"}


def _shader_id(shader) -> str:
    sid = shader.GetIdAttr().Get() if shader else None
    return str(sid or "")


def _surface_shader(material, render_context=""):
    out = material.GetSurfaceOutput(render_context) if render_context else material.GetSurfaceOutput()
    if not out:
        return None
    for src in out.GetConnectedSources()[0]:
        shader = _follow(src.source, src.sourceName, 0)
        if shader:
            return shader
    return None


def _follow(connectable, output_name, depth):
    """The shader at the end of a connection, through NodeGraph outputs."""
    prim = connectable.GetPrim()
    if prim.IsA(UsdShade.Shader):
        return UsdShade.Shader(prim)
    if depth > 8:
        return None
    out = UsdShade.NodeGraph(prim).GetOutput(output_name)
    if out:
        for src in out.GetConnectedSources()[0]:
            s = _follow(src.source, src.sourceName, depth + 1)
            if s:
                return s
    return None


def _through_conversions(shader, output):
    """(shader, output) upstream of MaterialX type conversions (``ND_convert_*``, such as the
    ``ND_convert_color4_color3`` Blender's exporter puts between an image and ``base_color``):
    a conversion passes its ``in`` on unchanged in value."""
    for _ in range(8):
        if not _shader_id(shader).startswith("ND_convert_"):
            break
        inp = shader.GetInput("in")
        if not inp or not inp.HasConnectedSource():
            break
        srcs = inp.GetConnectedSources()[0]
        up = _follow(srcs[0].source, srcs[0].sourceName, 0) if srcs else None
        if up is None:
            break
        shader, output = up, str(srcs[0].sourceName)
    return shader, output


class MaterialTable:
    """The IR `materials` list; one entry per bound UsdShade.Material (by path)."""

    def __init__(self, diag, textures, time) -> None:
        self.diag = diag
        self.textures = textures
        self.time = time
        self.materials: list[dict] = []
        self._index: dict = {}
        #: Names of the primvars some material reads per vertex (the meshes carry them).
        self.attribute_names: set[str] = set()

    def index_of(self, prim) -> int:
        """IR material index of the material bound to ``prim`` (or its displayColor)."""
        material, _ = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial()
        if material:
            key = str(material.GetPath())
            if key not in self._index:
                self.materials.append(self.read(material))
                self._index[key] = len(self.materials) - 1
            return self._index[key]
        from pxr import UsdGeom

        color = (0.18, 0.18, 0.18)
        pv = UsdGeom.PrimvarsAPI(prim).GetPrimvar("displayColor")
        if pv and pv.HasAuthoredValue():
            v = pv.Get(self.time)
            varying = v is not None and pv.GetInterpolation() != "constant" and (
                len(v) > 1 or (pv.IsIndexed() and len(pv.GetIndices(self.time)) > 1))
            if varying:
                # Colour per face or vertex: a diffuse surface reading it per vertex.
                key = ("displayColor", "varying")
                if key not in self._index:
                    self.attribute_names.add("displayColor")
                    self.materials.append({
                        "type": "graph", "name": "displayColor (per vertex)",
                        "nodes": [{"type": "attribute", "params": {"name": "displayColor"}},
                                  {"type": "diffuse",
                                   "inputs": {"color": {"node": 0, "output": "color"}}}],
                        "surface": {"node": 1}})
                    self._index[key] = len(self.materials) - 1
                return self._index[key]
            if v is not None and len(v):
                color = tuple(float(c) for c in v[0])
        key = ("displayColor", color)
        if key not in self._index:
            self.materials.append({"type": "diffuse", "name": f"displayColor{list(color)}",
                                   "color": list(color)})
            self._index[key] = len(self.materials) - 1
        return self._index[key]

    def read(self, material) -> dict:
        mtlx = _surface_shader(material, "mtlx")
        if mtlx is not None and _shader_id(mtlx) in (OPENPBR, STANDARD):
            if self._pbr_needs_graph(mtlx):
                return shading_graph.translate(self, material, mtlx)
            return self._mtlx(material, mtlx)
        if mtlx is not None and _shader_id(mtlx) == SURFACE:
            if self._surface_needs_graph(mtlx):
                return shading_graph.translate(self, material, mtlx)
            return mtlx_bsdf.read_surface(self, material, mtlx)
        if mtlx is not None and _shader_id(mtlx) == MTLX_PREVIEW:
            return self._preview_or_graph(material, mtlx)
        preview = _surface_shader(material)
        if preview is not None and _shader_id(preview) == PREVIEW:
            return self._preview_or_graph(material, preview)
        for s in (mtlx, preview):
            if s is not None:
                self.diag.warn(s.GetPrim(), f"unsupported surface shader `{_shader_id(s)}`; grey diffuse used")
        if mtlx is None and preview is None:
            self.diag.warn(material.GetPrim(), "material has no surface shader; grey diffuse used")
        return {"type": "diffuse", "name": str(material.GetPath()), "color": [0.18, 0.18, 0.18]}

    # -- inputs -------------------------------------------------------------------------

    def _value(self, shader, name, defaults):
        inp = shader.GetInput(name)
        if inp:
            v = inp.Get(self.time)
            if v is not None:
                return v
        return defaults.get(name)

    def _source(self, shader, name):
        """(source shader, output name) when the input is connected."""
        inp = shader.GetInput(name)
        if not inp or not inp.HasConnectedSource():
            return None
        for src in inp.GetConnectedSources()[0]:
            s = _follow(src.source, src.sourceName, 0)
            if s:
                return _through_conversions(s, str(src.sourceName))
        return None

    def color(self, shader, name, defaults, scale=1.0):
        src = self._source(shader, name)
        if src is not None:
            tex = self._texture(src[0], src[1], shader, name)
            if tex == "missing":
                return list(MAGENTA)
            if tex is not None:
                return {"texture": tex[0], "scale": [scale] * 3}
        v = self._value(shader, name, defaults)
        v = [float(c) for c in v] if v is not None else [0.0, 0.0, 0.0]
        return [max(0.0, c * scale) for c in v[:3]]

    def float_(self, shader, name, defaults, lo=0.0, hi=1.0):
        src = self._source(shader, name)
        if src is not None:
            tex = self._texture(src[0], src[1], shader, name)
            if tex not in (None, "missing"):
                return {"texture": tex[0], "channel": tex[1], "scale": 1.0}
        v = self._value(shader, name, defaults)
        return min(hi, max(lo, float(v if v is not None else 0.0)))

    def scalar(self, shader, name, defaults):
        if self._source(shader, name) is not None:
            self.diag.warn(shader.GetPrim(), f"`{name}` is connected to a node graph; its default value is used")
        v = self._value(shader, name, defaults)
        return float(v if v is not None else 0.0)

    def _texture(self, src, output, shader, name):
        """(texture index, channel) for a texture node; "missing" for a missing file; None for
        an unsupported node (warned)."""
        sid = _shader_id(src)
        channel = {"r": 0, "g": 1, "b": 2, "a": 3}.get(output, 0)
        if sid == "UsdUVTexture":
            path = resolve_asset(src.GetInput("file").Get(self.time) if src.GetInput("file") else None, src.GetPrim())
            cs = src.GetInput("sourceColorSpace")
            cs = str(cs.Get(self.time)) if cs and cs.Get(self.time) else "auto"
            wrap = src.GetInput("wrapS")
            wrap = str(wrap.Get(self.time)) if wrap and wrap.Get(self.time) else "useMetadata"
            wrap_t = src.GetInput("wrapT")
            if wrap_t and wrap_t.Get(self.time) and str(wrap_t.Get(self.time)) != wrap:
                self.diag.warn(src.GetPrim(), "wrapT differs from wrapS: wrapS is used for both")
            sc = src.GetInput("scale")
            bi = src.GetInput("bias")
            scale = tuple(sc.Get(self.time)) if sc and sc.Get(self.time) is not None else (1, 1, 1, 1)
            bias = tuple(bi.Get(self.time)) if bi and bi.Get(self.time) is not None else (0, 0, 0, 0)
            st = src.GetInput("st")
            if st and st.HasConnectedSource():
                reader = self._source(src, "st")
                if reader and not _shader_id(reader[0]).startswith("UsdPrimvarReader"):
                    self.diag.warn(reader[0].GetPrim(), f"texture coordinates from `{_shader_id(reader[0])}` unsupported; primvars:st used")
            idx = self.textures.add(src.GetPrim(), path, cs, wrap, scale, bias)
        elif sid.startswith(_MTLX_IMAGE):
            f = src.GetInput("file")
            path = resolve_asset(f.Get(self.time) if f else None, src.GetPrim())
            cs = (f.GetAttr().GetColorSpace() if f else "") or "auto"
            cs = {"srgb_texture": "sRGB", "lin_rec709": "raw", "raw": "raw"}.get(cs, cs)
            ua = src.GetInput("uaddressmode")
            wrap = _MTLX_WRAP.get(str(ua.Get(self.time)) if ua and ua.Get(self.time) else "periodic", "repeat")
            idx = self.textures.add(src.GetPrim(), path, cs, wrap)
            channel = {"outr": 0, "outg": 1, "outb": 2, "outa": 3}.get(output, channel)
        else:
            self.diag.warn(src.GetPrim(), f"node `{sid or src.GetPath()}` feeding `{name}` is unsupported; the input's value is used")
            return None
        if idx is None:
            return "missing"
        return idx, channel

    # -- flat or graph ------------------------------------------------------------------

    def _flat_source_ok(self, shader, name) -> bool:
        """Whether the flat material reads the input exactly: unconnected, or an image read
        at the mesh's UV (its scale and bias baked into the texture)."""
        src = self._source(shader, name)
        if src is None:
            return True
        s, _ = src
        sid = _shader_id(s)
        if sid == "UsdUVTexture":
            st = self._source(s, "st")
            if st is None:
                return True
            var = st[0].GetInput("varname")
            return (_shader_id(st[0]) == "UsdPrimvarReader_float2" and var is not None
                    and str(var.Get(self.time)) == "st")
        if sid.startswith("ND_image_"):
            filt = s.GetInput("filtertype")
            if filt and str(filt.Get(self.time) or "linear") != "linear":
                return False  # read between texels otherwise than bilinearly: a graph
            tc = self._source(s, "texcoord")
            return tc is None or (_shader_id(tc[0]).startswith("ND_texcoord_")
                                  and not tc[0].GetInput("index"))
        return False

    def _below_one(self, shader, name) -> bool:
        """Whether a coverage input is connected or below 1."""
        if self._source(shader, name) is not None:
            return True
        v = self._value(shader, name, {})
        if v is None:
            return False
        try:
            return min(float(c) for c in v) < 1.0
        except TypeError:
            return float(v) < 1.0

    def _preview_or_graph(self, material, s) -> dict:
        graph = (self._below_one(s, "opacity") or self._source(s, "normal") is not None
                 or self._source(s, "displacement") is not None
                 or not all(self._flat_source_ok(s, n) for n in
                            ("diffuseColor", "metallic", "roughness", "emissiveColor", "ior")))
        if graph:
            return shading_graph.translate(self, material, s)
        return self._preview(material, s)

    def _pbr_needs_graph(self, s) -> bool:
        if _shader_id(s) == OPENPBR:
            names = ("base_color", "base_weight", "base_metalness", "specular_roughness",
                     "specular_ior", "specular_weight", "transmission_weight",
                     "emission_color", "emission_luminance", "coat_weight", "coat_roughness",
                     "coat_ior", "coat_color")
            opacity, normals = "geometry_opacity", ("geometry_normal", "geometry_coat_normal")
        else:
            names = ("base_color", "base", "metalness", "specular_roughness", "specular_IOR",
                     "specular", "transmission", "emission_color", "emission")
            opacity, normals = "opacity", ("normal", "coat_normal")
        return (self._below_one(s, opacity)
                or any(self._source(s, n) is not None for n in normals)
                or not all(self._flat_source_ok(s, n) for n in names))

    def _surface_needs_graph(self, s) -> bool:
        """An ND_surface over more than one pbrlib node, or over one whose inputs are
        computed, or with an opacity."""
        bsdf = self._source(s, "bsdf")
        edf = self._source(s, "edf")
        if self._below_one(s, "opacity") or (bsdf is not None and edf is not None):
            return True
        node = (bsdf or edf or (None,))[0]
        if node is None:
            return False
        sid = _shader_id(node)
        if sid not in mtlx_bsdf.FLAT:
            return sid in mtlx_bsdf.GRAPH_ONLY
        if sid == "ND_dielectric_bsdf" and str(self._value(node, "scatter_mode", {}) or "R") == "T":
            return True  # refraction alone: the graph's Refraction BSDF
        inputs = [i.GetBaseName() for i in node.GetInputs()]
        if sid == "ND_conductor_bsdf":  # its ior and extinction: constants or ND_artistic_ior
            inputs = [n for n in inputs if n not in ("ior", "extinction")]
        return not all(self._flat_source_ok(node, n) for n in inputs)

    # -- shaders ------------------------------------------------------------------------

    def _preview(self, material, s) -> dict:
        d = _PREVIEW_DEFAULTS
        prim = s.GetPrim()
        if int(self._value(s, "useSpecularWorkflow", d) or 0):
            self.diag.warn(prim, "useSpecularWorkflow: approximated by the metallic workflow (specularColor ignored)")
        for name in ("clearcoat",):
            if float(self._value(s, name, d) or 0) > 0:
                self.diag.warn(prim, f"`{name}` is not supported; ignored")
        if self._source(s, "occlusion") is not None:
            self.diag.warn(prim, "`occlusion` input is not supported; ignored")
        m = {
            "type": "principled",
            "name": str(material.GetPath()),
            "base_color": self.color(s, "diffuseColor", d),
            "metallic": self.float_(s, "metallic", d),
            "roughness": self.float_(s, "roughness", d),
            "ior": max(1.0, self.scalar(s, "ior", d)),
        }
        em = self.color(s, "emissiveColor", d)
        if isinstance(em, dict) or any(c > 0 for c in em):
            m["emission_color"] = em
            m["emission_strength"] = 1.0
        return m

    def _mtlx(self, material, s) -> dict:
        prim = s.GetPrim()
        if _shader_id(s) == OPENPBR:
            d = _OPENPBR_DEFAULTS
            names = ("base_color", "base_weight", "base_metalness", "specular_roughness",
                     "specular_ior", "specular_weight", "transmission_weight",
                     "emission_color", "emission_luminance")
            unsupported = ("fuzz_weight", "thin_film_weight")
        else:
            d = _STANDARD_DEFAULTS
            names = ("base_color", "base", "metalness", "specular_roughness", "specular_IOR",
                     "specular", "transmission", "emission_color", "emission")
            unsupported = ("coat", "sheen", "thin_film_thickness")
        for name in unsupported:
            if float(self._value(s, name, d) or 0) > 0:
                self.diag.warn(prim, f"`{name}` is not supported; ignored")
        bc, bw, met, rough, ior, spec, trans, ec, el = names
        weight = self.scalar(s, bw, d)
        m = {
            "type": "principled",
            "name": str(material.GetPath()),
            "base_color": self.color(s, bc, d, scale=weight),
            "metallic": self.float_(s, met, d),
            "roughness": self.float_(s, rough, d),
            "ior": max(1.0, self.scalar(s, ior, d)),
            "specular": max(0.0, self.scalar(s, spec, d)),
            "transmission": min(1.0, max(0.0, self.scalar(s, trans, d))),
        }
        strength = max(0.0, self.scalar(s, el, d))
        if strength > 0:
            m["emission_color"] = self.color(s, ec, d)
            m["emission_strength"] = strength
        if _shader_id(s) == OPENPBR:
            coat = min(1.0, max(0.0, float(self._value(s, "coat_weight", d) or 0.0)))
            if coat > 0:
                tint = self.color(s, "coat_color", d)
                if isinstance(tint, dict):
                    self.diag.warn(prim, "a texture on `coat_color` is not supported; white")
                    tint = [1.0, 1.0, 1.0]
                m.update(coat_weight=coat,
                         coat_roughness=min(1.0, max(0.0, self.scalar(s, "coat_roughness", d))),
                         coat_ior=max(1.0, self.scalar(s, "coat_ior", d)),
                         coat_tint=tint)
        sub = self._subsurface(s, d, m["ior"])
        if sub is not None:
            m["subsurface"] = sub
        return m

    def _subsurface(self, s, d, ior):
        """The IR `subsurface` part of an OpenPBR or standard_surface shader (None without):
        radius = the radius times its per-channel scale, in stage units; the entry's IOR
        is the specular IOR. Radius 0 renders as the diffuse base (warned)."""
        prim = s.GetPrim()
        openpbr = _shader_id(s) == OPENPBR
        names = (("subsurface_weight", "subsurface_color", "subsurface_radius",
                  "subsurface_radius_scale", "subsurface_scatter_anisotropy") if openpbr else
                 ("subsurface", "subsurface_color", "subsurface_radius", "subsurface_scale",
                  "subsurface_anisotropy"))
        w, col, rad, scale, aniso = names
        weight = min(1.0, max(0.0, self.scalar(s, w, d)))
        if not weight > 0:
            return None
        color = self.color(s, col, d)
        if isinstance(color, dict):
            self.diag.warn(prim, f"a texture on `{col}` is not supported by subsurface "
                                 f"scattering; uses white")
            color = [1.0, 1.0, 1.0]

        def rgb(name):
            if self._source(s, name) is not None:
                self.diag.warn(prim, f"`{name}` is connected to a node graph; its default value "
                                     f"is used")
            v = self._value(s, name, d)
            if v is None:
                return [0.0, 0.0, 0.0]
            try:
                return [float(c) for c in v][:3]
            except TypeError:  # a float where a colour is expected
                return [float(v)] * 3

        radius = [a * b for a, b in zip(rgb(rad), rgb(scale))]
        if all(r == 0.0 for r in radius):
            self.diag.warn(prim, f"subsurface radius 0 (`{rad}` x `{scale}`); renders as its "
                                 f"diffuse base")
        elif any(not (r >= 0.0) or r != r for r in radius):
            self.diag.warn(prim, f"subsurface radius {radius} has negative or NaN channels")
        return {"weight": weight, "radius": radius, "color": color, "ior": ior,
                "anisotropy": self.scalar(s, aniso, d)}
