"""ROS 1 on the wire: a master (XML-RPC Master and Parameter Server APIs) backed by the
graph, and a bridge that makes the graph's nodes ROS 1 nodes (slave API, TCPROS), so real
ROS 1 programs (rostopic, rospy and roscpp nodes, rosbag, rviz) and belvedere meet."""

from __future__ import annotations

from dataclasses import dataclass

from belvedere.graph import Graph
from belvedere.ros1wire._bridge import BRIDGE_NODE, Ros1Bridge
from belvedere.ros1wire._master import Master, Registrations
from belvedere.ros1wire._params import GraphParams
from belvedere.ros1wire._remote import RemoteMaster, RemoteMasterError
from belvedere.ros1wire._tcpros import TcprosError

__all__ = [
    "BRIDGE_NODE",
    "DEFAULT_PORT",
    "Master",
    "MasterHandle",
    "Registrations",
    "RemoteMasterError",
    "Ros1Bridge",
    "TcprosError",
    "join_master",
    "start_master",
]

DEFAULT_PORT = 11311


@dataclass
class MasterHandle:
    """A running master and the bridge that shows it the graph."""

    master: Master | RemoteMaster
    bridge: Ros1Bridge

    @property
    def uri(self) -> str:
        return self.master.uri

    def close(self) -> None:
        if isinstance(self.master, RemoteMaster):
            self.master.close()  # unregister while the bridge still answers
            self.bridge.close()
        else:
            self.bridge.close()
            self.master.close()


def start_master(graph: Graph, host: str = "127.0.0.1", port: int = DEFAULT_PORT) -> MasterHandle:
    """A ROS 1 master on ``host``:``port`` (0: a free port) for ``graph``'s domain. Raises
    OSError when the port is taken."""
    master = Master(GraphParams(graph), host, port)
    try:
        bridge = Ros1Bridge(graph, master, host)
    except BaseException:
        master.close()
        raise
    return MasterHandle(master, bridge)


def join_master(graph: Graph, uri: str) -> MasterHandle:
    """Join the running ROS 1 master at ``uri``: the graph's nodes register there as one ROS 1
    node, whose slave API and TCPROS ports are served on ``ROS_IP`` or ``ROS_HOSTNAME`` if
    set (as a ROS 1 node's), else on 127.0.0.1. Raises RemoteMasterError when the master does
    not answer."""
    import os

    master = RemoteMaster(uri)
    host = os.environ.get("ROS_IP") or os.environ.get("ROS_HOSTNAME") or "127.0.0.1"
    bridge = Ros1Bridge(graph, master, host)
    params = master.params()
    if isinstance(params, dict):
        for key, value in params.items():
            if not graph.params.has(f"/{key}"):
                graph.params.set(f"/{key}", value)
    return MasterHandle(master, bridge)
