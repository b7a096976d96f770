"""`obstacle-fusion recover IN.mcap OUT.mcap`: a damaged or cut recording made whole.

A recording cut by a crash, a SIGKILL or a power cut has no summary, so MCAP's indexed
readers (Foxglove, `mcap` tools) refuse it or show nothing; one with damaged bytes in the
middle stops stream readers at the damage. This reads every intact message (see
outputs/mcap_salvage.py) and writes them, with the schemas, channels and metadata, as a
new indexed file. IN is never modified.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from obstacle_fusion.cli import _args
from obstacle_fusion.errors import UserError


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = subparsers.add_parser(
        "recover",
        help="rewrite a cut or damaged MCAP recording as a valid, indexed file",
        description="Read every intact message of a recording that was cut short (crash, "
        "SIGKILL, power cut) or damaged, and write them as a new indexed MCAP file that any "
        "MCAP reader opens. Exit 0 when written, 3 when damage in the middle lost messages.",
    )
    p.add_argument("recording", type=Path, help="IN.mcap, the cut or damaged recording")
    p.add_argument("output", type=Path, help="OUT.mcap, the file to write")
    p.add_argument("--overwrite", action="store_true", help="replace an existing OUT.mcap")
    p.set_defaults(func=run)


EXIT_LOST = 3  # damage in the middle lost messages: the same code as replay's


def run(args: argparse.Namespace) -> int:
    from obstacle_fusion.outputs.mcap_salvage import describe, scan, write_indexed

    src: Path = args.recording
    dst: Path = args.output
    if dst.suffix.lower() != ".mcap":
        raise UserError(f"{dst}: the output must be a .mcap file")
    if dst.exists() and src.exists() and dst.resolve() == src.resolve():
        raise UserError("the output must be another file than the recording it recovers")
    _args.refuse_overwrite(dst, "output", args.overwrite)
    if not src.is_file():
        raise UserError(f"{src} does not exist or is not a file")
    try:
        salvage = scan(src)
    except PermissionError:
        raise UserError(f"cannot read {src}: permission denied") from None
    except OSError as exc:
        raise UserError(f"cannot read {src}: {exc.strerror or exc}") from None
    except ValueError:
        raise UserError(f"{src} is not an MCAP file (no MCAP magic bytes at its start)") from None
    if not salvage.messages and not salvage.channels:
        raise UserError(f"{src}: nothing readable before the damage; no file written")
    try:
        n = write_indexed(salvage, dst, overwrite=args.overwrite)
    except OSError as exc:
        raise UserError(f"cannot write {dst}: {exc.strerror or exc}") from None
    state = "whole" if salvage.complete else "cut short"
    damage = describe(salvage)
    print(
        f"obstacle-fusion recover: {src} was {state}"
        + (f" and damaged ({damage})" if damage else "")
        + f"; wrote {n} messages on {len(salvage.channels)} channels to {dst}",
        file=sys.stderr,
    )
    return EXIT_LOST if salvage.damaged else 0
