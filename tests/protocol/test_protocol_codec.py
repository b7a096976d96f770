"""The Python codec against the golden vectors and against independent references."""

from __future__ import annotations

import binascii
import dataclasses
import json
import struct
from pathlib import Path

import pytest
from cobs import cobs
from hypothesis import given
from hypothesis import strategies as st
from obstacle_fusion.protocol import FrameError, decode_frame, encode
from obstacle_fusion.protocol.generated import (
    BY_NAME,
    MAX_FRAME,
    MESSAGES,
    SCHEMA_FINGERPRINT,
    Log,
    Range,
)

from tests.protocol.test_protocol_generated import gen

pytestmark = pytest.mark.cpu_only

ROOT = Path(__file__).resolve().parents[2]
VECTORS = json.loads((ROOT / "protocol" / "vectors" / "golden.json").read_text())


def test_every_message_has_a_vector() -> None:
    assert {v["message"] for v in VECTORS} == set(BY_NAME)


@pytest.mark.parametrize("vector", VECTORS, ids=lambda v: v["message"])
def test_golden_vector_round_trip(vector: dict) -> None:  # type: ignore[type-arg]
    cls = BY_NAME[vector["message"]]
    msg = cls(**vector["fields"])
    frame = encode(msg, vector["seq"])
    assert frame.hex() == vector["frame"]
    assert decode_frame(frame) == msg


@pytest.mark.parametrize("vector", VECTORS, ids=lambda v: v["message"])
def test_construct_layout_agrees_with_struct(vector: dict) -> None:  # type: ignore[type-arg]
    cls = BY_NAME[vector["message"]]
    payload = cobs.decode(bytes.fromhex(vector["frame"])[:-1])[2:-2]
    parsed = cls.LAYOUT.parse(payload)
    fields = dict(vector["fields"])
    if cls.TEXT_FIELD:
        fields[cls.TEXT_FIELD] = fields[cls.TEXT_FIELD].encode()
    assert {k: parsed[k] for k in fields} == fields
    assert cls.LAYOUT.build(fields) == payload


@given(st.binary(max_size=300))
def test_crc_matches_bitwise_reference(data: bytes) -> None:
    assert binascii.crc_hqx(data, 0xFFFF) == gen.crc16_ccitt(data)


@given(st.binary(max_size=600))
def test_cobs_matches_reference(data: bytes) -> None:
    assert bytes(cobs.encode(data)) == gen.cobs_encode(data)


def test_crc_check_value() -> None:
    # The catalogued check value of CRC-16/CCITT-FALSE.
    assert gen.crc16_ccitt(b"123456789") == 0x29B1


def test_frames_never_exceed_max_frame() -> None:
    longest = Log(level=3, text="x" * (Log.MAX_LEN - Log.MIN_LEN))
    assert len(encode(longest, 255)) <= MAX_FRAME


def test_schema_mismatch_is_rejected() -> None:
    """A peer built with another crc_extra for RANGE fails the CRC instead of misreading."""
    msg = Range(measurement=1, sensor_id=0, trigger_us=2, echo_ticks=3, status=0)
    body = bytes((Range.MSG_ID, 7)) + struct.pack("<IBIIB", 1, 0, 2, 3, 0)
    other_seed = binascii.crc_hqx(bytes([Range.CRC_EXTRA ^ 0x01]), 0xFFFF)
    crc = binascii.crc_hqx(body, other_seed)
    frame = bytes(cobs.encode(body + crc.to_bytes(2, "big")))
    with pytest.raises(FrameError) as info:
        decode_frame(frame)
    assert info.value.kind == "crc_errors"
    assert decode_frame(encode(msg, 7)) == msg


def test_encode_names_the_bad_field() -> None:
    with pytest.raises(ValueError, match="out of its type's range"):
        encode(Range(measurement=-1, sensor_id=0, trigger_us=0, echo_ticks=0, status=0), 0)
    with pytest.raises(ValueError, match="sensor_id"):
        encode(Range(measurement=0, sensor_id="a", trigger_us=0, echo_ticks=0, status=0), 0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="seq"):
        encode(Range(measurement=0, sensor_id=0, trigger_us=0, echo_ticks=0, status=0), 256)
    with pytest.raises(ValueError, match="text"):
        encode(Log(level=0, text="y" * 100), 0)


def test_hello_vector_carries_this_schema() -> None:
    hello = next(v for v in VECTORS if v["message"] == "hello")
    assert hello["fields"]["schema_fingerprint"] == SCHEMA_FINGERPRINT


def test_ids_unique_and_directions_split() -> None:
    ids = [cls.MSG_ID for cls in MESSAGES.values()]
    assert len(ids) == len(set(ids))
    for cls in MESSAGES.values():
        assert (cls.DIRECTION == "host_to_device") == (cls.MSG_ID >= 0x40)
        assert [f.name for f in dataclasses.fields(cls)] or cls.MIN_LEN == 0


def test_the_spec_says_the_crc_byte_order_the_wire_uses() -> None:
    """spec.toml's framing comment, protocol/README.md and the encoder agree: the CRC is
    sent high byte first (big-endian), as the C code and the golden vectors do."""
    import binascii
    import re
    from pathlib import Path

    from cobs import cobs
    from obstacle_fusion.protocol import encode as encode_frame
    from obstacle_fusion.protocol.codec import CRC_SEEDS
    from obstacle_fusion.protocol.generated import Ack as AckMsg

    root = Path(__file__).resolve().parents[2]
    spec = (root / "protocol" / "spec.toml").read_text()
    orders = re.findall(r"crc:u16(\w*)", spec)
    assert orders == ["be"], orders
    assert "crc:u16 (big-endian)" in (root / "protocol" / "README.md").read_text()
    body = cobs.decode(encode_frame(AckMsg(command_id=0x41, command_seq=9), 3)[:-1])
    crc = binascii.crc_hqx(body[:-2], CRC_SEEDS[AckMsg.MSG_ID])
    assert body[-2:] == crc.to_bytes(2, "big") != crc.to_bytes(2, "little")
