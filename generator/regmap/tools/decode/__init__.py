"""`regmap decode`: what a frame or a bus capture holds, named with the map's registers.

`frame` decodes one frame (problems, limits, values), `capture` reads a capture file line by line,
`text` prints the result; the values themselves are decoded by `regmap.core.decoding`, the code the
manual's annotated frames and `regmap read` use too.
"""

from regmap.tools.decode.capture import CaptureError, CaptureLine, CaptureResult, capture_lines, decode_capture, split_capture_line
from regmap.tools.decode.frame import Decoded, decode_answer, decode_frame, decode_mbap
from regmap.tools.decode.text import render_text

__all__ = [
    "CaptureError",
    "CaptureLine",
    "CaptureResult",
    "Decoded",
    "capture_lines",
    "decode_answer",
    "decode_capture",
    "decode_frame",
    "decode_mbap",
    "render_text",
    "split_capture_line",
]
