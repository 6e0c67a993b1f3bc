"""tf's ``Transformer``, ``TransformerROS`` and ``TransformListener``: ROS 1's tf API over a
tf2_ros ``Buffer``, as tf has been since tf2 (frames' leading ``/`` stripped, results as
``([x, y, z], [x, y, z, w])``, failures as ``tf.Exception`` — tf2's ``TransformException``)."""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
import yaml

from belvedere.ros1 import message_class, rospy, tf2_ros
from belvedere.ros1 import transformations as tft

__all__ = ["TransformListener", "Transformer", "TransformerROS"]


def _strip(frame: str) -> str:
    return frame[1:] if frame.startswith("/") else frame


def _pair(msg: Any) -> tuple[list[float], list[float]]:
    t, r = msg.transform.translation, msg.transform.rotation
    return [t.x, t.y, t.z], [r.x, r.y, r.z, r.w]


class Transformer:
    """The frame tree and its lookups, filled with :meth:`setTransform` (a
    :class:`TransformListener` fills itself from ``/tf``)."""

    def __init__(self, interpolate: bool = True, cache_time: Any = None) -> None:
        del interpolate  # tf2 always interpolates
        self._buffer = tf2_ros.Buffer(cache_time, debug=False)
        self._using_dedicated_thread = False

    def allFramesAsDot(self, current_time: Any = None) -> str:  # noqa: N802 (tf's name)
        if current_time:
            return self._buffer._allFramesAsDot(current_time)
        return self._buffer._allFramesAsDot()

    def allFramesAsString(self) -> str:  # noqa: N802
        return self._buffer.all_frames_as_string()

    def setTransform(self, transform: Any, authority: str = "default_authority") -> None:  # noqa: N802
        self._buffer.set_transform(transform, authority)

    def canTransform(self, target_frame: str, source_frame: str, time: Any) -> Any:  # noqa: N802
        return self._buffer.can_transform(_strip(target_frame), _strip(source_frame), time)

    def canTransformFull(  # noqa: N802
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
    ) -> Any:
        return self._buffer.can_transform_full(
            _strip(target_frame),
            target_time,
            _strip(source_frame),
            source_time,
            _strip(fixed_frame),
        )

    def _check_waiting(self) -> None:
        if not self._using_dedicated_thread:
            msg = (
                "cannot wait for transform without a dedicated thread that listens to incoming "
                "TF messages"
            )
            raise tf2_ros.TransformException(msg)

    def waitForTransform(  # noqa: N802
        self,
        target_frame: str,
        source_frame: str,
        time: Any,
        timeout: Any,
        polling_sleep_duration: Any = None,
    ) -> None:
        """Return once the transform can be looked up; raise ``tf.Exception`` (with tf2's
        reason) when ``timeout`` (a ``rospy.Duration``) passes first."""
        self._check_waiting()
        ok, why = self._buffer.can_transform(
            _strip(target_frame), _strip(source_frame), time, timeout, return_debug_tuple=True
        )
        if not ok:
            msg = why or f'no such transformation: "{source_frame}" -> "{target_frame}"'
            raise tf2_ros.TransformException(msg)

    def waitForTransformFull(  # noqa: N802
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
        timeout: Any,
        polling_sleep_duration: Any = None,
    ) -> None:
        self._check_waiting()
        ok, why = self._buffer.can_transform_full(
            _strip(target_frame),
            target_time,
            _strip(source_frame),
            source_time,
            _strip(fixed_frame),
            timeout,
            return_debug_tuple=True,
        )
        if not ok:
            msg = why or f'no such transformation: "{source_frame}" -> "{target_frame}"'
            raise tf2_ros.TransformException(msg)

    def clear(self) -> None:
        self._buffer.clear()

    def frameExists(self, frame_id: str) -> bool:  # noqa: N802
        """Whether ``frame_id`` is some transform's child (tf's rule: a root is not)."""
        return frame_id in self.getFrameStrings()

    def getFrameStrings(self) -> list[str]:  # noqa: N802
        """The frames that are some transform's child."""
        data = yaml.safe_load(self._buffer.all_frames_as_yaml()) or {}
        return list(data)

    def getLatestCommonTime(self, source_frame: str, dest_frame: str) -> Any:  # noqa: N802
        return self._buffer.get_latest_common_time(_strip(source_frame), _strip(dest_frame))

    def lookupTransform(  # noqa: N802
        self, target_frame: str, source_frame: str, time: Any
    ) -> tuple[list[float], list[float]]:
        """``([x, y, z], [x, y, z, w])``: ``source_frame``'s pose in ``target_frame`` at
        ``time`` (``rospy.Time(0)``: the latest)."""
        return _pair(
            self._buffer.lookup_transform(_strip(target_frame), _strip(source_frame), time)
        )

    def lookupTransformFull(  # noqa: N802
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
    ) -> tuple[list[float], list[float]]:
        return _pair(
            self._buffer.lookup_transform_full(
                _strip(target_frame),
                target_time,
                _strip(source_frame),
                source_time,
                _strip(fixed_frame),
            )
        )

    def lookupTwist(  # noqa: N802
        self, tracking_frame: str, observation_frame: str, time: Any, averaging_interval: Any
    ) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        return self.lookupTwistFull(
            tracking_frame,
            observation_frame,
            observation_frame,
            (0, 0, 0),
            tracking_frame,
            time,
            averaging_interval,
        )

    def lookupTwistFull(  # noqa: N802
        self,
        tracking_frame: str,
        observation_frame: str,
        reference_frame: str,
        ref_point: Any,
        reference_point_frame: str,
        time: Any,
        averaging_interval: Any,
    ) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """The velocity (linear, angular) of ``tracking_frame`` seen from
        ``observation_frame``, in ``reference_frame``, from two lookups
        ``averaging_interval`` apart around ``time``."""
        latest = self.getLatestCommonTime(observation_frame, tracking_frame)
        target_time = time or latest
        end = min(target_time + rospy.Duration(0.5 * averaging_interval.to_sec()), latest)
        start = max(rospy.Time(0.0001) + averaging_interval, end) - averaging_interval
        dt = (end - start).to_sec()
        t0, q0 = self.lookupTransform(observation_frame, tracking_frame, start)
        t1, q1 = self.lookupTransform(observation_frame, tracking_frame, end)
        turn = np.linalg.inv(tft.quaternion_matrix(q0)) @ tft.quaternion_matrix(q1)
        angle, axis, _ = tft.rotation_from_matrix(turn)
        linear = np.array([(t1[i] - t0[i]) / dt for i in range(3)])
        angular = np.array([axis[i] * angle / dt for i in range(3)])
        # into the reference frame, about the tracking frame's origin
        ref_t, ref_q = self.lookupTransform(reference_frame, tracking_frame, target_time)
        r = tft.quaternion_matrix(ref_q)[:3, :3]
        rot = r @ angular
        vel = r @ linear + np.cross(ref_t, rot)
        # then about the reference point
        origin = np.array((ref_t[0], ref_t[1], ref_t[2], 1.0))
        point_t, point_q = self.lookupTransform(reference_frame, reference_point_frame, target_time)
        moved = (tft.translation_matrix(point_t) @ tft.quaternion_matrix(point_q)) @ origin
        # tf adds the dot product (a number) to each component, not a cross product: kept,
        # so that scripts get tf's numbers
        vel += float(np.dot(rot, (moved - origin)[:3]))
        return (vel[0], vel[1], vel[2]), (rot[0], rot[1], rot[2])

    def setUsingDedicatedThread(self, value: bool) -> None:  # noqa: N802
        self._using_dedicated_thread = value

    def getTFPrefix(self) -> str:  # noqa: N802
        """Always ``""``: tf2 has no frame prefixes."""
        return ""


class TransformerROS(Transformer):
    """A :class:`Transformer` that transforms ``geometry_msgs`` messages too."""

    def asMatrix(self, target_frame: str, hdr: Any) -> npt.NDArray[np.float64]:  # noqa: N802
        """The 4x4 matrix taking ``hdr.frame_id`` coordinates at ``hdr.stamp`` into
        ``target_frame``'s."""
        translation, rotation = self.lookupTransform(target_frame, hdr.frame_id, hdr.stamp)
        return self.fromTranslationRotation(translation, rotation)

    def fromTranslationRotation(  # noqa: N802
        self, translation: Any, rotation: Any
    ) -> npt.NDArray[np.float64]:
        matrix: npt.NDArray[np.float64] = np.dot(
            tft.translation_matrix(translation), tft.quaternion_matrix(rotation)
        )
        return matrix

    @staticmethod
    def _stamped(kind: str, target_frame: str, header: Any) -> Any:
        out: Any = message_class(f"geometry_msgs/{kind}")()
        out.header.stamp = header.stamp
        out.header.frame_id = target_frame
        return out

    def transformPoint(self, target_frame: str, ps: Any) -> Any:  # noqa: N802
        """A ``PointStamped`` in ``target_frame``."""
        m = self.asMatrix(target_frame, ps.header)
        x, y, z = np.dot(m, np.array([ps.point.x, ps.point.y, ps.point.z, 1.0]))[:3]
        out = self._stamped("PointStamped", target_frame, ps.header)
        out.point = message_class("geometry_msgs/Point")(x, y, z)
        return out

    def transformVector3(self, target_frame: str, v3s: Any) -> Any:  # noqa: N802
        """A ``Vector3Stamped`` in ``target_frame`` (rotated only)."""
        m = self.asMatrix(target_frame, v3s.header)
        m[:3, 3] = 0.0
        x, y, z = np.dot(m, np.array([v3s.vector.x, v3s.vector.y, v3s.vector.z, 1.0]))[:3]
        out = self._stamped("Vector3Stamped", target_frame, v3s.header)
        out.vector = message_class("geometry_msgs/Vector3")(x, y, z)
        return out

    def transformQuaternion(self, target_frame: str, ps: Any) -> Any:  # noqa: N802
        """A ``QuaternionStamped`` in ``target_frame``."""
        m = self.asMatrix(target_frame, ps.header)
        q = ps.quaternion
        turned = np.dot(m, tft.quaternion_matrix((q.x, q.y, q.z, q.w)))
        out = self._stamped("QuaternionStamped", target_frame, ps.header)
        out.quaternion = message_class("geometry_msgs/Quaternion")(
            *tft.quaternion_from_matrix(turned)
        )
        return out

    def transformPose(self, target_frame: str, ps: Any) -> Any:  # noqa: N802
        """A ``PoseStamped`` in ``target_frame``."""
        m = self.asMatrix(target_frame, ps.header)
        p, q = ps.pose.position, ps.pose.orientation
        pose = np.dot(
            tft.translation_matrix((p.x, p.y, p.z)), tft.quaternion_matrix((q.x, q.y, q.z, q.w))
        )
        moved = np.dot(m, pose)
        out = self._stamped("PoseStamped", target_frame, ps.header)
        out.pose = message_class("geometry_msgs/Pose")(
            message_class("geometry_msgs/Point")(*tft.translation_from_matrix(moved)[:3]),
            message_class("geometry_msgs/Quaternion")(*tft.quaternion_from_matrix(moved)),
        )
        return out

    def transformPointCloud(self, target_frame: str, point_cloud: Any) -> Any:  # noqa: N802
        """A ``sensor_msgs/PointCloud`` in ``target_frame`` (channels kept)."""
        out: Any = message_class("sensor_msgs/PointCloud")()
        out.header.stamp = point_cloud.header.stamp
        out.header.frame_id = target_frame
        out.channels = point_cloud.channels
        m = self.asMatrix(target_frame, point_cloud.header)
        point = message_class("geometry_msgs/Point")
        out.points = [
            point(*np.dot(m, np.array([p.x, p.y, p.z, 1.0]))[:3]) for p in point_cloud.points
        ]
        return out


class TransformListener(TransformerROS):
    """A :class:`TransformerROS` kept up to date from ``/tf`` and ``/tf_static`` (create it
    after ``rospy.init_node``); :meth:`waitForTransform` works with it."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._listener = tf2_ros.TransformListener(self._buffer)
        self.setUsingDedicatedThread(True)
