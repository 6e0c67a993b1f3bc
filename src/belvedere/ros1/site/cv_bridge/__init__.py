"""cv_bridge, as belvedere provides it to the scripts it runs: ``CvBridge`` between
``sensor_msgs/Image`` (or ``CompressedImage``) and OpenCV's numpy images, and
``CvBridgeError``, as ROS's vision_opencv has them (its encodings, conversions and error
texts: checked against Debian's python3-cv-bridge)."""

from cv_bridge.core import CvBridge, CvBridgeError

__all__ = ["CvBridge", "CvBridgeError"]
