"""Blender -> photonmap scene IR, one converter per Blender ID type (mesh, light, material,
world, camera, image) and ``scene.export`` orchestrating them.

Everything here runs on Blender's thread: it copies data out of Blender into numpy arrays and
plain dicts (the IR of the core's ``src/scene/desc.rs``), which the render then uses with the
GIL released. Nothing here imports ``usd_delegate``.
"""

from .scene import ExportResult, export_scene  # noqa: F401
