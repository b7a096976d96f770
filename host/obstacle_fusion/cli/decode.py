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
        if sys.stdin is None:  # started with standard input closed (`<&-`)
            raise UserError("standard input is closed; give a capture file, or pipe one in")
        return sys.stdin.buffer
    try:
        return open(path, "rb")
    except FileNotFoundError:
        raise UserError(f"no such capture file: {path}") from None
    except IsADirectoryError:
        raise UserError(f"{path} is a directory; give a capture file") from None
    except PermissionError:
        raise UserError(f"cannot read {path}: permission denied") from None


MCAP_MAGIC = b"\x89MCAP"


def _read(stream: BinaryIO, name: str) -> bytes:
    try:
        return stream.read(CHUNK)
    except (OSError, ValueError) as exc:  # a closed descriptor, a directory, an I/O error
        what = "standard input" if name == "-" else name
        raise UserError(f"cannot read {what}: {getattr(exc, 'strerror', None) or exc}") from None


def run(args: argparse.Namespace) -> int:
    decoder = StreamDecoder()
    stream = _open(args.capture)
    out = sys.stdout
    try:
        first = True
        while chunk := _read(stream, args.capture):
            if first and chunk.startswith(MCAP_MAGIC):
                where = "FILE.mcap" if args.capture == "-" else args.capture
                save = "save it to a file, then " if args.capture == "-" else ""
                raise UserError(
                    f"{args.capture} is an MCAP recording, not a raw serial capture: "
                    f"{save}use `obstacle-fusion replay {where}`"
                )
            first = False
            for msg in decoder.feed(chunk):
                out.write(json.dumps(message_to_dict(msg)) + "\n")
    finally:
        if stream is not sys.stdin.buffer:
            stream.close()
    stats = decoder.stats.as_dict()
    stats["pending_bytes"] = decoder.pending_bytes
    out.write(json.dumps({"stats": stats}) + "\n")
    if stats["frames"] == 0 and stats["bytes"] > 0:
        print(
            f"obstacle-fusion decode: warning: no frame found in {stats['bytes']} bytes; "
            "is this a raw capture of the board's serial port (115200 8N1)?",
            file=sys.stderr,
        )
    return 0
