"""rospy's ``Service``, ``ServiceProxy`` and ``wait_for_service`` over belvedere's graph,
with rospy's rules for handler results and its error texts."""

from __future__ import annotations

import sys
import time
import traceback
from typing import Any

from belvedere.errors import BelvedereError
from belvedere.graph import ServiceFailedError, ServiceServer, ServiceUnavailableError
from belvedere.ros1._classes import from_store, to_store
from belvedere.ros1._message import Message
from belvedere.ros1.rospy import _state
from belvedere.ros1.rospy._exceptions import (
    ROSException,
    ROSInterruptException,
    ROSSerializationException,
    ServiceException,
)
from belvedere.ros1.rospy._topics import args_kwds_to_message

__all__ = ["Service", "ServiceProxy", "wait_for_service"]

_CALL_TIMEOUT = 3600.0
"""rospy's calls wait as long as the handler takes; this bounds a lost server."""


def _service_type(service_class: Any) -> str:
    kind = getattr(service_class, "_type", None)
    if not kind or not hasattr(service_class, "_request_class"):
        msg = f"{service_class!r} is not a service class"
        raise ValueError(msg)
    return str(kind)


def _to_response(response: Any, response_class: type[Message]) -> Message:
    """A handler's return value as a response, by rospy's rules: the response itself, a
    dict of fields, a tuple/list of all fields, or a single value for a one-field response."""
    if isinstance(response, Message) and response._type == response_class._type:
        return response
    if type(response) is dict:
        try:
            return response_class(**response)
        except AttributeError as err:
            msg = f"handler returned invalid value: {err}"
            raise ServiceException(msg) from None
    if response is None:
        msg = "service handler returned None"
        raise ServiceException(msg)
    if type(response) not in (list, tuple):
        try:
            return response_class(response)
        except TypeError as err:
            msg = f"handler returned invalid value: {err}"
            raise ServiceException(msg) from None
    try:
        return response_class(*response)
    except TypeError as err:
        msg = f"handler returned wrong number of values: {err}"
        raise ServiceException(msg) from None


def _default_error_handler(err: Exception, exc_type: Any, exc_value: Any, tb: Any) -> None:
    from belvedere.ros1.rospy._logging import ERROR, log

    lines = traceback.format_exception(exc_type, exc_value, tb)
    log(ERROR, "Error processing request: %s\n%s", (err, lines), depth=2)


class Service:
    """rospy.Service: answers requests with ``handler(request)``, each on its own thread."""

    def __init__(
        self,
        name: str,
        service_class: Any,
        handler: Any,
        buff_size: int = 65536,
        error_handler: Any = None,
    ) -> None:
        if not name or not isinstance(name, str):
            msg = "service name is not a non-empty string"
            raise ValueError(msg)
        self.service_class = service_class
        self.request_class: type[Message] = service_class._request_class
        self.response_class: type[Message] = service_class._response_class
        self.handler = handler
        self.error_handler = error_handler or _default_error_handler
        runtime = _state.required()
        self.resolved_name = runtime.node.resolve(name)
        self._server: ServiceServer | None = None

        def offer() -> None:
            self._server = runtime.node.service(
                self.resolved_name, _service_type(service_class), self._handle, threaded=True
            )

        try:
            runtime.run_on_executor(offer)
        except BelvedereError as err:
            raise ServiceException(err.message) from None

    def _handle(self, request: Any) -> Any:
        try:
            response = _to_response(self.handler(from_store(request)), self.response_class)
            return to_store(response)
        except ServiceException as err:
            raise ServiceFailedError(
                self.resolved_name, f"service cannot process request: {err}"
            ) from None
        except Exception as err:  # noqa: BLE001 (the caller is told, as rospy tells it)
            self.error_handler(err, *sys.exc_info())
            raise ServiceFailedError(
                self.resolved_name, f"error processing request: {err}"
            ) from None

    def shutdown(self, reason: str = "") -> None:
        server = self._server
        runtime = _state.current()
        if server is not None and runtime is not None:
            runtime.run_on_executor(lambda: runtime.graph.remove_service(server))
        self._server = None

    unregister = shutdown

    def spin(self) -> None:
        from belvedere.ros1.rospy._client import spin

        spin()


def _offered(name: str) -> bool:
    runtime = _state.required()
    if name in runtime.graph.services:
        return True
    transport = runtime.transport
    return transport is not None and transport.service_offered(name, timeout=0.5)


def wait_for_service(service: str, timeout: float | None = None) -> None:
    """Wait until ``service`` is offered (at most ``timeout`` wall seconds)."""
    resolved = _state.resolve(service)
    if timeout == 0.0:
        msg = "timeout must be non-zero"
        raise ValueError(msg)
    deadline = None if timeout is None else time.monotonic() + timeout
    stop = _state.shutdown_event()
    while not stop.is_set():
        if _offered(resolved):
            return
        if deadline is not None and time.monotonic() >= deadline:
            msg = f"timeout exceeded while waiting for service {resolved}"
            raise ROSException(msg)
        stop.wait(0.1 if deadline is None else max(0.0, min(0.1, deadline - time.monotonic())))
    msg = "rospy shutdown"
    raise ROSInterruptException(msg)


class ServiceProxy:
    """rospy.ServiceProxy: call with a request, its fields, or keywords."""

    def __init__(
        self, name: str, service_class: Any, persistent: bool = False, headers: Any = None
    ) -> None:
        self.service_class = service_class
        self.type = _service_type(service_class)
        self.request_class: type[Message] = service_class._request_class
        self.response_class: type[Message] = service_class._response_class
        self.resolved_name = _state.resolve(name)
        self.persistent = persistent

    def wait_for_service(self, timeout: float | None = None) -> None:
        wait_for_service(self.resolved_name, timeout)

    def __call__(self, *args: Any, **kwds: Any) -> Any:
        return self.call(*args, **kwds)

    def call(self, *args: Any, **kwds: Any) -> Any:
        request = args_kwds_to_message(self.request_class, args, kwds)
        if not isinstance(request, Message) or request._type != self.request_class._type:
            msg = "request object is not a valid request message instance"
            raise TypeError(msg)
        runtime = _state.required()
        try:
            data = to_store(request)
        except (BelvedereError, TypeError, ValueError, AttributeError) as err:
            raise ROSSerializationException(str(err)) from None
        try:
            response = runtime.node.call_service(
                self.resolved_name, self.type, data, timeout=_CALL_TIMEOUT
            )
        except ServiceUnavailableError:
            msg = f"service [{self.resolved_name}] unavailable"
            raise ServiceException(msg) from None
        except ServiceFailedError as err:
            why = err.reason.encode()
            text = f"service [{self.resolved_name}] responded with an error: {why!r}"
            raise ServiceException(text) from None
        return from_store(response)

    def close(self) -> None:
        """Nothing to close: calls are not connections here."""
