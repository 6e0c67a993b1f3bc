"""What every entry point shares below the command line: running a session, the clock
policy, joining a running graph, hosting user scripts, the Foxglove bridge beside a graph.

``belvedere``'s verbs (:mod:`belvedere.cli`) parse their arguments into the plain values
these take (:class:`SessionOptions`, :class:`GraphAddress`, :class:`BridgeOptions`, …) and
print; anything else that starts runs (a batch or test runner, a ROS 1 master) calls the
same functions.

- Joining: :func:`open_transport`, :func:`join_graph` (a graph on the running one, in its
  time), :func:`open_tool` (a tool's node), :func:`holds_parameters`.
- The clock: a graph has one; the process that makes the graph keeps its time
  (:func:`open_clock_transport`, :func:`refuse_second_clock`).
- Sessions: :func:`run_session` (a launch configuration on one graph until it ends),
  :func:`run_launch` (roslaunch's way), :func:`rosrun` and :func:`run_alone` (an executable,
  a user's script), :func:`install_script` (``--pub``/``--echo``).
- Beside a graph: :func:`start_bridge` (Foxglove).
- Asking it (rosnode, rosservice info): :func:`known_node`, :func:`ping_node`,
  :func:`kill_nodes`, :func:`machines`, :func:`unreachable_nodes`, :func:`offered_service`;
  roswtf's checks, :func:`check_graph`.

Importing this package loads the graph's modules but neither the launch runtime, the nodes
nor the bridge: those load when a session starts one.
"""

from belvedere.runtime._bridge import BridgeOptions, start_bridge
from belvedere.runtime._clock import open_clock_transport, refuse_second_clock
from belvedere.runtime._graphtools import (
    Pong,
    kill_nodes,
    known_node,
    machines,
    offered_service,
    ping_node,
    unreachable_nodes,
)
from belvedere.runtime._join import (
    GraphAddress,
    Tool,
    holds_parameters,
    join_graph,
    join_ros_master,
    open_tool,
    open_transport,
    wait_for,
    wait_for_messages,
)
from belvedere.runtime._rosrun import HandOver, rosrun, run_alone
from belvedere.runtime._scripted import ScriptOptions, install_script
from belvedere.runtime._session import (
    SessionOptions,
    ViewerOptions,
    joins_running_graph,
    run_launch,
    run_session,
)
from belvedere.runtime._wtf import WtfReport, check_graph

__all__ = [
    "BridgeOptions",
    "GraphAddress",
    "HandOver",
    "Pong",
    "ScriptOptions",
    "SessionOptions",
    "Tool",
    "ViewerOptions",
    "WtfReport",
    "check_graph",
    "holds_parameters",
    "install_script",
    "join_graph",
    "join_ros_master",
    "joins_running_graph",
    "kill_nodes",
    "known_node",
    "machines",
    "offered_service",
    "open_clock_transport",
    "open_tool",
    "open_transport",
    "ping_node",
    "refuse_second_clock",
    "rosrun",
    "run_alone",
    "run_launch",
    "run_session",
    "start_bridge",
    "unreachable_nodes",
    "wait_for",
    "wait_for_messages",
]
