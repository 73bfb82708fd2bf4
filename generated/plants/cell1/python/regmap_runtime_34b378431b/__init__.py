"""Runtime support for regmap-generated clients: RTU framing, value codecs, read plans, the client base.

This package is copied verbatim into every `generated/python/` tree, so a generated client needs
only pymodbus. The regmap generator and its frame tools use the very same code.
"""

from .rtu import FrameError, crc16, parse_frame, parse_hex, to_hex

__all__ = ["FrameError", "crc16", "parse_frame", "parse_hex", "to_hex"]
