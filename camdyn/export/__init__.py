"""Files for other programs: the cam contour for manufacturing (DXF, CSV, SVG) and case files camdyn writes."""

from .profile import FORMATS, resample, write_profile
from .toml import camdyn_version, dumps_case

__all__ = ["FORMATS", "camdyn_version", "dumps_case", "resample", "write_profile"]
