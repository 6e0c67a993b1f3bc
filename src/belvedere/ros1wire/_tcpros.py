"""TCPROS framing: connection headers and length-prefixed messages over a socket.

A header is a 4-byte little-endian length, then fields each a 4-byte length and
``key=value`` bytes; a message is a 4-byte length and its ROS 1 bytes. A service response
is a byte (1: ok, 0: failed) before its length and bytes (a failed call's bytes are the
error's text)."""

from __future__ import annotations

import socket
import struct
from collections.abc import Iterable, Iterator
from typing import Final

__all__ = [
    "MAX_HEADER",
    "TcprosError",
    "decode_header",
    "encode_header",
    "read_frame",
    "read_frames",
    "read_header",
    "read_service_reply",
    "write_frame",
    "write_frames",
    "write_header",
]

_LENGTH: Final = struct.Struct("<I")
MAX_HEADER: Final = 1 << 20
"""A header longer than this is not a header (a stray client, a port scan)."""
MAX_MESSAGE: Final = 1 << 30
"""roscpp refuses messages of a gigabyte or more."""


class TcprosError(Exception):
    """A connection that broke, or did not speak TCPROS."""


def encode_header(fields: dict[str, str]) -> bytes:
    parts = []
    for key, value in fields.items():
        item = f"{key}={value}".encode()
        parts.append(_LENGTH.pack(len(item)) + item)
    body = b"".join(parts)
    return _LENGTH.pack(len(body)) + body


def decode_header(body: bytes) -> dict[str, str]:
    """The fields of a header's body (without its leading length)."""
    fields: dict[str, str] = {}
    at = 0
    while at < len(body):
        if at + 4 > len(body):
            msg = "a connection header ends inside a field's length"
            raise TcprosError(msg)
        (size,) = _LENGTH.unpack_from(body, at)
        at += 4
        if at + size > len(body):
            msg = "a connection header's field runs past its end"
            raise TcprosError(msg)
        key, eq, value = body[at : at + size].decode("utf-8", errors="replace").partition("=")
        if not eq:
            msg = f"a connection header's field has no '=': {key[:60]!r}"
            raise TcprosError(msg)
        fields[key] = value
        at += size
    return fields


def _read_exactly(sock: socket.socket, size: int) -> bytes:
    if size == 0:
        return b""
    buffer = bytearray(size)
    view = memoryview(buffer)
    got = 0
    while got < size:
        n = sock.recv_into(view[got:], size - got)
        if n == 0:
            msg = "the connection closed"
            raise TcprosError(msg)
        got += n
    return bytes(buffer)


def _read_length(sock: socket.socket, limit: int, what: str) -> int:
    (size,) = _LENGTH.unpack(_read_exactly(sock, 4))
    if size > limit:
        msg = f"a {what} of {size} bytes (more than {limit})"
        raise TcprosError(msg)
    return int(size)


def read_header(sock: socket.socket) -> dict[str, str]:
    return decode_header(_read_exactly(sock, _read_length(sock, MAX_HEADER, "header")))


def write_header(sock: socket.socket, fields: dict[str, str]) -> None:
    sock.sendall(encode_header(fields))


def read_frames(sock: socket.socket) -> Iterator[bytes]:
    """A connection's messages until it closes (TcprosError), read through a buffer: many
    small messages cost one system call, not two each."""
    reader = sock.makefile("rb", buffering=1 << 16)
    try:
        while True:
            head = reader.read(4)
            if len(head) < 4:
                msg = "the connection closed"
                raise TcprosError(msg)
            (size,) = _LENGTH.unpack(head)
            if size > MAX_MESSAGE:
                msg = f"a message of {size} bytes (more than {MAX_MESSAGE})"
                raise TcprosError(msg)
            data = reader.read(size)
            if len(data) < size:
                msg = "the connection closed"
                raise TcprosError(msg)
            yield data
    finally:
        reader.close()


def read_frame(sock: socket.socket) -> bytes:
    return _read_exactly(sock, _read_length(sock, MAX_MESSAGE, "message"))


_JOIN_BELOW: Final = 1 << 16
"""Frames smaller than this go in one send (one packet with TCP_NODELAY); larger ones are
not copied to join their length on."""


def write_frame(sock: socket.socket, data: bytes | memoryview) -> None:
    length = _LENGTH.pack(len(data))
    if len(data) < _JOIN_BELOW:
        sock.sendall(length + bytes(data))
    else:
        sock.sendall(length)
        sock.sendall(data)


def read_service_reply(sock: socket.socket) -> tuple[bool, bytes]:
    """(ok, the response's bytes or the error's text)."""
    ok = _read_exactly(sock, 1) != b"\x00"
    return ok, read_frame(sock)


def write_frames(sock: socket.socket, frames: Iterable[bytes | memoryview]) -> None:
    """Several messages in as few sends as their sizes allow (small ones joined)."""
    joined = bytearray()
    for data in frames:
        if len(data) >= _JOIN_BELOW:
            if joined:
                sock.sendall(joined)
                joined.clear()
            write_frame(sock, data)
        else:
            joined += _LENGTH.pack(len(data))
            joined += data
    if joined:
        sock.sendall(joined)
