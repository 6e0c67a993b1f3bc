"""XML-RPC as ROS 1 speaks it: a threaded server for the master's and the slave's APIs, and
a client with a timeout.

Python's XML-RPC parses with expat and never resolves external entities or fetches DTDs, so
a request cannot make the server read a file or touch the network."""

from __future__ import annotations

import http.client
import socketserver
import threading
import xmlrpc.client
import xmlrpc.server
from collections.abc import Callable
from typing import Any

__all__ = ["XmlRpcServer", "request_path", "server_proxy"]

_request = threading.local()


def request_path() -> str:
    """The path the request being answered (on this thread) was posted to: one server can
    stand for several ROS 1 nodes, each with its own URI."""
    return str(getattr(_request, "path", "/"))


class _Server(socketserver.ThreadingMixIn, xmlrpc.server.SimpleXMLRPCServer):
    daemon_threads = True
    allow_reuse_address = True


class _Quiet(xmlrpc.server.SimpleXMLRPCRequestHandler):
    rpc_paths = ()  # ROS 1 clients post to "/" and to "/RPC2" alike

    def log_message(self, format: str, *args: Any) -> None:
        pass

    def do_POST(self) -> None:  # noqa: N802 (http.server's name)
        _request.path = self.path  # each request has its own thread (ThreadingMixIn)
        super().do_POST()


class XmlRpcServer:
    """Serve ``dispatch(method, params)`` on ``host``:``port`` (0: a free port)."""

    def __init__(
        self, host: str, port: int, dispatch: Callable[[str, tuple[Any, ...]], Any]
    ) -> None:
        self._server = _Server(
            (host, port), requestHandler=_Quiet, allow_none=False, logRequests=False
        )
        self._server.register_instance(_Instance(dispatch))
        # rospy unregisters all of a node's topics at its end in one system.multicall
        self._server.register_multicall_functions()
        self.host = host
        self.port = int(self._server.server_address[1])
        self.uri = f"http://{host}:{self.port}/"
        self._thread = threading.Thread(
            target=self._server.serve_forever, name="belvedere-xmlrpc", daemon=True
        )
        self._thread.start()

    def close(self) -> None:
        self._server.shutdown()
        self._server.server_close()


class _Instance:
    def __init__(self, dispatch: Callable[[str, tuple[Any, ...]], Any]) -> None:
        self._dispatch_to = dispatch

    def _dispatch(self, method: str, params: tuple[Any, ...]) -> Any:
        return self._dispatch_to(method, params)


class _TimeoutTransport(xmlrpc.client.Transport):
    def __init__(self, timeout: float) -> None:
        super().__init__()
        self._timeout = timeout

    def make_connection(self, host: Any) -> http.client.HTTPConnection:
        connection = super().make_connection(host)
        connection.timeout = self._timeout
        return connection


def server_proxy(uri: str, timeout: float = 10.0) -> xmlrpc.client.ServerProxy:
    return xmlrpc.client.ServerProxy(uri, transport=_TimeoutTransport(timeout), allow_none=False)
