"""Volume shaders -> IR homogeneous media.

Follows a Volume socket (a Material Output's or a World Output's) through Reroutes, Add Shader
and Mix Shader (constant factor) to these nodes, with Cycles' coefficients (its SVM kernel,
``svm_node_principled_volume`` and ``svm_node_closure_volume``; d = max(Density, 0)):

| node | sigma_s | sigma_a | g |
|---|---|---|---|
| Principled Volume | d C | d max(1 - C, 0) max(1 - sqrt(A), 0) | Anisotropy |
| Volume Scatter | d C | 0 | Anisotropy |
| Volume Absorption | 0 | d (1 - C) | - |
| Volume Coefficients | Scatter Coefficients | Absorption Coefficients | Anisotropy |

C is the Color, A the Absorption Color. Add Shader sums the coefficients, Mix Shader blends
them; the phase of a sum is Henyey-Greenstein with the scattering-weighted mean anisotropy
(exact when the parts share one). Cycles clamps |g| to 1 - 1e-3, so does this.

Densities are per Blender unit, as the IR's coefficients (IR lengths are Blender units; Cycles
ignores the scene's unit scale for volumes too). Mesh objects have no voxel grids, so the
Principled Volume's attribute names have nothing to read there, as in Cycles.

Not supported (reported through the returned issues, the constant socket values are used):
textures or attributes driving an input, volume emission and blackbody, phase functions other
than Henyey-Greenstein.
"""

from __future__ import annotations

import math

from .material import _source

G_MAX = 1.0 - 1e-3
VOLUME_NODES = {"ShaderNodeVolumePrincipled", "ShaderNodeVolumeScatter",
                "ShaderNodeVolumeAbsorption", "ShaderNodeVolumeCoefficients"}


class _Coeffs:
    """Coefficients of a (sum of) volume closures: sigma_a, sigma_s and sum(sigma_s * g)."""

    def __init__(self, sigma_a=(0.0, 0.0, 0.0), sigma_s=(0.0, 0.0, 0.0), g=0.0):
        self.sigma_a = [float(x) for x in sigma_a]
        self.sigma_s = [float(x) for x in sigma_s]
        # Scattering-weighted anisotropy, per channel (the weights of a sum's phase).
        self.sg = [s * g for s in self.sigma_s]
        self.gs = {round(g, 6)} if any(self.sigma_s) else set()

    def scaled(self, k: float) -> "_Coeffs":
        c = _Coeffs()
        c.sigma_a = [k * x for x in self.sigma_a]
        c.sigma_s = [k * x for x in self.sigma_s]
        c.sg = [k * x for x in self.sg]
        c.gs = set(self.gs) if k > 0 else set()
        return c

    def __add__(self, o: "_Coeffs") -> "_Coeffs":
        c = _Coeffs()
        c.sigma_a = [a + b for a, b in zip(self.sigma_a, o.sigma_a)]
        c.sigma_s = [a + b for a, b in zip(self.sigma_s, o.sigma_s)]
        c.sg = [a + b for a, b in zip(self.sg, o.sg)]
        c.gs = self.gs | o.gs
        return c

    def g(self) -> float:
        s = sum(self.sigma_s)
        g = sum(self.sg) / s if s > 0 else 0.0
        return max(-G_MAX, min(G_MAX, g))


class VolumeReader:
    """Reads one Volume socket; ``issues`` collects what is approximated (for the caller to
    report with the name of the object or world)."""

    def __init__(self):
        self.issues: list[str] = []

    def _issue(self, msg: str) -> None:
        if msg not in self.issues:
            self.issues.append(msg)

    def _const(self, node, name, default):
        s = node.inputs.get(name)
        if s is None:
            return default
        src, out = _source(s)
        value = s.default_value
        if src is not None:
            if src.bl_idname in {"ShaderNodeValue", "ShaderNodeRGB"}:
                value = out.default_value
            else:
                kind = "an attribute" if "Attribute" in src.bl_idname else "a texture"
                self._issue(f"{kind} ('{src.name}') on {node.name}'s {name} is not supported; "
                            f"uses the constant {_fmt(value)}")
        if hasattr(value, "__len__"):
            return [float(x) for x in value[:3]]
        return float(value)

    def read(self, socket) -> dict | None:
        """The IR medium (without a name) of the shader feeding ``socket``; None when nothing
        usable feeds it."""
        node, _ = _source(socket)
        if node is None:
            return None
        c = self._node(node)
        if c is None:
            return None
        return {"sigma_a": [max(x, 0.0) for x in c.sigma_a],
                "sigma_s": [max(x, 0.0) for x in c.sigma_s], "g": c.g()}

    def _node(self, node) -> _Coeffs | None:
        kind = node.bl_idname
        if kind == "ShaderNodeAddShader":
            parts = [self._node(n) for n, _ in (_source(s) for s in node.inputs) if n is not None]
            parts = [p for p in parts if p is not None]
            if not parts:
                return None
            total = parts[0]
            for p in parts[1:]:
                total = total + p
            return self._check_phase(total)
        if kind == "ShaderNodeMixShader":
            fac = node.inputs.get("Fac") or node.inputs.get("Factor")
            f = min(max(self._const(node, fac.name, 0.5) if fac is not None else 0.5, 0.0), 1.0)
            a, _ = _source(node.inputs[1])
            b, _ = _source(node.inputs[2])
            ca = self._node(a) if a is not None else None
            cb = self._node(b) if b is not None else None
            total = _Coeffs()
            if ca is not None:
                total = total + ca.scaled(1.0 - f)
            if cb is not None:
                total = total + cb.scaled(f)
            return self._check_phase(total) if (ca or cb) else None
        if kind == "ShaderNodeVolumePrincipled":
            return self._principled(node)
        if kind == "ShaderNodeVolumeScatter":
            d = max(self._const(node, "Density", 1.0), 0.0)
            color = self._const(node, "Color", [0.8] * 3)
            g = self._phase_g(node)
            return _Coeffs(sigma_s=[d * c for c in color], g=g)
        if kind == "ShaderNodeVolumeAbsorption":
            d = max(self._const(node, "Density", 1.0), 0.0)
            color = self._const(node, "Color", [0.8] * 3)
            return _Coeffs(sigma_a=[d * (1.0 - c) for c in color])
        if kind == "ShaderNodeVolumeCoefficients":
            sa = self._const(node, "Absorption Coefficients", [1.0] * 3)
            ss = self._const(node, "Scatter Coefficients", [1.0] * 3)
            em = self._const(node, "Emission Coefficients", [0.0] * 3)
            if any(x > 0 for x in em):
                self._issue(f"volume emission ({node.name}) is not supported; ignored")
            return _Coeffs(sigma_a=sa, sigma_s=ss, g=self._phase_g(node))
        self._issue(f"volume shader node '{node.name}' ({kind}) is not supported; no medium")
        return None

    def _check_phase(self, c: _Coeffs) -> _Coeffs:
        if len(c.gs) > 1:
            self._issue(f"volume shaders of different anisotropies {sorted(c.gs)} are combined "
                        f"into one of anisotropy {c.g():.3f}")
        return c

    def _phase_g(self, node) -> float:
        phase = getattr(node, "phase", "HENYEY_GREENSTEIN")
        g = self._const(node, "Anisotropy", 0.0)
        if phase == "DRAINE":
            self._issue(f"{node.name}: the Draine phase function is not supported; uses "
                        f"Henyey-Greenstein of the same anisotropy")
        elif phase != "HENYEY_GREENSTEIN":
            self._issue(f"{node.name}: the {phase.replace('_', '-').title()} phase function is "
                        f"not supported; uses isotropic scattering")
            g = 0.0
        return g

    def _principled(self, node) -> _Coeffs:
        d = max(self._const(node, "Density", 1.0), 0.0)
        color = self._const(node, "Color", [0.5] * 3)
        g = self._const(node, "Anisotropy", 0.0)
        absorption = self._const(node, "Absorption Color", [0.0] * 3)
        for name in ("Density Attribute", "Color Attribute", "Temperature Attribute"):
            s = node.inputs.get(name)
            if s is not None and s.is_linked:
                self._issue(f"a linked {name} on {node.name} is not supported; ignored")
        if self._const(node, "Emission Strength", 0.0) > 0.0:
            self._issue(f"volume emission ({node.name}'s Emission Strength) is not supported; "
                        f"ignored")
        if self._const(node, "Blackbody Intensity", 0.0) > 0.0:
            self._issue(f"blackbody emission ({node.name}'s Blackbody Intensity) is not "
                        f"supported; ignored")
        sigma_s = [d * c for c in color]
        sigma_a = [d * max(1.0 - c, 0.0) * max(1.0 - math.sqrt(max(a, 0.0)), 0.0)
                   for c, a in zip(color, absorption)]
        return _Coeffs(sigma_a=sigma_a, sigma_s=sigma_s, g=g)


def _fmt(v) -> str:
    if hasattr(v, "__len__"):
        return "(" + ", ".join(f"{float(x):.4g}" for x in v[:3]) + ")"
    return f"{float(v):.4g}"


def material_volume_socket(mat):
    """The linked Volume socket of ``mat``'s active output, else None."""
    from .material import _output_node

    if mat is None:
        return None
    tree = mat.node_tree if getattr(mat, "use_nodes", True) else None
    if tree is None:
        return None
    out = _output_node(tree)
    if out is None:
        return None
    vol = out.inputs.get("Volume")
    return vol if vol is not None and vol.is_linked else None


def world_volume_socket(world):
    if world is None:
        return None
    tree = world.node_tree if getattr(world, "use_nodes", True) else None
    if tree is None:
        return None
    outs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld"]
    out = next((n for n in outs if n.is_active_output), outs[0] if outs else None)
    if out is None:
        return None
    vol = out.inputs.get("Volume")
    return vol if vol is not None and vol.is_linked else None


def read_volume(socket) -> tuple[dict | None, list[str]]:
    """(medium or None, issues) of a Volume socket."""
    r = VolumeReader()
    try:
        m = r.read(socket)
    except Exception as e:  # a node of an unexpected version; never fail the render
        return None, [f"the volume could not be read ({e}); no medium"]
    if m is not None and not any(m["sigma_a"]) and not any(m["sigma_s"]):
        return None, r.issues
    return m, r.issues
