"""The runtime graph: nodes, topics, parameters, services and time, as in ROS 1.

Everything that runs is a node on one graph. One executor runs every callback, timer and
simulation step in a defined order, in simulated or wall time. Inside a process messages pass
as objects; a transport (Zenoh) carries them, CDR-encoded, to other processes.
"""

from belvedere.graph._action import ActionClient, ActionServer, GoalHandle, GoalStatus
from belvedere.graph._endpoints import Publisher, SeqRule, ServiceServer, Subscription, Topic
from belvedere.graph._errors import GraphError, ServiceFailedError, ServiceUnavailableError
from belvedere.graph._executor import NS, Executor, Timer
from belvedere.graph._graph import Graph, Node, Rate, Transport, process_node_name
from belvedere.graph._hosts import (
    HostAccess,
    HostAccessError,
    check_token,
    endpoint_host,
    new_token,
)
from belvedere.graph._log import NodeLogger
from belvedere.graph._log_rows import SEVERITIES, LogFilter, LogRow, log_row
from belvedere.graph._names import RosArgs, did_you_mean, parse_ros_args, resolve_name
from belvedere.graph._names import validate as validate_name
from belvedere.graph._params import ParamError, ParamTree
from belvedere.graph._params import leaves as param_leaves
from belvedere.graph._rosparam import documents as param_documents
from belvedere.graph._rosparam import dump_text as param_dump_text
from belvedere.graph._rosparam import get_text as param_get_text
from belvedere.graph._rosparam import leaf_lines as param_leaf_lines
from belvedere.graph._rosparam import shown as param_shown
from belvedere.graph._topics import GraphTopics
from belvedere.graph._zenoh import ZenohTransport
from belvedere.graph._zenoh_discovery import GraphInfo
from belvedere.graph._zenoh_latch import LatchedOnce, Sent
from belvedere.graph._zenoh_session import (
    DEFAULT_ENDPOINT,
    MAX_DOMAIN,
    TransportError,
    check_domain,
    domain_endpoint,
    graph_running,
)

__all__ = [
    "DEFAULT_ENDPOINT",
    "MAX_DOMAIN",
    "NS",
    "SEVERITIES",
    "ActionClient",
    "ActionServer",
    "Executor",
    "GoalHandle",
    "GoalStatus",
    "Graph",
    "GraphError",
    "GraphInfo",
    "GraphTopics",
    "HostAccess",
    "HostAccessError",
    "LatchedOnce",
    "LogFilter",
    "LogRow",
    "Node",
    "NodeLogger",
    "ParamError",
    "ParamTree",
    "Publisher",
    "Rate",
    "RosArgs",
    "Sent",
    "SeqRule",
    "ServiceFailedError",
    "ServiceServer",
    "ServiceUnavailableError",
    "Subscription",
    "Timer",
    "Topic",
    "Transport",
    "TransportError",
    "ZenohTransport",
    "check_domain",
    "check_token",
    "did_you_mean",
    "domain_endpoint",
    "endpoint_host",
    "graph_running",
    "log_row",
    "new_token",
    "param_documents",
    "param_dump_text",
    "param_get_text",
    "param_leaf_lines",
    "param_leaves",
    "param_shown",
    "parse_ros_args",
    "process_node_name",
    "resolve_name",
    "validate_name",
]
