"""Services across the bridge: a ROS 1 call of a graph service arrives on the TCPROS port
(``rosrpc://``) and is made on the graph; a ROS 1 program's service is offered on the graph,
its type asked of its server with a probe as rosservice does, each call a one-shot
connection as rospy's default."""

from __future__ import annotations

import logging
import socket
import threading
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.graph import Graph, Node
from belvedere.msgs import ros1_name, types
from belvedere.ros1._spec import service_md5
from belvedere.ros1wire._master import MasterSide, Registrations
from belvedere.ros1wire._tcpros import (
    TcprosError,
    read_frame,
    read_header,
    read_service_reply,
    write_frame,
    write_header,
)

__all__ = ["ServiceSide"]

logger = logging.getLogger("belvedere.ros1wire")


class ServiceSide:
    """The bridge's services (a mixin of :class:`~belvedere.ros1wire._bridge.Ros1Bridge`)."""

    graph: Graph
    node: Node
    master: MasterSide
    caller_id: str
    _stop: threading.Event
    _probed: set[tuple[str, str]]
    _offered: dict[str, Any]

    def graph_state(self) -> Registrations:
        raise NotImplementedError

    def _reconcile_services(self, state: Registrations) -> None:
        """Offer each ROS 1 service on the graph (its type asked of the server with a
        probe, as rosservice does), and withdraw those gone."""
        ros1 = {
            name: next(iter(providers.values()))
            for name, providers in self.master.ros1_view().services.items()
            if providers
        }
        for name in [n for n in self._offered if n not in ros1]:
            server = self._offered.pop(name)
            self.graph.executor.post(server.unregister)
        for name, uri in ros1.items():
            if name in self._offered or (name, uri) in self._probed or name in state.services:
                continue
            self._probed.add((name, uri))
            threading.Thread(
                target=self._offer_service,
                args=(name, uri),
                name="belvedere-tcpros-probe",
                daemon=True,
            ).start()

    def _offer_service(self, name: str, uri: str) -> None:
        try:
            header = _service_header(
                uri, {"callerid": self.caller_id, "service": name, "md5sum": "*", "probe": "1"}
            )
            srv_type = types().resolve_service(header["type"])
        except (OSError, TcprosError, BelvedereError, KeyError, ValueError) as err:
            # roscpp's own logger services and services of types only their package
            # defines (a service's header carries no definition to learn from)
            text = err.message if isinstance(err, BelvedereError) else str(err)
            logger.debug("ros1: cannot offer %s on the graph: %s", name, text)
            return

        def forward(request: Any) -> Any:
            return self._call_ros1(name, uri, srv_type, request)

        def offer() -> None:
            if name not in self._offered and not self._stop.is_set():
                self._offered[name] = self.node.service(name, srv_type, forward, threaded=True)

        self.graph.executor.post(offer)

    def _call_ros1(self, name: str, uri: str, srv_type: str, request: Any) -> Any:
        """One call of a ROS 1 service (a one-shot connection, as rospy's default)."""
        store = types().store
        host, port = _rosrpc_address(uri)
        with socket.create_connection((host, port), timeout=30.0) as sock:
            write_header(
                sock,
                {"callerid": self.caller_id, "service": name, "md5sum": service_md5(srv_type)},
            )
            header = read_header(sock)
            if "error" in header:
                raise TcprosError(header["error"])
            write_frame(sock, store.serialize_ros1(request, f"{srv_type}_Request"))
            ok, data = read_service_reply(sock)
        if not ok:
            msg = f"service [{name}] responded with an error: {data.decode(errors='replace')}"
            raise BelvedereError(msg)
        return store.deserialize_ros1(data, f"{srv_type}_Response")

    def _serve_service(self, sock: socket.socket, header: dict[str, str]) -> None:
        name, caller = header["service"], header.get("callerid", "")
        providers = self.graph_state().services.get(name)
        if not providers:
            write_header(sock, {"error": f"no service [{name}] on the graph"})
            return
        srv_type = next(iter(providers.values()))
        md5 = service_md5(srv_type)
        wanted = header.get("md5sum", "*")
        if wanted not in ("*", md5):
            write_header(
                sock,
                {"error": f"request from [{caller}]: md5sums do not match: [{wanted}] vs. [{md5}]"},
            )
            return
        ros1 = ros1_name(srv_type).replace("/srv/", "/")
        write_header(
            sock,
            {
                "callerid": sorted(providers)[0],
                "md5sum": md5,
                "request_type": f"{ros1}Request",
                "response_type": f"{ros1}Response",
                "type": ros1,
            },
        )
        if header.get("probe") == "1":
            return
        store = types().store
        while not self._stop.is_set():
            try:
                data = read_frame(sock)
            except TcprosError:
                return  # the client is done (a one-shot call ends so)
            try:
                request = store.deserialize_ros1(data, f"{srv_type}_Request")
                response = self.node.call_service(name, srv_type, request, timeout=30.0)
                reply = bytes(store.serialize_ros1(response, f"{srv_type}_Response"))
                sock.sendall(b"\x01")
                write_frame(sock, reply)
            except Exception as err:  # noqa: BLE001 (the handler's failure is the caller's answer)
                text = err.message if isinstance(err, BelvedereError) else str(err)
                sock.sendall(b"\x00")
                write_frame(sock, text.encode())
            if header.get("persistent") != "1":
                return


def _rosrpc_address(uri: str) -> tuple[str, int]:
    """``rosrpc://host:port`` → (host, port)."""
    rest = uri.removeprefix("rosrpc://").rstrip("/")
    host, _, port = rest.rpartition(":")
    return host, int(port)


def _service_header(uri: str, fields: dict[str, str]) -> dict[str, str]:
    """A ROS 1 service server's answer to ``fields`` (a probe), on a connection of its own."""
    with socket.create_connection(_rosrpc_address(uri), timeout=10.0) as sock:
        write_header(sock, fields)
        header = read_header(sock)
    if "error" in header:
        raise TcprosError(header["error"])
    return header
