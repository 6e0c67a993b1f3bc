"""Message types: rosbags' ROS 1 Noetic store, plus the standard types it lacks.

Names are accepted in both spellings (``geometry_msgs/Twist``, ``geometry_msgs/msg/Twist``);
services are ``pkg/srv/Name`` with ``_Request``/``_Response`` message types. An unknown name
is an error that suggests close ones.
"""

from __future__ import annotations

import contextlib
import difflib
import struct
import threading
from collections.abc import Callable, Iterable, Iterator
from dataclasses import replace
from functools import cache
from pathlib import Path
from typing import Any, Final

import numpy as np
from rosbags.interfaces import Nodetype
from rosbags.serde import SerdeError
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from rosbags.typesys.store import Typestore

from belvedere.errors import BelvedereError
from belvedere.msgs import _dynamic_reconfigure_types
from belvedere.msgs._genmsg import PLACEHOLDER, Definition, typedef
from belvedere.msgs._packages import PackageInterfaces
from belvedere.msgs._ros1bytes import Ros1Parts, holds_views
from belvedere.msgs._turtlesim_types import TURTLESIM_MESSAGES, TURTLESIM_SERVICES

__all__ = ["PLACEHOLDER", "MessageTypeError", "TypeRegistry", "types"]


# Standard ROS types missing from rosbags' Noetic store, in .msg syntax (types, not code).
_EXTRA_MESSAGES: Final = {
    "tf2_msgs/msg/TFMessage": "geometry_msgs/TransformStamped[] transforms",
    "tf/msg/tfMessage": "geometry_msgs/TransformStamped[] transforms",
    "control_msgs/msg/JointTolerance": (
        "string name\nfloat64 position\nfloat64 velocity\nfloat64 acceleration"
    ),
    "control_msgs/msg/FollowJointTrajectoryGoal": (
        "trajectory_msgs/JointTrajectory trajectory\n"
        "control_msgs/JointTolerance[] path_tolerance\n"
        "control_msgs/JointTolerance[] goal_tolerance\n"
        "duration goal_time_tolerance"
    ),
    "control_msgs/msg/FollowJointTrajectoryResult": (
        "int32 SUCCESSFUL=0\nint32 INVALID_GOAL=-1\nint32 INVALID_JOINTS=-2\n"
        "int32 OLD_HEADER_TIMESTAMP=-3\nint32 PATH_TOLERANCE_VIOLATED=-4\n"
        "int32 GOAL_TOLERANCE_VIOLATED=-5\nint32 error_code\nstring error_string"
    ),
    "control_msgs/msg/FollowJointTrajectoryFeedback": (
        "std_msgs/Header header\nstring[] joint_names\n"
        "trajectory_msgs/JointTrajectoryPoint desired\n"
        "trajectory_msgs/JointTrajectoryPoint actual\n"
        "trajectory_msgs/JointTrajectoryPoint error"
    ),
    "control_msgs/msg/FollowJointTrajectoryActionGoal": (
        "std_msgs/Header header\nactionlib_msgs/GoalID goal_id\n"
        "control_msgs/FollowJointTrajectoryGoal goal"
    ),
    "control_msgs/msg/FollowJointTrajectoryActionResult": (
        "std_msgs/Header header\nactionlib_msgs/GoalStatus status\n"
        "control_msgs/FollowJointTrajectoryResult result"
    ),
    "control_msgs/msg/FollowJointTrajectoryActionFeedback": (
        "std_msgs/Header header\nactionlib_msgs/GoalStatus status\n"
        "control_msgs/FollowJointTrajectoryFeedback feedback"
    ),
    "move_base_msgs/msg/MoveBaseGoal": "geometry_msgs/PoseStamped target_pose",
    "move_base_msgs/msg/MoveBaseResult": "",
    "move_base_msgs/msg/MoveBaseFeedback": "geometry_msgs/PoseStamped base_position",
    "move_base_msgs/msg/MoveBaseActionGoal": (
        "std_msgs/Header header\nactionlib_msgs/GoalID goal_id\nmove_base_msgs/MoveBaseGoal goal"
    ),
    "move_base_msgs/msg/MoveBaseActionResult": (
        "std_msgs/Header header\nactionlib_msgs/GoalStatus status\n"
        "move_base_msgs/MoveBaseResult result"
    ),
    "move_base_msgs/msg/MoveBaseActionFeedback": (
        "std_msgs/Header header\nactionlib_msgs/GoalStatus status\n"
        "move_base_msgs/MoveBaseFeedback feedback"
    ),
    "move_base_msgs/msg/MoveBaseAction": (
        "move_base_msgs/MoveBaseActionGoal action_goal\n"
        "move_base_msgs/MoveBaseActionResult action_result\n"
        "move_base_msgs/MoveBaseActionFeedback action_feedback"
    ),
    "map_msgs/msg/OccupancyGridUpdate": (
        "std_msgs/Header header\nint32 x\nint32 y\nuint32 width\nuint32 height\nint8[] data"
    ),
    "move_base_msgs/msg/RecoveryStatus": (
        "geometry_msgs/PoseStamped pose_stamped\nuint16 current_recovery_number\n"
        "uint16 total_number_of_recoveries\nstring recovery_behavior_name"
    ),
    "gazebo_msgs/msg/ModelState": (
        "string model_name\ngeometry_msgs/Pose pose\ngeometry_msgs/Twist twist\n"
        "string reference_frame"
    ),
    "gazebo_msgs/msg/ModelStates": (
        "string[] name\ngeometry_msgs/Pose[] pose\ngeometry_msgs/Twist[] twist"
    ),
    "gazebo_msgs/msg/LinkState": (
        "string link_name\ngeometry_msgs/Pose pose\ngeometry_msgs/Twist twist\n"
        "string reference_frame"
    ),
    "gazebo_msgs/msg/LinkStates": (
        "string[] name\ngeometry_msgs/Pose[] pose\ngeometry_msgs/Twist[] twist"
    ),
    "gazebo_msgs/msg/ODEPhysics": (
        "bool auto_disable_bodies\nuint32 sor_pgs_precon_iters\nuint32 sor_pgs_iters\n"
        "float64 sor_pgs_w\nfloat64 sor_pgs_rms_error_tol\nfloat64 contact_surface_layer\n"
        "float64 contact_max_correcting_vel\nfloat64 cfm\nfloat64 erp\nuint32 max_contacts"
    ),
    "control_msgs/msg/JointTrajectoryControllerState": (
        "std_msgs/Header header\nstring[] joint_names\n"
        "trajectory_msgs/JointTrajectoryPoint desired\n"
        "trajectory_msgs/JointTrajectoryPoint actual\n"
        "trajectory_msgs/JointTrajectoryPoint error"
    ),
    "controller_manager_msgs/msg/HardwareInterfaceResources": (
        "string hardware_interface\nstring[] resources"
    ),
    "controller_manager_msgs/msg/ControllerState": (
        "string name\nstring state\nstring type\n"
        "controller_manager_msgs/HardwareInterfaceResources[] claimed_resources"
    ),
    **TURTLESIM_MESSAGES,
    **_dynamic_reconfigure_types.MESSAGES,
}
_EXTRA_SERVICES: Final = {
    "controller_manager_msgs/srv/LoadController": ("string name", "bool ok"),
    "controller_manager_msgs/srv/UnloadController": ("string name", "bool ok"),
    "controller_manager_msgs/srv/SwitchController": (
        "string[] start_controllers\nstring[] stop_controllers\nint32 strictness\n"
        "bool start_asap\nfloat64 timeout",
        "bool ok",
    ),
    "controller_manager_msgs/srv/ListControllers": (
        "",
        "controller_manager_msgs/ControllerState[] controller",
    ),
    "gazebo_msgs/srv/SpawnModel": (
        "string model_name\nstring model_xml\nstring robot_namespace\n"
        "geometry_msgs/Pose initial_pose\nstring reference_frame",
        "bool success\nstring status_message",
    ),
    "gazebo_msgs/srv/DeleteModel": ("string model_name", "bool success\nstring status_message"),
    "gazebo_msgs/srv/GetModelState": (
        "string model_name\nstring relative_entity_name",
        "std_msgs/Header header\ngeometry_msgs/Pose pose\ngeometry_msgs/Twist twist\n"
        "bool success\nstring status_message",
    ),
    "gazebo_msgs/srv/SetModelState": (
        "gazebo_msgs/ModelState model_state",
        "bool success\nstring status_message",
    ),
    "gazebo_msgs/srv/GetPhysicsProperties": (
        "",
        "float64 time_step\nbool pause\nfloat64 max_update_rate\n"
        "geometry_msgs/Vector3 gravity\ngazebo_msgs/ODEPhysics ode_config\n"
        "bool success\nstring status_message",
    ),
    # belvedere's own: gazebo_ros has no service that saves the world (gzclient's menu does)
    "belvedere_msgs/srv/SaveWorld": (
        "string path",
        "bool success\nstring status_message\nstring path",
    ),
    "arbotix_msgs/srv/Relax": ("", ""),
    "arbotix_msgs/srv/Enable": ("bool enable", "bool state"),
    "arbotix_msgs/srv/SetSpeed": ("float64 speed", ""),
    "arbotix_msgs/srv/SetupChannel": ("string topic_name\nuint8 pin\nuint8 value\nuint8 rate", ""),
    "std_srvs/srv/Empty": ("", ""),
    "std_srvs/srv/Trigger": ("", "bool success\nstring message"),
    "std_srvs/srv/SetBool": ("bool data", "bool success\nstring message"),
    "nav_msgs/srv/GetMap": ("", "nav_msgs/OccupancyGrid map"),
    "nav_msgs/srv/GetPlan": (
        "geometry_msgs/PoseStamped start\ngeometry_msgs/PoseStamped goal\nfloat32 tolerance",
        "nav_msgs/Path plan",
    ),
    "nav_msgs/srv/LoadMap": (
        "string map_url",
        "uint8 RESULT_SUCCESS=0\nuint8 RESULT_MAP_DOES_NOT_EXIST=1\n"
        "uint8 RESULT_INVALID_MAP_DATA=2\nuint8 RESULT_INVALID_MAP_METADATA=3\n"
        "uint8 RESULT_UNDEFINED_FAILURE=255\n"
        "nav_msgs/OccupancyGrid map\nuint8 result",
    ),
    "nav_msgs/srv/SetMap": (
        "nav_msgs/OccupancyGrid map\ngeometry_msgs/PoseWithCovarianceStamped initial_pose",
        "bool success",
    ),
    "sensor_msgs/srv/SetCameraInfo": (
        "sensor_msgs/CameraInfo camera_info",
        "bool success\nstring status_message",
    ),
    "tf2_msgs/srv/FrameGraph": ("", "string frame_yaml"),
    **TURTLESIM_SERVICES,
    **_dynamic_reconfigure_types.SERVICES,
}


class MessageTypeError(BelvedereError):
    """An unknown or malformed message type name."""


def canonical(name: str, kind: str = "msg") -> str:
    """``pkg/Type`` → ``pkg/msg/Type`` (or ``pkg/srv/Type``); full names pass through."""
    parts = [p for p in name.strip().split("/") if p]
    if len(parts) == 2:
        return f"{parts[0]}/{kind}/{parts[1]}"
    if len(parts) == 3:
        return "/".join(parts)
    msg = f"malformed type name {name!r}: expected package/Type, e.g. geometry_msgs/Twist"
    raise MessageTypeError(msg)


def short(name: str) -> str:
    """``pkg/msg/Type`` → ``pkg/Type`` (the ROS 1 spelling)."""
    parts = name.split("/")
    return f"{parts[0]}/{parts[-1]}" if len(parts) == 3 else name


class TypeRegistry:
    """All known message and service types over one rosbags typestore."""

    def __init__(self) -> None:
        self.store: Typestore = get_typestore(Stores.ROS1_NOETIC)
        extra: dict[str, Any] = {}
        for name, text in _EXTRA_MESSAGES.items():
            extra.update(get_types_from_msg(text, name))
        for name, (req, res) in _EXTRA_SERVICES.items():
            for suffix, text in (("_Request", req), ("_Response", res)):
                # rosbags files every definition under pkg/msg/…; keep services under pkg/srv/
                pkg, _, base = name.partition("/srv/")
                (fielddef,) = get_types_from_msg(text, f"{pkg}/msg/{base}{suffix}").values()
                extra[f"{name}{suffix}"] = fielddef
        self.store.register(extra)
        self._ros1 = Ros1Parts(self.store)
        self.services = frozenset(_EXTRA_SERVICES)
        self.own = PackageInterfaces()
        """The packages on the package path: their msg/, srv/ and action/ files."""
        self.definitions: dict[str, Definition] = {}
        """The types read from those files, by store name (their text as written)."""
        self._asked: set[str] = set()
        self._learning = threading.RLock()
        self._askers: list[Callable[[str], bool]] = []

    # --- the user's own packages -------------------------------------------------------------
    def add_package_path(self, dirs: Iterable[Path]) -> None:
        """Look for packages' own types in ``dirs`` too (a command's package path)."""
        with self._learning:
            self.own.add_path(dirs)
            # packages not found so far may be on the new path
            self._asked &= {d.package for d in self.definitions.values()}

    def learn(self, package: str) -> bool:
        """Read the types of ``package`` (and of the packages they use) from its msg/, srv/
        and action/ files if not done yet; true if that made new types known. A bad
        definition is an error at its file and line (asked again, read again)."""
        with self._learning:
            if package in self._asked:
                return False
            found = self.own.load(package, self.store.fielddefs.__contains__)
            self._asked.update({package, *found.packages})
            new = {n: d for n, d in found.definitions.items() if n not in self.store.fielddefs}
            if not new:
                return False
            self.store.register({name: typedef(d) for name, d in new.items()})
            self.definitions.update(new)
            self.services = self.services | found.services
            return True

    def adopt(self, definitions: dict[str, Definition], services: Iterable[str] = ()) -> None:
        """Make known the types of ``definitions`` this registry lacks (read from a text that
        came with the data: a bag's, another process's), with their text as written, as
        :meth:`learn` does for a package's files. The caller has checked them (MD5 sums,
        no clash with a type known here)."""
        with self._learning:
            new = {n: d for n, d in definitions.items() if n not in self.store.fielddefs}
            if new:
                self.store.register({name: typedef(d) for name, d in new.items()})
                self.definitions.update(new)
            self.services = self.services | set(services)

    # --- types from elsewhere ------------------------------------------------------------------
    def add_asker(self, asker: Callable[[str], bool]) -> None:
        """Ask ``asker`` for a type no package on the path defines (a store name: a message,
        or a service ``pkg/srv/Name``) before calling it unknown; it answers whether it made
        the type known. The graph's transport is one: it asks the other processes."""
        self._askers.append(asker)

    def remove_asker(self, asker: Callable[[str], bool]) -> None:
        with contextlib.suppress(ValueError):
            self._askers.remove(asker)

    def _ask(self, full: str) -> bool:
        return any(asker(full) for asker in list(self._askers))

    # --- names ---------------------------------------------------------------------------------
    def message_names(self) -> Iterator[str]:
        return (n for n in self.store.fielddefs if "/msg/" in n)

    def service_names(self) -> list[str]:
        """Every service type the store holds (``pkg/srv/Name``, both halves registered),
        sorted: the standard ones and any added to the store since."""
        found = set(self.services)
        for name in self.store.fielddefs:
            if "/srv/" in name and name.endswith("_Request"):
                base = name.removesuffix("_Request")
                if f"{base}_Response" in self.store.fielddefs:
                    found.add(base)
        return sorted(found)

    def resolve(self, name: str) -> str:
        """The canonical name of a message type, or an error suggesting close names."""
        full = canonical(name)
        if full in self.store.fielddefs:
            return full
        if self.learn(full.split("/", 1)[0]):
            return self.resolve(name)
        service = "/srv/" in full and full.rsplit("_", 1)[-1] in ("Request", "Response")
        if self._ask(full.rsplit("_", 1)[0] if service else full) and full in self.store.fielddefs:
            return full
        if service:
            msg = f"unknown service message type {name!r}"
            raise MessageTypeError(msg)
        known = sorted(self.message_names())
        close = difflib.get_close_matches(full, known, n=3, cutoff=0.6)
        if not close:  # try by the type's own name, whatever the package
            tail = full.rsplit("/", 1)[-1].lower()
            close = [k for k in known if k.rsplit("/", 1)[-1].lower() == tail][:3]
        hint = "did you mean " + ", ".join(short(c) for c in close) + "?" if close else None
        msg = f"unknown message type {name!r}"
        raise MessageTypeError(msg, hint=hint)

    def resolve_service(self, name: str) -> str:
        full = canonical(name, "srv")
        if full in self.services:
            return full
        if self.learn(full.split("/", 1)[0]):
            return self.resolve_service(name)
        if self._ask(full) and full in self.services:
            return full
        close = difflib.get_close_matches(full, sorted(self.services), n=3)
        hint = "did you mean " + ", ".join(short(c) for c in close) + "?" if close else None
        msg = (
            f"unknown service type {name!r} (known: {', '.join(sorted(map(short, self.services)))})"
        )
        raise MessageTypeError(msg, hint=hint)

    # --- types ---------------------------------------------------------------------------------
    def cls(self, name: str) -> type[Any]:
        cls: type[Any] = self.store.types[self.resolve(name)]
        return cls

    # --- wire format ---------------------------------------------------------------------------
    def serialize(self, msg: Any) -> bytes:
        """CDR bytes, as ROS 2 sends them. A message that ends in a large byte array (an
        Image, a CompressedImage) is serialized without its array, which is then joined on:
        one copy of the pixels, not rosbags' two."""
        name = msg.__msgtype__
        tail = self._byte_tail(name)
        if tail is not None:
            array = getattr(msg, tail)
            if isinstance(array, np.ndarray) and array.dtype == np.uint8 and array.size > 4096:
                head = self.store.serialize_cdr(replace(msg, **{tail: _EMPTY_BYTES}), name)
                # The head ends with the array's length, 0: put the real one there.
                pixels = np.ascontiguousarray(array).reshape(-1)
                return b"".join((head[:-4], struct.pack("<I", pixels.size), pixels.data))
        return bytes(self.store.serialize_cdr(msg, name))

    def ros1_parts(self, msg: Any, name: str) -> tuple[bytes | memoryview, ...]:
        """ROS 1 bytes of ``msg`` (type ``name``, a store name) as parts to send in turn: a
        large string or byte array at its end is not copied into one buffer with the rest."""
        return self._ros1.parts(msg, name)

    def ros1_reader(
        self, name: str, *, borrowed: bool = False
    ) -> Callable[[bytes | memoryview], Any]:
        """Messages of type ``name`` (a store name) from their ROS 1 bytes: rosbags'
        deserializer looked up once, for a connection's every message (``SerdeError``, or
        the ``struct.error`` / ``UnicodeDecodeError`` of bad bytes, when they are not one).
        ``borrowed``: the bytes are reused once read (a socket's buffer); a type whose
        messages would keep views of them (numpy arrays) is then read from a copy."""
        msgdef = self.store.get_msgdef(name)
        read, cls, store = msgdef.deserialize_ros1, msgdef.cls, self.store
        copy = borrowed and holds_views(store, name)

        def message(data: bytes | memoryview) -> Any:
            if copy:
                data = bytes(data)
            msg, end = read(data, 0, cls, store)
            if end != len(data):
                text = f"{len(data)} bytes for a {short(name)} of {end}"
                raise SerdeError(text)
            return msg

        return message

    def _byte_tail(self, name: str) -> str | None:
        """The last field of a message type when it is a ``uint8[]`` (else None)."""
        tail = self._ros1.tail(name)
        return tail[0] if tail is not None and tail[1] == "uint8[]" else None

    def prepare(self, name: str) -> None:
        """Make the serializers of message type ``name`` (and of the types in it) now: rosbags
        generates them on first use, milliseconds of work (tens on a busy machine) that
        would otherwise delay the first message sent or received."""
        if name not in self.store.fielddefs:
            name = self.resolve(name)
        self.store.get_msgdef(name)

    def deserialize(self, data: bytes | memoryview, name: str) -> Any:
        if name not in self.store.fielddefs:  # canonical names (the usual case) skip this
            name = self.resolve(name)
        return self.store.deserialize_cdr(
            bytes(data) if isinstance(data, memoryview) else data, name
        )


_SEQUENCE: Final = int(Nodetype.SEQUENCE)
_BASE: Final = Nodetype.BASE
_EMPTY_BYTES: Final = np.zeros(0, dtype=np.uint8)


@cache
def types() -> TypeRegistry:
    """The process-wide registry (built on first use: it costs a few milliseconds)."""
    return TypeRegistry()
