"""The wire protocol: generated message definitions, framing, and the streaming decoder."""

from obstacle_fusion.protocol.codec import FrameError, decode_frame, encode
from obstacle_fusion.protocol.generated import MESSAGES, PROTOCOL_VERSION, SCHEMA_FINGERPRINT
from obstacle_fusion.protocol.stream import DecoderStats, StreamDecoder

__all__ = [
    "MESSAGES",
    "PROTOCOL_VERSION",
    "SCHEMA_FINGERPRINT",
    "DecoderStats",
    "FrameError",
    "StreamDecoder",
    "decode_frame",
    "encode",
]
