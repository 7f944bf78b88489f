"""Files for other programs: the cam for manufacturing (the outline as DXF, CSV or SVG; a CNC cutter path; a cam
grinder's table; a STEP or STL solid with the optional extra ``camdyn[cad]``) and case files camdyn writes."""

from .profile import FORMATS, OUTLINE_FORMATS, resample, resample_u, write_profile
from .toml import camdyn_version, dumps_case

__all__ = ["FORMATS", "OUTLINE_FORMATS", "camdyn_version", "dumps_case", "resample", "resample_u", "write_profile"]
