"""The Principled BSDF's subsurface sockets as the exporter reads them (the exporter module
alone, without installing the extension): Radius x Scale, the IOR per method, Anisotropy,
Christensen-Burley as Random Walk with a warning, none without Subsurface Weight."""
import importlib.util
from pathlib import Path

import bpy
import pytest

_PATH = Path(__file__).resolve().parents[2] / "blender_addon" / "export" / "material.py"


def _exporter(warn):
    spec = importlib.util.spec_from_file_location("photonmap_material_export", _PATH)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.MaterialExporter(None, warn)


def _wax():
    mat = bpy.data.materials.new("Wax")
    mat.use_nodes = True
    n = mat.node_tree.nodes["Principled BSDF"]
    n.inputs["Subsurface Weight"].default_value = 1.0
    n.inputs["Subsurface Radius"].default_value = (1.0, 0.5, 0.25)
    n.inputs["Subsurface Scale"].default_value = 0.1
    n.inputs["Subsurface Anisotropy"].default_value = 0.2
    next(i for i in n.inputs if i.name == "Subsurface IOR").default_value = 1.35
    n.inputs["IOR"].default_value = 1.45
    return mat, n


@pytest.mark.parametrize("method,ior,ir_method", [("RANDOM_WALK", 1.45, None),
                                                  ("RANDOM_WALK_SKIN", 1.35, "skin")])
def test_random_walk_sockets(method, ior, ir_method):
    mat, n = _wax()
    n.subsurface_method = method
    warns = []
    sub = _exporter(warns.append).export(mat)["subsurface"]
    assert sub["weight"] == 1.0
    assert sub["radius"] == pytest.approx([0.1, 0.05, 0.025])
    assert sub["anisotropy"] == pytest.approx(0.2) and sub["ior"] == pytest.approx(ior)
    assert sub.get("method") == ir_method
    assert not warns


def test_burley_is_random_walk_with_a_warning_and_weight_zero_is_none():
    mat, n = _wax()
    n.subsurface_method = "BURLEY"
    warns = []
    d = _exporter(warns.append).export(mat)
    assert d["subsurface"]["radius"] == pytest.approx([0.1, 0.05, 0.025])
    assert any("Christensen-Burley" in w and f"'{mat.name}'" in w for w in warns)
    n.inputs["Subsurface Weight"].default_value = 0.0
    assert "subsurface" not in _exporter(warns.append).export(mat)
