"""World -> IR environment: Background colour x strength, or an Environment Texture
(equirectangular; Blender's orientation is the IR's). The World's Volume shader becomes the
IR's ``world_medium`` (scene.py, volume.py)."""

from __future__ import annotations

from .material import _source


def export_world(world, images, warn) -> dict | None:
    if world is None:
        return None
    tree = world.node_tree if getattr(world, "use_nodes", True) else None
    if tree is None:
        c = [float(x) for x in world.color[:3]]
        return {"color": c, "strength": 1.0} if any(c) else None
    outs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld"]
    out = next((n for n in outs if n.is_active_output), outs[0] if outs else None)
    if out is None:
        return None
    bg, _ = _source(out.inputs["Surface"])
    if bg is None:
        return None
    if bg.bl_idname != "ShaderNodeBackground":
        warn(f"world '{world.name}': '{bg.name}' ({bg.bl_idname}) is not supported; black world")
        return None
    strength_in = bg.inputs["Strength"]
    if strength_in.is_linked:
        warn(f"world '{world.name}': a linked Strength is not supported; uses its value")
    env = {"color": [1.0, 1.0, 1.0], "strength": float(strength_in.default_value)}
    color_in = bg.inputs["Color"]
    src, out_sock = _source(color_in)
    if src is None:
        env["color"] = [float(x) for x in color_in.default_value[:3]]
    elif src.bl_idname == "ShaderNodeTexEnvironment":
        if src.projection != "EQUIRECTANGULAR":
            warn(f"world '{world.name}': {src.projection} projection is not supported; "
                 f"treated as equirectangular")
        vec, _ = _source(src.inputs["Vector"])
        if vec is not None:
            warn(f"world '{world.name}': the Environment Texture's vector input "
                 f"('{vec.name}') is ignored")
        t = images.texture(src.image, "REPEAT", f" (world '{world.name}')")
        if t is not None:
            env["texture"] = t
    elif src.bl_idname == "ShaderNodeRGB":
        env["color"] = [float(x) for x in out_sock.default_value[:3]]
    else:
        warn(f"world '{world.name}': '{src.name}' ({src.bl_idname}) on Color is not supported; "
             f"uses the socket's colour")
        env["color"] = [float(x) for x in color_in.default_value[:3]]
    if env["strength"] == 0.0 or ("texture" not in env and not any(env["color"])):
        return None
    return env
