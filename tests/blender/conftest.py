"""Runs the PhotonMap Blender extension in the `bpy` module (headless).

The extension zip comes from ``PHOTONMAP_BLENDER_ZIP``, or is built by
scripts/build_blender_extension.py (with ``PHOTONMAP_WHEEL`` as the wheel when set). It is
installed the way users install it, into a throw-away Blender user folder.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
# Blender reads its user folder at import: point it somewhere disposable first.
USER_DIR = tempfile.mkdtemp(prefix="photonmap-blender-user-")
os.environ["BLENDER_USER_RESOURCES"] = USER_DIR
sys.path.insert(0, str(HERE))

import bpy  # noqa: E402
import pytest  # noqa: E402

sys.path.append(str(HERE.parent))
import skip_policy  # noqa: E402


def pytest_configure(config):
    # Skips are listed at the end; on CI one not allowed by tests/skip_policy.py fails the run.
    skip_policy.register(config)

MODULE = "bl_ext.user_default.photonmap"


def _extension_zip() -> Path:
    given = os.environ.get("PHOTONMAP_BLENDER_ZIP")
    if given:
        return Path(given)
    out = Path(tempfile.mkdtemp(prefix="photonmap-ext-"))
    cmd = [sys.executable, str(ROOT / "scripts" / "build_blender_extension.py"), "--out", str(out)]
    if os.environ.get("PHOTONMAP_WHEEL"):
        cmd += ["--wheel", os.environ["PHOTONMAP_WHEEL"]]
    res = subprocess.run(cmd, check=True, capture_output=True, text=True)
    return Path(res.stdout.strip().splitlines()[-1])


def _install(zip_path: Path) -> None:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    res = bpy.ops.extensions.package_install_files(
        repo="user_default", filepath=str(zip_path), enable_on_install=True)
    assert res == {"FINISHED"}, res


# Installed at collection, as a user would, so that test modules can import `photonmap` from
# the extensions' site-packages.
EXTENSION_ZIP = _extension_zip()
_install(EXTENSION_ZIP)


@pytest.fixture(scope="session")
def addon():
    """The installed and enabled add-on module."""
    return enable()


def enable():
    """(Re-)enables the add-on: read_factory_settings also resets the preferences."""
    import addon_utils

    mod = addon_utils.enable(MODULE, default_set=True)
    assert mod is not None, f"{MODULE} did not enable"
    return sys.modules[MODULE]


@pytest.fixture
def photonmap_scene(addon):
    """Builds a scene with ``builder`` and makes PhotonMap its engine."""

    def make(builder, quality="draft"):
        sc = builder()
        enable()
        sc.render.engine = "PHOTONMAP"
        sc.photonmap.quality = quality
        return sc

    return make


def set_multilayer_exr(sc, path):
    sc.render.filepath = str(path)
    sc.render.image_settings.media_type = "MULTI_LAYER_IMAGE"
    sc.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
    sc.render.image_settings.color_depth = "32"


def exr_parts(path) -> dict:
    """Every part (subimage) of an EXR: {part name or '': {channel: (H,W) array}}."""
    import OpenImageIO as oiio

    inp = oiio.ImageInput.open(str(path))
    assert inp is not None, oiio.geterror()
    n = 0
    while inp.seek_subimage(n, 0):
        n += 1
    inp.close()
    parts = {}
    for i in range(n):
        buf = oiio.ImageBuf(str(path), i, 0)
        spec = buf.spec()
        px = buf.get_pixels(oiio.FLOAT)
        name = spec.get_string_attribute("name")
        parts[name] = {c: px[..., k] for k, c in enumerate(spec.channelnames)}
    return parts


class Reports:
    """Records the engine's reports (``self.report`` goes through ``_report``)."""

    def __init__(self):
        self.items = []

    def __call__(self, kind, message):
        self.items.append((set(kind), message))

    def of(self, kind):
        return [m for k, m in self.items if kind in k]


@pytest.fixture
def reports(addon, monkeypatch):
    r = Reports()
    monkeypatch.setattr(addon.engine.PhotonMapRenderEngine, "_report",
                        lambda engine, kind, message: r({kind}, message))
    return r


def pytest_terminal_summary(terminalreporter):
    """The node corpus' sensitivity table (test_node_sensitivity.py), when its cases ran."""
    mod = sys.modules.get("corpus.sensitivity")
    if mod is not None and mod.TABLE:
        terminalreporter.section("node corpus sensitivity at 'ci': margins beyond the tolerance")
        terminalreporter.line(mod.HEADER)
        for line in mod.TABLE:
            terminalreporter.line(line)
