"""Foxglove: the graph's topics over Foxglove's WebSocket protocol.

:class:`FoxgloveBridge` joins a graph as a node and serves its topics to Foxglove (the app,
or anything speaking ``foxglove.sdk.v1``, the WebSocket protocol formerly named
``foxglove.websocket.v1``) through the ``foxglove-sdk`` package: every topic someone
publishes is a channel in ROS 1's encoding (``ros1``) with its full message definition as
the schema (``ros1msg``, the text ROS 1 bags carry); the graph is subscribed to a topic only
while a client subscribes to its channel; each message goes out stamped with the graph's
time at receipt (simulated time in a simulation), and that time is the server's time.
Clients may publish (Foxglove's Publish panel, in ``ros1`` or ``json``) and read and set the
graph's parameters.

Only this package imports ``foxglove``; without it, :class:`FoxgloveBridge` raises one
:class:`FoxgloveBridgeError` that says how to install it.
"""

from belvedere.foxglove._bridge import (
    DEFAULT_PORT,
    MESSAGE_ENCODING,
    SCHEMA_ENCODING,
    FoxgloveBridge,
    FoxgloveBridgeError,
    require_sdk,
    ros1_schema,
)

__all__ = [
    "DEFAULT_PORT",
    "MESSAGE_ENCODING",
    "SCHEMA_ENCODING",
    "FoxgloveBridge",
    "FoxgloveBridgeError",
    "require_sdk",
    "ros1_schema",
]
