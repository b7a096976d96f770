"""Live view: the run's Foxglove topics served over the Foxglove WebSocket protocol.

The server is foxglove-sdk's (the ``foxglove`` extra); every topic of
:mod:`obstacle_fusion.outputs.foxglove_schemas` is advertised with its JSON schema, and the
messages are the very bytes the MCAP recording holds. A client that joins late gets the
transforms and the calibration within a second (they are repeated). Foxglove: "Open
connection" -> "Foxglove WebSocket" -> ``ws://HOST:PORT``.
"""

from __future__ import annotations

import errno
import json
import logging
import socket
from dataclasses import dataclass
from typing import Any

from obstacle_fusion.errors import UserError
from obstacle_fusion.outputs.foxglove_schemas import TopicMessage, topic_schemas

log = logging.getLogger(__name__)

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8765


@dataclass(frozen=True)
class Address:
    host: str
    port: int

    @classmethod
    def parse(cls, text: str) -> Address:
        """``PORT``, ``HOST:PORT`` or ``[IPv6]:PORT``; the host defaults to 127.0.0.1."""
        value = text.strip()
        host, port_text = DEFAULT_HOST, value
        if value.startswith("["):
            end = value.find("]")
            if end < 0 or not value[end + 1 :].startswith(":"):
                raise UserError(f"--foxglove {text!r}: write an IPv6 host as [ADDR]:PORT")
            host, port_text = value[1:end], value[end + 2 :]
        elif ":" in value:
            host, _, port_text = value.rpartition(":")
        try:
            port = int(port_text)
        except ValueError:
            raise UserError(
                f"--foxglove {text!r}: give PORT or HOST:PORT (e.g. 8765 or 0.0.0.0:8765)"
            ) from None
        if not 0 <= port <= 65535:
            raise UserError(f"--foxglove {text!r}: the port must be within 0..65535")
        if not host:
            raise UserError(f"--foxglove {text!r}: the host is empty")
        return cls(host, port)


def require_sdk() -> Any:
    try:
        import foxglove
    except ImportError:
        raise UserError(
            "--foxglove needs the foxglove-sdk package: pip install 'obstacle-fusion[foxglove]' "
            "(make setup installs it)"
        ) from None
    return foxglove


def check_free(addr: Address) -> None:
    """A taken port is a user error with a clear message, before the SDK tries it."""
    if addr.port == 0:
        return
    try:
        infos = socket.getaddrinfo(addr.host, addr.port, type=socket.SOCK_STREAM)
    except socket.gaierror as exc:
        raise UserError(f"--foxglove: unknown host {addr.host!r} ({exc.strerror})") from None
    family, _, _, _, sockaddr = infos[0]
    with socket.socket(family, socket.SOCK_STREAM) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind(sockaddr)
        except OSError as exc:
            if exc.errno == errno.EADDRINUSE:
                raise UserError(
                    f"--foxglove {addr.host}:{addr.port}: the port is in use (another "
                    "obstacle-fusion run?); give another port"
                ) from None
            raise UserError(
                f"--foxglove {addr.host}:{addr.port}: cannot listen there ({exc.strerror})"
            ) from None


class FoxgloveLiveServer:
    """A Foxglove WebSocket server publishing TopicMessages; close() stops it."""

    def __init__(self, address: Address, *, name: str = "obstacle-fusion") -> None:
        foxglove = require_sdk()
        check_free(address)
        self._ctx = foxglove.Context()
        try:
            self._server = foxglove.start_server(
                name=name, host=address.host, port=address.port, context=self._ctx
            )
        except Exception as exc:  # the SDK reports bind failures as its own error types
            raise UserError(
                f"--foxglove {address.host}:{address.port}: cannot start the server ({exc})"
            ) from None
        self.host = address.host
        self.port = int(self._server.port)
        self._channels: dict[str, Any] = {}
        for topic, (schema_name, schema) in topic_schemas().items():
            self._channels[topic] = foxglove.Channel(
                topic,
                schema=foxglove.Schema(
                    name=schema_name, encoding="jsonschema", data=json.dumps(schema).encode()
                ),
                message_encoding="json",
                context=self._ctx,
            )
        self.sent: dict[str, int] = dict.fromkeys(self._channels, 0)
        self._closed = False
        log.info("Foxglove WebSocket server on ws://%s:%d", self.host, self.port)

    @property
    def url(self) -> str:
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"ws://{host}:{self.port}"

    def write(self, msg: TopicMessage) -> None:
        if self._closed:
            return
        channel = self._channels.get(msg.topic)
        if channel is None:
            return
        channel.log(msg.data, log_time=msg.log_time_ns)
        self.sent[msg.topic] += 1

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        for channel in self._channels.values():
            channel.close()
        self._server.stop()

    def __enter__(self) -> FoxgloveLiveServer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
