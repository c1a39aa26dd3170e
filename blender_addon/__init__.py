"""PhotonMap: a two-pass photon-mapping render engine for Blender (Jensen 2001).

The renderer is the ``photonmap`` Python package (a Rust core), installed from the wheel
listed in ``blender_manifest.toml``. This add-on exports the depsgraph to the core's scene IR
(``export/``), renders it with the GIL released, and writes Combined plus one pass per term.
"""

import bpy

from . import engine, properties, ui


def register():
    properties.register()
    bpy.utils.register_class(engine.PhotonMapRenderEngine)
    ui.register()


def unregister():
    ui.unregister()
    bpy.utils.unregister_class(engine.PhotonMapRenderEngine)
    properties.unregister()
