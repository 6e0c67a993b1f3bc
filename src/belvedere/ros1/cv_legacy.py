"""``cv2.cv`` for Python-2-era OpenCV scripts (rbx1_vision's ``import cv2.cv as cv``): the
OpenCV 2 constants they use, translated by name to OpenCV 4's, with a one-line notice.

Where it stops: constants (``CV_CAP_PROP_*``, colour conversions ``CV_BGR2GRAY``,
``CV_HAAR_*``, ``CV_FILLED``/``CV_AA``, fonts, thresholds, windows, term criteria), the
``RGB`` macro and the window functions (``NamedWindow``, ``WaitKey``, ``DestroyAllWindows``,
``MoveWindow``, ``ResizeWindow``, ``ShowImage``).
The OpenCV 1 C API (``CreateImage``, ``fromarray``, IplImage, CvMat) is gone from OpenCV 4;
each of its names is an error saying so.
"""

from __future__ import annotations

import re
import sys
from types import ModuleType
from typing import Any, Final

__all__ = ["legacy_module", "translate"]

# old prefix -> new prefix
_PREFIXES: Final = (
    ("CV_CAP_PROP_", "CAP_PROP_"),
    ("CV_HAAR_", "CASCADE_"),
    ("CV_FONT_", "FONT_"),
    ("CV_THRESH_", "THRESH_"),
    ("CV_WINDOW_", "WINDOW_"),
    ("CV_TERMCRIT_", "TERM_CRITERIA_"),
    ("CV_INTER_", "INTER_"),
    ("CV_EVENT_", "EVENT_"),
    ("CV_RETR_", "RETR_"),
    ("CV_CHAIN_", "CHAIN_"),
    ("CV_MORPH_", "MORPH_"),
    ("CV_LOAD_IMAGE_", "IMREAD_"),
)
_RENAMED: Final = {
    "CV_FILLED": "FILLED",
    "CV_AA": "LINE_AA",
    "CV_TERMCRIT_ITER": "TERM_CRITERIA_MAX_ITER",
    "CV_TERMCRIT_EPS": "TERM_CRITERIA_EPS",
    "CV_HAAR_DO_CANNY_PRUNING": "CASCADE_DO_CANNY_PRUNING",
    "CV_HAAR_SCALE_IMAGE": "CASCADE_SCALE_IMAGE",
    "CV_GAUSSIAN": "GaussianBlur",
}
_COLOUR: Final = re.compile(r"CV_([A-Za-z]+[0-9]*)2([A-Za-z]+[0-9]*(?:_[A-Z0-9]+)?)")


def translate(cv2: ModuleType, name: str) -> Any:
    """OpenCV 4's value for the OpenCV 2 ``cv2.cv`` name ``name``.

    Raises:
        AttributeError: not a name the table translates (saying where it stops).
    """
    candidates = []
    if name in _RENAMED:
        candidates.append(_RENAMED[name])
    for old, new in _PREFIXES:
        if name.startswith(old):
            candidates.append(new + name[len(old) :])
    colour = _COLOUR.fullmatch(name)
    if colour:
        candidates.append(f"COLOR_{colour[1]}2{colour[2]}")
    if name.startswith("CV_"):
        candidates.append(name[3:])
    for candidate in candidates:
        if hasattr(cv2, candidate):
            return getattr(cv2, candidate)
    msg = (
        f"cv2.cv.{name}: OpenCV 4 has no cv2.cv; belvedere translates its constants, RGB "
        "and the window functions only (the OpenCV 1 C API, IplImage and CvMat, is gone: "
        "use cv2 and numpy arrays)"
    )
    raise AttributeError(msg)


def legacy_module(cv2: ModuleType) -> ModuleType:
    """A ``cv2.cv`` module over ``cv2``."""
    module = ModuleType("cv2.cv", "OpenCV 2's cv2.cv constants, translated by belvedere")

    def rgb(r: float, g: float, b: float) -> tuple[float, float, float, float]:
        return (b, g, r, 0.0)  # cv.RGB: OpenCV's BGR order

    functions = {
        "RGB": rgb,
        "NamedWindow": lambda name, flags=0: cv2.namedWindow(name, flags),
        "WaitKey": lambda delay=0: cv2.waitKey(delay),
        "DestroyAllWindows": lambda: cv2.destroyAllWindows(),
        "DestroyWindow": lambda name: cv2.destroyWindow(name),
        "ShowImage": lambda name, image: cv2.imshow(name, image),
        "MoveWindow": lambda name, x, y: cv2.moveWindow(name, x, y),
        "ResizeWindow": lambda name, width, height: cv2.resizeWindow(name, width, height),
    }
    for name, function in functions.items():
        setattr(module, name, function)
    noticed: list[bool] = []

    def __getattr__(name: str) -> Any:  # noqa: N807 (a module's attribute hook)
        if name.startswith("__"):
            raise AttributeError(name)
        value = translate(cv2, name)
        if not noticed:
            noticed.append(True)
            sys.stderr.write(
                "[belvedere] cv2.cv is OpenCV 2's: its constants are translated to OpenCV 4's "
                "(cv2.cv.CV_BGR2GRAY is cv2.COLOR_BGR2GRAY)\n"
            )
        return value

    module.__getattr__ = __getattr__  # type: ignore[method-assign]
    return module
