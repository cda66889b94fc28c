"""The engineer's own structure, as described: a 3-D frame (:class:`Frame`, SI units) and its validation
(frame.py), the members' sections and materials (sections.py), and its file format, JSON or TOML (file.py).

The FE solution of a described frame (its mesh and modes) is era/fem/solution.py's; ``Frame.modes`` and the
other solving methods call it. ``era.Frame`` and ``era.Section`` are these.
"""

from .file import frame_from_dict, frame_to_dict, load_frame, save_frame
from .frame import DIRECTIONS, SUPPORT_KEYS, UNITS_M, Frame
from .sections import MATERIALS, Section

__all__ = ["Frame", "Section", "MATERIALS", "SUPPORT_KEYS", "DIRECTIONS", "UNITS_M", "frame_to_dict",
           "frame_from_dict", "save_frame", "load_frame"]
