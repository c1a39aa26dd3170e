"""The render's line in Blender's status bar, from the core's stats. Plain Python (no bpy),
so that it is tested with the package alone (``tests/python/test_blender_status.py``)."""

from __future__ import annotations


def _mib(n) -> str:
    return f"{(n or 0) / (1024 * 1024):.1f} MiB"


def stats_line(stats: dict) -> str:
    """Photons stored per map, time per pass and memory, from the core's stats. The memory
    is the stats' ``memory_bytes``, which counts the film, the scene geometry and the photon
    maps (``photon_maps[*].memory_bytes``) together."""
    stored = ", ".join(f"{k} {v:,}" for k, v in (stats.get("photons_stored") or {}).items())
    secs = ", ".join(f"{k} {v:.2f}s" for k, v in (stats.get("seconds") or {}).items())
    reuse = stats.get("photon_map_reuse") or {}
    maps = {"loaded": "photon maps loaded", "reused": "photon maps reused"}.get(reuse.get("maps"), "")
    if reuse.get("saved_to"):
        maps = "photon maps saved"
    n = stats.get("unsupported_nodes", 0)
    unsupported = f"{n} unsupported shader node{'s' if n != 1 else ''}" if n else ""
    parts = [p for p in (maps, f"photons stored: {stored}" if stored else "", secs,
                         _mib(stats.get("memory_bytes")), unsupported) if p]
    return " | ".join(parts)
