"""Materials -> IR materials.

Follows the node tree from the active Material Output's Surface socket:

| node | IR |
|---|---|
| Principled BSDF | `principled`: Base Color, Metallic, Roughness, IOR, Transmission Weight, Specular IOR Level (x 2 = `specular`), Emission Color and Strength, Coat (Weight, Roughness, IOR, Tint), Subsurface (Weight, Radius x Scale, IOR with Random Walk (Skin), Anisotropy; Christensen-Burley as Random Walk, warned); Multiscatter GGX or GGX (`multiscatter`) |
| Diffuse BSDF | `diffuse` (roughness ignored) |
| Glossy / Anisotropic BSDF | `glossy`: Color as a tint (no Fresnel, as Cycles), Roughness, Multiscatter GGX or GGX (anisotropy ignored) |
| Glass BSDF | `dielectric`; Multiscatter GGX or GGX (`multiscatter`) |
| Transparent BSDF | `dielectric` of IOR 1 (a pass-through; shadows of it are not exact) |
| Emission | `emission` |

Image Texture nodes (through Reroutes) on colour inputs, and on Metallic/Roughness of the
Principled BSDF, become IR textures on the mesh UVs. Any other node tree becomes a shading
graph (node_graph.py). A material with a Volume shader and no Surface shader
becomes `null` (an invisible boundary: Cycles' pass-through surface); its volume becomes an IR
medium (volume.py).
"""

from __future__ import annotations

GREY = {"type": "diffuse", "color": [0.8, 0.8, 0.8]}


def _output_node(tree):
    outs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"]
    for n in outs:
        if n.is_active_output and n.target in {"ALL", "CYCLES"}:
            return n
    for n in outs:
        if n.target in {"ALL", "CYCLES"}:
            return n
    return outs[0] if outs else None


def _source(socket):
    """The node (and its output socket) feeding ``socket``, through reroutes; None if unlinked."""
    while socket.is_linked:
        link = socket.links[0]
        if not link.is_valid or link.is_muted:
            return None, None
        node = link.from_node
        if node.bl_idname == "NodeReroute":
            socket = node.inputs[0]
            continue
        return node, link.from_socket
    return None, None


# Shaders the plain IR materials render, and the inputs of theirs that may take an Image
# Texture (other inputs take constants, RGB or Value nodes).
_PLAIN = {
    "ShaderNodeBsdfPrincipled": {"Base Color", "Metallic", "Roughness", "Emission Color"},
    "ShaderNodeBsdfDiffuse": {"Color"},
    "ShaderNodeBsdfGlossy": set(),
    "ShaderNodeBsdfAnisotropic": set(),
    "ShaderNodeBsdfGlass": set(),
    "ShaderNodeBsdfTransparent": set(),
    "ShaderNodeEmission": {"Color"},
}


def _image_at_uv(node) -> bool:
    """Whether an Image Texture node reads the mesh's UV as it is (what a plain material's
    texture does): its Vector unlinked, a flat projection and linear interpolation."""
    return (not node.inputs["Vector"].is_linked and node.projection == "FLAT"
            and node.interpolation == "Linear")


def _subsurface_on(principled) -> bool:
    """Whether a Principled BSDF's Subsurface Weight is linked or above zero."""
    s = principled.inputs.get("Subsurface Weight")
    return s is not None and (s.is_linked or float(s.default_value) > 0.0)


def _needs_graph(mat) -> bool:
    """Whether ``mat``'s surface needs a shading graph: a shader the plain materials do not
    have, an input fed by a node other than an Image Texture read at the UV (where they take
    one), RGB or Value, a Principled Alpha below 1, or a linked Displacement."""
    tree = mat.node_tree if getattr(mat, "use_nodes", True) else None
    out = _output_node(tree) if tree is not None else None
    if out is None:
        return False
    surf, _ = _source(out.inputs["Surface"])
    if surf is None:
        return False
    disp = out.inputs.get("Displacement")
    if disp is not None and disp.is_linked:
        return True
    images = _PLAIN.get(surf.bl_idname)
    if images is None:
        return True
    for s in surf.inputs:
        src, _ = _source(s)
        if src is None or src.bl_idname in {"ShaderNodeRGB", "ShaderNodeValue"}:
            continue
        if src.bl_idname == "ShaderNodeTexImage" and s.name in images and _image_at_uv(src):
            continue
        if s.name in {"Subsurface Radius", "Subsurface IOR"}:
            continue  # warned by the plain export, which keeps the subsurface walk
        if s.name == "Coat Normal" and _subsurface_on(surf):
            continue  # the same: a graph has no subsurface walk
        return True
    a = surf.inputs.get("Alpha") if surf.bl_idname == "ShaderNodeBsdfPrincipled" else None
    return a is not None and float(a.default_value) < 1.0


class MaterialExporter:
    def __init__(self, images, warn, stats=None):
        self.images = images
        self.warn = warn
        self.stats = stats if stats is not None else {}

    def export(self, mat) -> dict:
        """One IR material for the Blender material ``mat`` (None: Blender's default grey).

        A material the plain IR materials render exactly is written as one; any other node
        tree becomes a shading graph (node_graph.py)."""
        if mat is None or not _needs_graph(mat):
            return self._export_plain(mat)
        from importlib import import_module
        try:
            translate = import_module(".node_graph", __package__).translate
        except (ImportError, TypeError):  # loaded as a lone module (tests)
            import importlib.util
            import pathlib
            spec = importlib.util.spec_from_file_location(
                "photonmap_node_graph", pathlib.Path(__file__).with_name("node_graph.py"))
            mod = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(mod)
            translate = mod.translate
        g = translate(mat, _output_node(mat.node_tree), self.images, self.warn, self.stats)
        if g is None:
            self.warn(f"material '{mat.name}': the Surface reaches no shader; renders grey diffuse")
            return dict(GREY, name=mat.name)
        return g

    @staticmethod
    def _volume_only(mat) -> bool:
        tree = mat.node_tree if getattr(mat, "use_nodes", True) else None
        out = _output_node(tree) if tree is not None else None
        return out is None or not out.inputs["Surface"].is_linked

    def _input(self, node, name):
        s = node.inputs.get(name)
        if s is None:
            return None
        return s

    def _color(self, node, name, mat_name, default=(0.8, 0.8, 0.8)):
        s = self._input(node, name)
        if s is None:
            return list(default)
        src, out = _source(s)
        if src is None:
            return [float(c) for c in s.default_value[:3]]
        if src.bl_idname == "ShaderNodeTexImage":
            t = self.images.texture(src.image, src.extension, f" (material '{mat_name}')")
            if t is not None:
                if out is not None and out.name == "Alpha":
                    self.warn(f"material '{mat_name}': {name} from an image's alpha; uses its colour")
                return {"texture": t}
        elif src.bl_idname == "ShaderNodeRGB":
            return [float(c) for c in out.default_value[:3]]
        self.warn(f"material '{mat_name}': '{src.name}' ({src.bl_idname}) on {name} is not "
                  f"supported; uses the input's value")
        return [float(c) for c in s.default_value[:3]]

    def _float(self, node, name, mat_name, default=0.0, textures=True):
        s = self._input(node, name)
        if s is None:
            return float(default)
        src, out = _source(s)
        if src is None:
            return float(s.default_value)
        if textures and src.bl_idname == "ShaderNodeTexImage":
            t = self.images.texture(src.image, src.extension, f" (material '{mat_name}')")
            if t is not None:
                return {"texture": t, "channel": 0, "scale": 1.0}
        if src.bl_idname == "ShaderNodeValue":
            return float(out.default_value)
        self.warn(f"material '{mat_name}': '{src.name}' ({src.bl_idname}) on {name} is not "
                  f"supported; uses the input's value")
        return float(s.default_value)

    def _const(self, value, mat_name, name):
        """Inputs the IR takes only as constants: a texture becomes its mean."""
        if isinstance(value, dict):
            self.warn(f"material '{mat_name}': a texture on {name} is not supported by the core; "
                      f"uses 1")
            return 1.0
        return value

    def _export_plain(self, mat) -> dict:
        """The plain IR material for ``mat``, warning about whatever it cannot render."""
        if mat is None:
            return dict(GREY, name="(default)")
        name = mat.name
        tree = mat.node_tree if getattr(mat, "use_nodes", True) else None
        if tree is None:
            return {"type": "diffuse", "name": name, "color": [float(c) for c in mat.diffuse_color[:3]]}
        out = _output_node(tree)
        if out is None:
            self.warn(f"material '{name}': no Material Output; renders grey diffuse")
            return dict(GREY, name=name)
        vol = out.inputs.get("Volume")
        surf, _ = _source(out.inputs["Surface"])
        if surf is None:
            if vol is not None and vol.is_linked:
                # A volume-only material: Cycles' surface is then a pass-through (the volume
                # itself becomes an IR medium, see volume.py).
                return {"type": "null", "name": name}
            return {"type": "diffuse", "name": name, "color": [0.0, 0.0, 0.0]}
        kind = surf.bl_idname
        try:
            if kind == "ShaderNodeBsdfPrincipled":
                return self._principled(surf, name)
            if kind == "ShaderNodeBsdfDiffuse":
                return {"type": "diffuse", "name": name, "color": self._color(surf, "Color", name)}
            if kind in {"ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic"}:
                return {"type": "glossy", "name": name,
                        "color": self._const_color(self._color(surf, "Color", name), name, "Color"),
                        "roughness": self._const(self._float(surf, "Roughness", name, 0.5), name,
                                                 "Roughness"),
                        "multiscatter": self._multiscatter(surf, name)}
            if kind == "ShaderNodeBsdfGlass":
                return {"type": "dielectric", "name": name,
                        "ior": self._const(self._float(surf, "IOR", name, 1.5), name, "IOR"),
                        "roughness": self._const(self._float(surf, "Roughness", name, 0.0), name,
                                                 "Roughness"),
                        "color": self._const_color(self._color(surf, "Color", name, (1, 1, 1)),
                                                   name, "Color"),
                        "multiscatter": self._multiscatter(surf, name)}
            if kind == "ShaderNodeBsdfTransparent":
                return {"type": "dielectric", "name": name, "ior": 1.0, "roughness": 0.0,
                        "color": self._const_color(self._color(surf, "Color", name, (1, 1, 1)),
                                                   name, "Color")}
            if kind == "ShaderNodeEmission":
                return {"type": "emission", "name": name,
                        "color": self._color(surf, "Color", name, (1, 1, 1)),
                        "strength": self._const(self._float(surf, "Strength", name, 1.0), name,
                                                "Strength")}
        except Exception as e:  # a node of an unexpected version; never fail the render
            self.warn(f"material '{name}': {e}; renders grey diffuse")
            return dict(GREY, name=name)
        self.warn(f"material '{name}': shader node '{surf.name}' ({kind}) is not supported; "
                  f"renders grey diffuse")
        return dict(GREY, name=name)

    def _const_color(self, value, mat_name, name):
        if isinstance(value, dict):
            self.warn(f"material '{mat_name}': a texture on {name} is not supported by the core "
                      f"for this shader; uses white")
            return [1.0, 1.0, 1.0]
        return value

    def _multiscatter(self, node, mat_name) -> bool:
        """Whether the node's microfacet distribution is Multiscatter GGX (Blender's default);
        Beckmann and Ashikhmin-Shirley render as GGX (warned)."""
        dist = getattr(node, "distribution", "MULTI_GGX")
        if dist not in {"MULTI_GGX", "GGX"}:
            self.warn(f"material '{mat_name}': the {dist} distribution is not supported; "
                      f"renders as GGX")
        return dist == "MULTI_GGX"

    def _principled(self, n, name) -> dict:
        ior = self._const(self._float(n, "IOR", name, 1.5, textures=False), name, "IOR")
        transmission = self._const(self._float(n, "Transmission Weight", name, 0.0, textures=False),
                                   name, "Transmission Weight")
        level = self._const(self._float(n, "Specular IOR Level", name, 0.5, textures=False), name,
                            "Specular IOR Level")
        d = {
            "type": "principled", "name": name,
            "base_color": self._color(n, "Base Color", name),
            "metallic": self._float(n, "Metallic", name, 0.0),
            "roughness": self._float(n, "Roughness", name, 0.5),
            "ior": float(ior),
            "transmission": float(transmission),
            "specular": 2.0 * float(level),
            "emission_color": self._color(n, "Emission Color", name, (1, 1, 1)),
            "emission_strength": float(self._const(
                self._float(n, "Emission Strength", name, 0.0, textures=False), name,
                "Emission Strength")),
            "multiscatter": self._multiscatter(n, name),
        }
        coat = self._const(self._float(n, "Coat Weight", name, 0.0, textures=False), name,
                           "Coat Weight")
        if float(coat) > 0.0:
            d.update(
                coat_weight=min(1.0, float(coat)),
                coat_roughness=float(self._const(self._float(n, "Coat Roughness", name, 0.03,
                                                             textures=False), name,
                                                 "Coat Roughness")),
                coat_ior=max(1.0, float(self._const(self._float(n, "Coat IOR", name, 1.5,
                                                                textures=False), name,
                                                    "Coat IOR"))),
                coat_tint=self._const_color(self._color(n, "Coat Tint", name, (1, 1, 1)), name,
                                            "Coat Tint"),
            )
            s = n.inputs.get("Coat Normal")
            if s is not None and s.is_linked:
                self.warn(f"material '{name}': Coat Normal is not read beside subsurface "
                          f"scattering (a shading graph has no subsurface walk); the coat "
                          f"uses the surface's normal")
        sub = self._subsurface(n, name, float(ior))
        if sub is not None:
            d["subsurface"] = sub
        s = n.inputs.get("Sheen Weight")
        if s is not None and (s.is_linked or float(s.default_value) > 0.0):
            self.warn(f"material '{name}': Sheen Weight is not supported; ignored")
        s = n.inputs.get("Normal")
        if s is not None and s.is_linked:
            self.warn(f"material '{name}': normal maps are not supported; ignored")
        return d

    def _subsurface(self, n, name, ior):
        """The IR `subsurface` part of a Principled BSDF, as Cycles' random walk reads the
        node: radius = Radius x Scale (Blender units), the colour is the Base Color, the
        entry's IOR the node's IOR (Random Walk) or Subsurface IOR with method `skin`
        (Random Walk (Skin)), Anisotropy as it is. None without subsurface (Weight 0)."""
        weight = self._const(self._float(n, "Subsurface Weight", name, 0.0, textures=False),
                             name, "Subsurface Weight")
        if not float(weight) > 0.0:
            return None
        method = getattr(n, "subsurface_method", "RANDOM_WALK")
        if method == "BURLEY":
            self.warn(f"material '{name}': subsurface method Christensen-Burley renders as "
                      f"Random Walk")
        s = n.inputs.get("Subsurface Radius")
        radius = [1.0, 0.2, 0.1]
        if s is not None:
            if s.is_linked:
                self.warn(f"material '{name}': a node on Subsurface Radius is not supported; "
                          f"uses the input's value")
            radius = [float(c) for c in s.default_value[:3]]
        scale = float(self._const(self._float(n, "Subsurface Scale", name, 0.05, textures=False),
                                  name, "Subsurface Scale"))
        sub = {"weight": min(1.0, float(weight)),
               "radius": [r * scale for r in radius],
               "anisotropy": float(self._const(self._float(n, "Subsurface Anisotropy", name, 0.0,
                                                           textures=False), name,
                                               "Subsurface Anisotropy"))}
        if method == "RANDOM_WALK_SKIN":
            sub["method"] = "skin"
            # Blender's inputs.get() does not find this socket by its name (it is unavailable
            # for the other methods); look it up by name among all inputs.
            sock = next((i for i in n.inputs if i.name == "Subsurface IOR"), None)
            sub["ior"] = 1.4 if sock is None else float(sock.default_value)
            if sock is not None and sock.is_linked:
                self.warn(f"material '{name}': a node on Subsurface IOR is not supported; uses "
                          f"the input's value")
        else:
            sub["ior"] = ior
        if all(r == 0.0 for r in sub["radius"]):
            self.warn(f"material '{name}': subsurface radius 0; renders as its diffuse base")
        return sub
