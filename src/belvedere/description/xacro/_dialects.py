"""Which xacro a file was written for, and what its unprefixed tags mean in each dialect."""

from __future__ import annotations

import enum
import shlex
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Final

from belvedere.description.xacro._macros import Macro
from belvedere.errors import SourceLocation
from belvedere.xmldom import Element

__all__ = [
    "FIX_SED",
    "KNOWN_ELEMENTS",
    "LEGACY_KEYWORDS",
    "Dialect",
    "XacroWarning",
    "legacy_summary",
    "unprefixed_call",
]


class Dialect(enum.Enum):
    """Which xacro the input was written for."""

    AUTO = "auto"
    """Modern semantics; legacy unprefixed tags and macro calls expanded, with a warning."""
    MODERN = "modern"
    """Exactly xacro 2.1.1 (ROS Noetic and later)."""
    MELODIC = "melodic"
    """xacro 1.13 in-order: unprefixed tags and calls, macros defined in macros leak."""
    KINETIC = "kinetic"
    """xacro 1.11 default: two passes (includes, macros, properties first), literal typing."""


LEGACY_KEYWORDS: Final = frozenset(
    {"property", "macro", "include", "arg", "if", "unless", "insert_block"}
)

# Tags of URDF, SDF and Gazebo extensions: an unprefixed tag of these names that also names a
# macro is ambiguous (melodic swallowed it into the macro, ros/xacro#41).
KNOWN_ELEMENTS: Final = frozenset(
    """
    robot link joint inertial origin mass inertia visual collision geometry box cylinder sphere
    mesh material color texture parent child axis calibration dynamics limit mimic
    safety_controller transmission type hardwareInterface actuator mechanicalReduction gazebo
    plugin sensor camera ray scan horizontal vertical range noise image clip update_rate
    visualize always_on topic pose model world include uri name static light physics scene
    state contact friction surface ode bounce kp kd mu mu1 mu2 fdir1 minDepth maxVel
    selfCollide gravity turnGravityOff provideFeedback implicitSpringDamper frame imu
    force_torque lidar gpu_ray depth_camera
    """.split()  # noqa: SIM905 (a word list reads better than a literal)
)

FIX_SED: Final = (
    'find . -iname "*.xacro" | xargs sed -i \'s#<\\([/]\\?\\)\\(if\\|unless\\|include'
    "\\|arg\\|property\\|macro\\|insert_block\\)\\([ >]\\)#<\\1xacro:\\2\\3#g'"
)


@dataclass(frozen=True, slots=True)
class XacroWarning:
    """A warning the processor gave, with where it applies."""

    message: str
    location: SourceLocation | None = None
    legacy: str | None = None
    """The tag, when the warning is about one legacy unprefixed tag or macro call that
    ``--fix`` rewrites (these are summed up in one line: :func:`legacy_summary`)."""

    def __str__(self) -> str:
        return f"{self.location}: warning: {self.message}" if self.location else self.message


def unprefixed_call(
    dialect: Dialect, el: Element, macro: Macro, *, calling: list[str]
) -> tuple[bool, str, str]:
    """What an unprefixed tag naming a macro is: (expand it?, warning key, warning).

    ``calling`` are the macros being expanded around it (a tag named like one of them is
    content, not a recursive call)."""
    tag = el.tag
    if dialect is Dialect.MODERN:
        return (
            False,
            f"call:{tag}",
            f"<{tag}> names a macro but has no 'xacro:' prefix: modern xacro leaves it "
            f"unexpanded (write <xacro:{tag}>, or use --dialect auto)",
        )
    if dialect is not Dialect.AUTO:
        return (
            True,
            "melodic-deprecated",
            f"Deprecated: xacro tag '{tag}' w/o 'xacro:' xml namespace prefix "
            f"(will be forbidden in Noetic)\nUse the following command to fix incorrect "
            f"tag usage:\n{FIX_SED}",
        )
    if tag in KNOWN_ELEMENTS:
        return (
            False,
            f"call:{tag}",
            f"<{tag}> is both a macro and a URDF/SDF element: kept as the element. "
            f"If you meant the macro, write <xacro:{tag}>",
        )
    if tag in calling:
        return (
            False,
            f"call:{tag}",
            f"<{tag}> inside the expansion of macro '{tag}' is kept as an element "
            f"(as a call it would recurse). If it is a call, write <xacro:{tag}>",
        )
    unknown = [a for a in el.attrs if a not in macro.params]
    if unknown:
        return (
            False,
            f"call:{tag}",
            f"<{tag}> has the name of a macro but attributes it does not take "
            f"({', '.join(unknown)}): kept as an element. If it is a call, write <xacro:{tag}>",
        )
    return (
        True,
        f"call:{tag}",
        f"deprecated macro call <{tag}> without the 'xacro:' prefix: expanded as ROS "
        f"Melodic did (modern xacro leaves it unexpanded and the robot loses it). "
        f"Write <xacro:{tag}>, or run 'belvedere xacro --fix FILE'",
    )


def legacy_summary(path: str, sites: Sequence[tuple[SourceLocation | None, str]]) -> str | None:
    """One line for every legacy unprefixed tag and macro call that expanding ``path`` met
    (``sites``: where, and the tag), in place of a warning each; None if there were none."""
    if not sites:
        return None
    calls = sum(1 for _, tag in sites if tag not in LEGACY_KEYWORDS)
    keywords = len(sites) - calls
    parts = [
        f"{n} legacy {what}{'' if n == 1 else 's'}"
        for n, what in ((calls, "macro call"), (keywords, "xacro tag"))
        if n
    ]
    elsewhere = any(loc is not None and loc.path != path for loc, _ in sites)
    where = f"{path} and the files it includes" if elsewhere else path
    how = "expanded" if not keywords else "processed"
    them = "it" if len(sites) == 1 else "them"
    return (
        f"note: {' and '.join(parts)} without the 'xacro:' prefix in {where} ({how} as ROS "
        f"Melodic did); 'belvedere xacro --fix {shlex.quote(path)}' rewrites {them}; -v lists "
        f"{them}"
    )
