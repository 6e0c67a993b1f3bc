"""Foxglove: the graph's topics over Foxglove's WebSocket protocol.

:class:`FoxgloveBridge` joins a graph as a node and serves its topics to Foxglove (the app,
or anything speaking ``foxglove.sdk.v1``, the WebSocket protocol formerly named
``foxglove.websocket.v1``), served here over ``websockets``: every topic someone
publishes is a channel in ROS 1's encoding (``ros1``) with its full message definition as
the schema (``ros1msg``, the text ROS 1 bags carry); the graph is subscribed to a topic only
while a client subscribes to its channel; each message goes out stamped with the graph's
time at receipt (simulated time in a simulation), and that time is the server's time.
Clients may publish (Foxglove's Publish panel, in ``ros1`` or ``json``) and read and set the
graph's parameters.

The server is ours rather than ``foxglove-sdk``'s because the SDK's server has no hook to
check a handshake: any web page could connect and drive the robot. Ours refuses foreign
origins and, off loopback, clients without the run's token (see :mod:`belvedere.access`),
and treats every client message as untrusted input (:mod:`._protocol`).
"""

from belvedere.foxglove._bridge import (
    DEFAULT_PORT,
    FOXGLOVE_APP,
    MESSAGE_ENCODING,
    SCHEMA_ENCODING,
    FoxgloveBridge,
    FoxgloveBridgeError,
    ros1_schema,
)

__all__ = [
    "DEFAULT_PORT",
    "FOXGLOVE_APP",
    "MESSAGE_ENCODING",
    "SCHEMA_ENCODING",
    "FoxgloveBridge",
    "FoxgloveBridgeError",
    "ros1_schema",
]
