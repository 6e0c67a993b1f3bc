"""belvedere's actionlib for rospy scripts: ROS 1's Python ``actionlib`` API (action clients
and servers, simple and not) speaking actionlib's protocol on belvedere's graph, so it works
with ROS 1 action nodes and with :mod:`belvedere.graph`'s own action servers and clients.

Scripts import it as ``actionlib`` (``from actionlib import SimpleActionClient``); action
message classes come from the type store (``from move_base_msgs.msg import MoveBaseAction``).
"""

from belvedere.ros1.actionlib._client import (
    ActionClient,
    ClientGoalHandle,
    CommStateMachine,
    GoalManager,
)
from belvedere.ros1.actionlib._ids import GoalIDGenerator
from belvedere.ros1.actionlib._server import ActionServer, ServerGoalHandle, StatusTracker, nop_cb
from belvedere.ros1.actionlib._simple_client import SimpleActionClient
from belvedere.ros1.actionlib._simple_server import SimpleActionServer
from belvedere.ros1.actionlib._states import (
    ActionException,
    CommState,
    GoalID,
    GoalStatus,
    GoalStatusArray,
    SimpleGoalState,
    TerminalState,
    get_name_of_constant,
)

__all__ = [
    "ActionClient",
    "ActionException",
    "ActionServer",
    "ClientGoalHandle",
    "CommState",
    "CommStateMachine",
    "GoalID",
    "GoalIDGenerator",
    "GoalManager",
    "GoalStatus",
    "GoalStatusArray",
    "ServerGoalHandle",
    "SimpleActionClient",
    "SimpleActionServer",
    "SimpleGoalState",
    "StatusTracker",
    "TerminalState",
    "get_name_of_constant",
    "nop_cb",
]
