"""Framing: messages to COBS frames and back (CRC-16 seeded per message, see protocol/README.md)."""

from __future__ import annotations

import binascii
import dataclasses

from cobs import cobs

from obstacle_fusion.protocol.generated import CRC_INIT, MAX_BODY, MESSAGES, Message

# CRC state after the message's crc_extra byte: the seed of that message's frame CRC.
CRC_SEEDS: dict[int, int] = {
    msg_id: binascii.crc_hqx(bytes([cls.CRC_EXTRA]), CRC_INIT) for msg_id, cls in MESSAGES.items()
}


class FrameError(ValueError):
    """A frame that cannot be decoded; ``kind`` names the counter it belongs to."""

    def __init__(self, kind: str, detail: str) -> None:
        super().__init__(detail)
        self.kind = kind


def pack_payload(msg: Message) -> bytes:
    values = [getattr(msg, f.name) for f in dataclasses.fields(msg)]
    text_field = msg.TEXT_FIELD
    if text_field is not None:
        text = values.pop()
        data = str(text).encode("ascii", errors="replace")
        if len(data) > msg.MAX_LEN - msg.MIN_LEN:
            raise ValueError(
                f"{msg.NAME}.{text_field}: {len(data)} bytes, at most {msg.MAX_LEN - msg.MIN_LEN}"
            )
    else:
        data = b""
    try:
        return msg.STRUCT.pack(*values) + data
    except Exception as exc:  # struct.error names no field; find the culprit for the user
        for field, value in zip(dataclasses.fields(msg), values, strict=False):
            if not isinstance(value, int):
                raise ValueError(f"{msg.NAME}.{field.name}: {value!r} is not an integer") from exc
        raise ValueError(f"{msg.NAME}: a field is out of its type's range: {exc}") from exc


def encode(msg: Message, seq: int) -> bytes:
    """One complete frame for ``msg``: COBS bytes followed by the 0x00 delimiter."""
    if not 0 <= seq <= 0xFF:
        raise ValueError(f"seq {seq} is outside 0..255")
    body = bytes((msg.MSG_ID, seq)) + pack_payload(msg)
    crc = binascii.crc_hqx(body, CRC_SEEDS[msg.MSG_ID])
    return bytes(cobs.encode(body + crc.to_bytes(2, "big"))) + b"\x00"


def decode_body(body: bytes) -> Message:
    """Decode one un-COBSed frame body (id, seq, payload, crc); raise FrameError if bad."""
    if len(body) < 4:
        raise FrameError("truncated", f"frame of {len(body)} bytes is shorter than 4")
    if len(body) > MAX_BODY:
        raise FrameError("oversized", f"frame of {len(body)} bytes exceeds {MAX_BODY}")
    msg_id = body[0]
    cls = MESSAGES.get(msg_id)
    if cls is None:
        raise FrameError("unknown_ids", f"unknown message id {msg_id:#04x}")
    if binascii.crc_hqx(body, CRC_SEEDS[msg_id]) != 0:
        raise FrameError("crc_errors", f"CRC mismatch for {cls.NAME}")
    n = len(body) - 4
    if not cls.MIN_LEN <= n <= cls.MAX_LEN:
        raise FrameError("bad_lengths", f"{cls.NAME} payload of {n} bytes")
    values = cls.STRUCT.unpack_from(body, 2)
    if cls.TEXT_FIELD is not None:
        text = body[2 + cls.MIN_LEN : -2].decode("ascii", errors="replace")
        return cls(*values, text)  # type: ignore[call-arg]
    return cls(*values)  # type: ignore[call-arg]


def decode_frame(frame: bytes) -> Message:
    """Decode one frame's COBS bytes (with or without the trailing 0x00)."""
    if frame.endswith(b"\x00"):
        frame = frame[:-1]
    try:
        body = cobs.decode(frame)
    except cobs.DecodeError as exc:
        raise FrameError("cobs_errors", f"bad COBS encoding: {exc}") from exc
    return decode_body(bytes(body))
