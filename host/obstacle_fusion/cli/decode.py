"""`obstacle-fusion decode CAPTURE`: a raw serial capture as JSON lines."""

from __future__ import annotations

import argparse
import json
import sys
from typing import BinaryIO

from obstacle_fusion.errors import UserError
from obstacle_fusion.protocol import StreamDecoder
from obstacle_fusion.protocol.jsonview import message_to_dict

CHUNK = 1 << 16


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "decode",
        help="decode a raw byte capture of the serial link into JSON lines",
        description="Print each message of a raw serial capture as one JSON line, then one "
        "line with the decoder's counters (CRC errors, lost frames, ...).",
    )
    parser.add_argument("capture", help="capture file, or - for standard input")
    parser.set_defaults(func=run)


def _open(path: str) -> BinaryIO:
    if path == "-":
        return sys.stdin.buffer
    try:
        return open(path, "rb")
    except FileNotFoundError:
        raise UserError(f"no such capture file: {path}") from None
    except IsADirectoryError:
        raise UserError(f"{path} is a directory; give a capture file") from None
    except PermissionError:
        raise UserError(f"cannot read {path}: permission denied") from None


def run(args: argparse.Namespace) -> int:
    decoder = StreamDecoder()
    stream = _open(args.capture)
    out = sys.stdout
    try:
        while chunk := stream.read(CHUNK):
            for msg in decoder.feed(chunk):
                out.write(json.dumps(message_to_dict(msg)) + "\n")
    finally:
        if stream is not sys.stdin.buffer:
            stream.close()
    stats = decoder.stats.as_dict()
    stats["pending_bytes"] = decoder.pending_bytes
    out.write(json.dumps({"stats": stats}) + "\n")
    return 0
