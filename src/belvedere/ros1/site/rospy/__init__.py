"""rospy, as belvedere provides it to the scripts it runs (belvedere.ros1.rospy)."""

from belvedere.ros1.rospy import *  # noqa: F403
from belvedere.ros1.rospy import __all__ as __all__

# As after a real `import rospy`, its submodules are attributes (rospy.exceptions.…).
from rospy import client as client
from rospy import core as core
from rospy import exceptions as exceptions
from rospy import names as names
from rospy import rostime as rostime
from rospy import service as service
from rospy import timer as timer
from rospy import topics as topics
