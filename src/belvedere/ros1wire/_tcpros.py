"""TCPROS framing: connection headers and length-prefixed messages over a socket.

A header is a 4-byte little-endian length, then fields each a 4-byte length and
``key=value`` bytes; a message is a 4-byte length and its ROS 1 bytes. A service response
is a byte (1: ok, 0: failed) before its length and bytes (a failed call's bytes are the
error's text)."""

from __future__ import annotations

import socket
import struct
from collections.abc import Callable, Iterable, Sequence
from typing import Final, TypeVar

__all__ = [
    "MAX_HEADER",
    "FrameReader",
    "TcprosError",
    "decode_header",
    "encode_header",
    "read_frame",
    "read_header",
    "read_service_reply",
    "write_frame",
    "write_frames",
    "write_header",
]

T = TypeVar("T")

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


class FrameReader:
    """A connection's messages, read in large chunks: one ``recv`` brings every message the
    sender has written meanwhile (hundreds of small ones), which :meth:`batch` splits. A
    message larger than the chunk is read into a buffer of its own size, not copied again.

    :meth:`batch` hands each message to a reader as a view of the buffer, valid only during
    that call (the buffer is then reused): a deserializer that keeps views of its input (numpy
    arrays) must be given a copy."""

    def __init__(self, sock: socket.socket, chunk: int = 1 << 16) -> None:
        self._sock = sock
        self._buffer = bytearray(chunk)
        self._view = memoryview(self._buffer)
        self._start = 0
        """Where the first message not yet handed out begins in the buffer."""
        self._end = 0
        """Where the bytes received end."""

    def batch(self, read: Callable[[memoryview], T]) -> list[T]:
        """``read`` of every complete message received so far, waiting for at least one;
        TcprosError when the connection closes (or sends a length over :data:`MAX_MESSAGE`)."""
        while True:
            frames = self._split(read)
            if frames:
                return frames
            large = self._fill()
            if large is not None:
                return [read(memoryview(large))]

    def _split(self, read: Callable[[memoryview], T]) -> list[T]:
        frames: list[T] = []
        buffer, view, at, end = self._buffer, self._view, self._start, self._end
        unpack = _LENGTH.unpack_from
        try:
            while end - at >= 4:
                (size,) = unpack(buffer, at)
                if at + 4 + size > end:
                    break
                frames.append(read(view[at + 4 : at + 4 + size]))
                at += 4 + size
        finally:  # a message read raises: those before it are not read again
            self._start = at
        return frames

    def _fill(self) -> bytearray | None:
        """Receive more bytes after a message cut short (or none yet); a message too large
        for the buffer is read whole and returned."""
        start, end = self._start, self._end
        have = end - start
        if have >= 4:
            (size,) = _LENGTH.unpack_from(self._buffer, start)
            if size > MAX_MESSAGE:
                msg = f"a message of {size} bytes (more than {MAX_MESSAGE})"
                raise TcprosError(msg)
            if 4 + size > len(self._buffer):
                return self._read_large(size)
        if start > 0:  # the cut message moves to the front, making room behind it
            # (through a copy: the two ranges may overlap, which a slice assignment's memcpy
            # does not allow)
            self._buffer[:have] = bytes(self._view[start:end])
            self._start, self._end = 0, have
        got = self._sock.recv_into(self._view[self._end :])
        if got == 0:
            msg = "the connection closed"
            raise TcprosError(msg)
        self._end += got
        return None

    def _read_large(self, size: int) -> bytearray:
        """A message larger than the buffer: its bytes so far, and the rest read straight
        into a buffer of its size."""
        message = bytearray(size)
        have = self._end - self._start - 4
        message[:have] = self._view[self._start + 4 : self._end]
        self._start = self._end = 0
        view = memoryview(message)
        while have < size:
            got = self._sock.recv_into(view[have:])
            if got == 0:
                msg = "the connection closed"
                raise TcprosError(msg)
            have += got
        return message


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


def write_frames(sock: socket.socket, frames: Iterable[Sequence[bytes | memoryview]]) -> None:
    """Several messages, each given as parts to send in turn (its ROS 1 bytes cut where a
    large field begins), in as few system calls as their sizes allow: small ones joined into
    one send, a large one's parts handed to ``sendmsg`` as they are (never copied here)."""
    joined = bytearray()
    pack = _LENGTH.pack
    for parts in frames:
        if len(parts) == 1:  # most messages: one part, small
            size = len(parts[0])
            if size < _JOIN_BELOW:
                joined += pack(size)
                joined += parts[0]
                continue
        else:
            size = sum(map(len, parts))
        if joined:
            sock.sendall(joined)
            joined.clear()
        _send_parts(sock, [pack(size), *parts])
    if joined:
        sock.sendall(joined)


def _send_parts(sock: socket.socket, parts: list[bytes | memoryview]) -> None:
    """``sendmsg`` until every part is sent (it may stop inside one)."""
    views = [memoryview(part).cast("B") for part in parts if len(part)]
    while views:
        sent = sock.sendmsg(views)
        while views and sent >= len(views[0]):
            sent -= len(views[0])
            views.pop(0)
        if sent:
            views[0] = views[0][sent:]
