"""Render Properties panels, and the built-in panels PhotonMap shares with other engines."""

from __future__ import annotations

import bpy

from .properties import SCHEMA

ENGINE = "PHOTONMAP"

# Built-in panels that show for EEVEE/Workbench and make sense here too (materials, world and
# light properties, format and output panels already list BLENDER_RENDER).
_SHARED = {
    "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface", "MATERIAL_PT_preview",
    "EEVEE_WORLD_PT_surface", "WORLD_PT_context_world", "DATA_PT_light", "DATA_PT_EEVEE_light",
    "DATA_PT_context_light", "DATA_PT_area", "DATA_PT_spot", "DATA_PT_lens", "DATA_PT_camera",
    "DATA_PT_camera_dof", "DATA_PT_camera_dof_aperture", "DATA_PT_context_camera",
}
_EXCLUDE = {"VIEWLAYER_PT_filter", "VIEWLAYER_PT_layer_passes"}
_added: list = []


class PhotonMapPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


def draw_group(layout, s, group: str) -> None:
    """The settings of one schema group, in schema order; a setting of the other mode is
    hidden, one whose switch is off is greyed out."""
    layout.use_property_split = True
    for f in SCHEMA:
        if f["group"] != group or (f["modes"] and s.mode not in f["modes"]):
            continue
        row = layout.row()
        if f["requires"]:
            row.active = bool(getattr(s, f["requires"]))
        row.prop(s, f["name"])


class PHOTONMAP_PT_quality(PhotonMapPanel, bpy.types.Panel):
    bl_label = "Quality"

    def draw(self, context):
        draw_group(self.layout, context.scene.photonmap, "quality")


class PHOTONMAP_PT_photons(PhotonMapPanel, bpy.types.Panel):
    bl_label = "Photons"

    def draw(self, context):
        draw_group(self.layout, context.scene.photonmap, "photons")


class PHOTONMAP_PT_gather(PhotonMapPanel, bpy.types.Panel):
    bl_label = "Final Gathering"

    def draw(self, context):
        draw_group(self.layout, context.scene.photonmap, "gathering")


class PHOTONMAP_PT_passes(PhotonMapPanel, bpy.types.Panel):
    bl_label = "Passes"

    def draw(self, context):
        draw_group(self.layout, context.scene.photonmap, "passes")


CLASSES = (PHOTONMAP_PT_quality, PHOTONMAP_PT_photons, PHOTONMAP_PT_gather, PHOTONMAP_PT_passes)


def _shared_panels():
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if engines is None or panel.__name__ in _EXCLUDE:
            continue
        if "BLENDER_RENDER" in engines or panel.__name__ in _SHARED:
            yield panel


def register():
    for c in CLASSES:
        bpy.utils.register_class(c)
    for panel in _shared_panels():
        if ENGINE not in panel.COMPAT_ENGINES:
            panel.COMPAT_ENGINES.add(ENGINE)
            _added.append(panel)


def unregister():
    for panel in _added:
        panel.COMPAT_ENGINES.discard(ENGINE)
    _added.clear()
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)
