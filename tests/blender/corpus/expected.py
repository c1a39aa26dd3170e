"""Corpus scenes known to fail their comparison, per path, with the reason (no bpy).

The tests mark these ``xfail(strict=True)``: the suite stays green while they fail and turns
red when they start to pass, so that the entry is removed with the fix. Figures for each are
in the test's message (compare.py) and in scripts/corpus_compare.py's table.
"""

from __future__ import annotations

# Defects in the core, being fixed there.
AREA_BACK = ("core: the back of an area light renders as an opaque black quad (Cycles: "
             "one-sided, invisible from behind, never occludes)")
SPOT_RADIUS = "core: a spot light with a radius loses its cone (Cycles keeps it sharp)"
SOFT_FALLOFF = ("core: Blender's Soft Falloff (on by default) is not modelled (Cycles reads "
                "the point light as a disk facing the shading point)")
SPREAD = "core: area light Spread is not modelled (emits into the whole hemisphere)"
ELLIPSE = "core: an ellipse area light is rendered as a disk of the same area"

#: scene -> reason, for the add-on path (tests/blender/test_corpus.py).
ADDON: dict[str, str] = {}

#: scene -> reason, for the USD path (tests/python/test_corpus_usd.py).
USD: dict[str, str] = {}


def reason(path: str, name: str) -> str | None:
    return {"addon": ADDON, "usd": USD}[path].get(name)


def marks(path: str, name: str) -> list:
    """pytest marks for scene ``name`` on ``path`` ("addon" or "usd")."""
    import pytest

    why = reason(path, name)
    return [pytest.mark.xfail(strict=True, reason=why)] if why else []
