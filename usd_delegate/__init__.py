"""USD stage -> photonmap scene IR.

One reader module per prim kind: ``mesh`` (UsdGeom.Mesh), ``instancing`` (instanceable prims,
UsdGeom.PointInstancer), ``lights`` (UsdLux), ``materials`` (UsdShade: UsdPreviewSurface,
MaterialX OpenPBR and standard_surface), ``textures`` (UsdUVTexture, MaterialX image nodes,
read with OpenImageIO), ``camera`` (UsdGeom.Camera). ``stage`` walks the stage and assembles
the IR; ``diagnostics`` collects warnings (named by prim path) and errors.

    from usd_delegate import load_stage
    result = load_stage("shot.usda", frame=12, camera="/World/Cam")
    result.ir          # dict mirroring the JSON IR, mesh arrays as numpy
    result.stats       # prims read, triangles, warnings ...
    result.diagnostics.messages()
"""

from .diagnostics import Diagnostics, UsdImportError
from .frames import parse_frames
from .stage import ImportResult, load_stage

__all__ = ["load_stage", "ImportResult", "Diagnostics", "UsdImportError", "parse_frames"]
