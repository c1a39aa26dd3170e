"""The compositing passes in Blender: the denoising guides under Blender's Denoise node,
Cryptomatte under Blender's Cryptomatte node, and light groups beside Combined."""

from __future__ import annotations

import bpy
import numpy as np
import photonmap
import pytest
import scenes
from conftest import exr_parts, set_multilayer_exr


def _compositor(sc):
    """An empty compositing node group of ``sc`` with an Image output; its Render Layers
    node."""
    tree = bpy.data.node_groups.new("Compositing", "CompositorNodeTree")
    tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
    out = tree.nodes.new("NodeGroupOutput")
    rl = tree.nodes.new("CompositorNodeRLayers")
    rl.scene = sc
    sc.compositing_node_group = tree
    sc.render.use_compositing = True
    return tree, rl, out


def _render_rgb(sc, path) -> np.ndarray:
    """Renders ``sc`` to a single-layer float EXR at ``path`` (the composited image when the
    compositor is on) and reads its RGB."""
    import OpenImageIO as oiio

    sc.render.filepath = str(path)
    sc.render.image_settings.media_type = "IMAGE"
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    bpy.ops.render.render(write_still=True)
    return oiio.ImageBuf(str(path)).get_pixels(oiio.FLOAT)[..., :3]


def _noise(img: np.ndarray) -> float:
    """Mean absolute difference between a pixel and the mean of its four neighbours."""
    c = img[1:-1, 1:-1]
    nb = (img[:-2, 1:-1] + img[2:, 1:-1] + img[1:-1, :-2] + img[1:-1, 2:]) / 4
    return float(np.abs(c - nb).mean())


def test_denoise_node_runs_on_the_denoising_passes(photonmap_scene, addon, tmp_path):
    sc = photonmap_scene(scenes.cornell_area)
    sc.photonmap.spp = 2
    sc.photonmap.adaptive_sampling = False
    sc.photonmap.denoising_data = True
    # The passes exist, in the result and the multilayer EXR, with the guides' contents.
    set_multilayer_exr(sc, tmp_path / "passes.exr")
    bpy.ops.render.render(write_still=True)
    parts = exr_parts(tmp_path / "passes.exr")
    layer = bpy.context.view_layer.name
    albedo = parts[f"{layer}.Denoising Albedo"]
    normal = parts[f"{layer}.Denoising Normal"]
    a = np.stack([albedo[f"{layer}.Denoising Albedo.{c}"] for c in "RGB"], -1)
    n = np.stack([normal[f"{layer}.Denoising Normal.{c}"] for c in "XYZ"], -1)
    # The back wall (white, 0.8) faces the camera: normal z < 0 in camera space.
    centre = (slice(28, 36), slice(28, 36))
    assert np.allclose(a[centre], 0.8, atol=0.02), a[centre].mean((0, 1))
    assert (n[centre][..., 2] < -0.9).all(), n[centre].mean((0, 1))
    # The red left wall's albedo is red.
    left = a[28:36, 2:6].mean((0, 1))
    assert left[0] > 0.7 and left[1] < 0.2, left

    raw = _render_rgb(sc, tmp_path / "raw.exr")
    tree, rl, out = _compositor(sc)
    dn = tree.nodes.new("CompositorNodeDenoise")
    links = [tree.links.new(rl.outputs["Image"], dn.inputs["Image"]),
             tree.links.new(rl.outputs["Denoising Albedo"], dn.inputs["Albedo"]),
             tree.links.new(rl.outputs["Denoising Normal"], dn.inputs["Normal"]),
             tree.links.new(dn.outputs["Image"], out.inputs["Image"])]
    assert all(lk.is_valid for lk in links)
    assert rl.outputs["Denoising Albedo"].enabled and rl.outputs["Denoising Normal"].enabled
    den = _render_rgb(sc, tmp_path / "denoised.exr")
    assert np.isfinite(den).all()
    # Open Image Denoise ran: the noise is several times lower, the brightness kept.
    assert _noise(den) < 0.4 * _noise(raw), (_noise(den), _noise(raw))
    assert abs(den.mean() / raw.mean() - 1) < 0.05, (den.mean(), raw.mean())


def _crypto_matte(parts, layer, type_name, name) -> np.ndarray:
    """``name``'s matte decoded from the multilayer EXR's Cryptomatte passes: the sum of the
    coverages of the ranks whose id is the name's (its hash from the manifest)."""
    out = None
    for part, chans in parts.items():
        if not part.startswith(f"{layer}.{type_name}"):
            continue
        px = np.stack([chans[f"{part}.{c}"] for c in "RGBA"], -1)
        out = np.zeros(px.shape[:2], np.float32) if out is None else out
        for k in (0, 2):
            out += np.where(px[..., k] == _name_id(name), px[..., k + 1], 0.0)
    return out


def _name_id(name: str) -> np.float32:
    """The float id of a name, from the core's manifest (MurmurHash3, per the spec)."""
    header = photonmap.cryptomatte_header({"T": [name]})
    manifest = next(v for k, v in header.items() if k.endswith("/manifest"))
    import json
    import struct

    hexid = json.loads(manifest)[name]
    return np.float32(struct.unpack(">f", bytes.fromhex(hexid))[0])


def test_cryptomatte_node_extracts_a_matte(photonmap_scene, addon, tmp_path):
    sc = photonmap_scene(scenes.cornell_area)
    sc.photonmap.spp = 4
    sc.photonmap.adaptive_sampling = False
    sc.photonmap.cryptomatte = "both"
    set_multilayer_exr(sc, tmp_path / "crypto.exr")
    bpy.ops.render.render(write_still=True)
    layer = bpy.context.view_layer.name
    parts = exr_parts(tmp_path / "crypto.exr")
    for t in ("CryptoObject", "CryptoMaterial"):
        assert {f"{layer}.{t}0{i}" for i in range(3)} <= set(parts), sorted(parts)
    ours = _crypto_matte(parts, layer, "CryptoObject", "back")
    # The back wall fills the upper middle of the frame and none of its left edge.
    assert ours[8:32, 20:44].min() > 0.99 and ours[:, :8].max() == 0.0

    tree, rl, out = _compositor(sc)
    node = tree.nodes.new("CompositorNodeCryptomatteV2")
    node.source = "RENDER"
    node.scene = sc
    node.layer_name = f"{layer}.CryptoObject"
    node.matte_id = "back"
    tree.links.new(rl.outputs["Image"], node.inputs["Image"])
    tree.links.new(node.outputs["Matte"], out.inputs["Image"])
    got = _render_rgb(sc, tmp_path / "matte.exr")[..., 0]
    # Blender's node decodes the same matte from our passes and manifest.
    assert got.max() > 0.99
    np.testing.assert_allclose(got, ours, atol=1e-5)


def test_light_group_passes_exist_and_sum_to_combined(photonmap_scene, addon, tmp_path):
    sc = photonmap_scene(scenes.cornell_area)
    sc.photonmap.spp = 4
    sc.photonmap.adaptive_sampling = False
    layer = bpy.context.view_layer
    for name in ("key", "fill"):
        layer.lightgroups.add(name=name)
    area = next(o for o in sc.objects if o.type == "LIGHT")
    area.lightgroup = "key"
    lamp = scenes.light("POINT", (-0.6, 0.3, 0.5), energy=20.0, color=(1.0, 0.7, 0.4),
                        shadow_soft_size=0.05)
    lamp.lightgroup = "fill"
    layer.update_render_passes()
    set_multilayer_exr(sc, tmp_path / "groups.exr")
    bpy.ops.render.render(write_still=True)
    parts = exr_parts(tmp_path / "groups.exr")
    name = layer.name
    groups = ["key", "fill", "default"]
    rgb = lambda p: np.stack([parts[f"{name}.{p}"][f"{name}.{p}.{c}"] for c in "RGB"], -1)  # noqa
    comb = rgb("Combined")
    total = sum(rgb(f"Combined_{g}") for g in groups)
    assert comb.mean() > 0.05
    np.testing.assert_allclose(total, comb, rtol=1e-4, atol=1e-5)
    key, fill = rgb("Combined_key"), rgb("Combined_fill")
    assert key.mean() > 0.02 and fill.mean() > 0.005
    assert not rgb("Combined_default").any()  # every light is in a group
    # The warm lamp's group is warm.
    assert fill[..., 0].mean() > 1.3 * fill[..., 2].mean()
    # The compositor's Render Layers node offers the groups as sockets.
    tree, rl, out = _compositor(sc)
    sockets = {o.name for o in rl.outputs if o.enabled}
    assert {f"Combined_{g}" for g in groups} <= sockets, sockets
