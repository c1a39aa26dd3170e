#!/usr/bin/env python3
"""Builds the PhotonMap Blender extension zip.

    python3 scripts/build_blender_extension.py              # builds the abi3 wheel, then the zip
    python3 scripts/build_blender_extension.py --wheel W    # uses an already built wheel

1. Builds the ``photonmap`` abi3 wheel (maturin; ``pip wheel . --no-deps`` when maturin is not
   installed) into ``dist/``.
2. Copies it to ``blender_addon/wheels/`` (only that wheel).
3. Zips ``blender_addon/`` as ``dist/photonmap-blender-<version>-<platform>.zip``, with the
   manifest's ``wheels`` and ``platforms`` naming the wheel just built.

Blender installs only the wheels the manifest lists and ignores their declared dependencies
(usd-core, OpenImageIO: used by the command line only; the add-on imports ``photonmap`` and
numpy, which Blender ships).
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ADDON = ROOT / "blender_addon"

# Wheel platform tag -> Blender extension platform.
PLATFORMS = [
    (re.compile(r"(manylinux|musllinux|linux)_.*x86_64"), "linux-x64"),
    (re.compile(r"(manylinux|musllinux|linux)_.*aarch64"), "linux-arm64"),
    (re.compile(r"macosx_.*(x86_64|universal2)"), "macos-x64"),
    (re.compile(r"macosx_.*(arm64|universal2)"), "macos-arm64"),
    (re.compile(r"win_amd64"), "windows-x64"),
    (re.compile(r"win_arm64"), "windows-arm64"),
]


def build_wheel(out: Path) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    before = set(out.glob("photonmap-*.whl"))
    env = dict(os.environ)
    if shutil.which("maturin"):
        cmd = ["maturin", "build", "--release", "-o", str(out)]
    else:
        cmd = [sys.executable, "-m", "pip", "wheel", ".", "--no-deps", "-w", str(out)]
    print("+", " ".join(cmd), flush=True)
    subprocess.run(cmd, cwd=ROOT, env=env, check=True)
    wheels = sorted(out.glob("photonmap-*-abi3-*.whl"), key=lambda p: p.stat().st_mtime)
    if not wheels:
        sys.exit("no photonmap abi3 wheel was built")
    new = [w for w in wheels if w not in before]
    return (new or wheels)[-1]


def platforms_of(wheel: Path) -> list[str]:
    tag = wheel.stem.split("-")[-1]
    found = []
    for part in tag.split("."):
        for rx, name in PLATFORMS:
            if rx.search(part) and name not in found:
                found.append(name)
    if not found:
        sys.exit(f"unknown platform tag in {wheel.name}")
    return found


def manifest_for(wheel: Path) -> str:
    text = (ADDON / "blender_manifest.toml").read_text()
    plats = ", ".join(f'"{p}"' for p in platforms_of(wheel))
    text = re.sub(r"(?m)^platforms\s*=.*$", f"platforms = [{plats}]", text)
    text = re.sub(r"(?m)^wheels\s*=.*$", f'wheels = ["./wheels/{wheel.name}"]', text)
    return text


def addon_version() -> str:
    m = re.search(r'(?m)^version\s*=\s*"([^"]+)"', (ADDON / "blender_manifest.toml").read_text())
    return m.group(1) if m else "0"


def build_zip(wheel: Path, out: Path) -> Path:
    wheels_dir = ADDON / "wheels"
    if wheels_dir.exists():
        shutil.rmtree(wheels_dir)
    wheels_dir.mkdir()
    shutil.copy2(wheel, wheels_dir / wheel.name)
    plat = "-".join(platforms_of(wheel))
    zpath = out / f"photonmap-blender-{addon_version()}-{plat}.zip"
    out.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(zpath, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("blender_manifest.toml", manifest_for(wheel))
        for path in sorted(ADDON.rglob("*")):
            rel = path.relative_to(ADDON)
            if path.is_dir() or rel.name == "blender_manifest.toml" or rel.name == ".gitignore":
                continue
            if "__pycache__" in rel.parts or path.suffix in {".zip", ".pyc"}:
                continue
            z.write(path, rel.as_posix())
    return zpath


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--wheel", type=Path, help="use this photonmap wheel instead of building one")
    ap.add_argument("--out", type=Path, default=ROOT / "dist", help="output folder (dist/)")
    a = ap.parse_args()
    wheel = a.wheel.resolve() if a.wheel else build_wheel(a.out.resolve())
    zpath = build_zip(wheel, a.out.resolve())
    print(zpath)


if __name__ == "__main__":
    main()
