"""`obstacle-fusion calibrate-rig PHOTO...`: the rig file from photos of a board on the floor."""

from __future__ import annotations

import argparse
import logging
import math
import sys
from pathlib import Path

from obstacle_fusion.cli.calibrate import MAX_SQUARE_MM, MIN_SQUARE_MM
from obstacle_fusion.errors import UserError

log = logging.getLogger(__name__)


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "calibrate-rig",
        help="the rig (camera height, pitch) from photos of a chessboard lying on the floor",
        description="Lay the chessboard flat on the floor in front of the robot, wholly in "
        "view (0.4-1 m ahead), and take one or more photos with the robot's camera. From the "
        "board's pose each photo gives the lens's height above the floor, its pitch and its "
        "roll; their medians, with the sonar's offsets given here, are written as the rig "
        "TOML that `measure --rig` and `run --rig` read.",
    )
    parser.add_argument(
        "photos", nargs="+", metavar="PHOTO", help="photos of the board on the floor"
    )
    parser.add_argument(
        "--calib", type=Path, help="camera calibration (default: the paper's 4:3 lens, warned)"
    )
    parser.add_argument(
        "--board", default="9x6", help="INNER corners per row x per column (default 9x6)"
    )
    parser.add_argument(
        "--square-mm", type=float, default=25.0, help="side of one square in mm (default 25)"
    )
    parser.add_argument(
        "--board-thickness-mm",
        type=float,
        default=0.0,
        help="thickness of the board (a printed sheet: 0; foam board: 5), added to the height",
    )
    parser.add_argument(
        "-o", "--output", type=Path, default=Path("rig.toml"), help="rig file (default rig.toml)"
    )
    sonar = parser.add_argument_group("the sonar, relative to the lens (metres)")
    sonar.add_argument("--sonar-below-m", type=float, default=0.05, help="default 0.05")
    sonar.add_argument("--sonar-right-m", type=float, default=0.0, help="default 0")
    sonar.add_argument("--sonar-ahead-m", type=float, default=0.0, help="default 0")
    sonar.add_argument(
        "--beam-width-deg", type=float, default=15.0, help="full beam angle (default 15)"
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from obstacle_fusion.vision.camera import CameraModel
    from obstacle_fusion.vision.chessboard import BoardSpec
    from obstacle_fusion.vision.rig_calibration import calibrate_rig_files

    if not (MIN_SQUARE_MM <= args.square_mm <= MAX_SQUARE_MM):
        raise UserError(
            f"--square-mm must be a positive size in mm, {MIN_SQUARE_MM:g} to "
            f"{MAX_SQUARE_MM:g}, got {args.square_mm}"
        )
    if not (math.isfinite(args.board_thickness_mm) and 0.0 <= args.board_thickness_mm <= 50.0):
        raise UserError(f"--board-thickness-mm must be within 0..50, got {args.board_thickness_mm}")
    board = BoardSpec.parse(args.board, args.square_mm / 1000.0)
    out: Path = args.output
    if out.is_dir():
        raise UserError(f"-o {out} is a directory; give a file name such as {out}/rig.toml")
    if not out.parent.exists():
        raise UserError(f"cannot write {out}: folder {out.parent} does not exist")
    if args.calib is not None:
        camera = CameraModel.load(args.calib)
        camera_name = f"--calib {args.calib}"
    else:
        camera = CameraModel.paper()
        camera_name = "the paper's camera (no --calib)"
        log.warning(
            "no --calib: fitting with the paper's lens; the height and pitch are only as right "
            "as that guess (run obstacle-fusion calibrate first)"
        )
    result = calibrate_rig_files(
        args.photos,
        board,
        camera,
        board_thickness_m=args.board_thickness_mm / 1000.0,
        camera_name=camera_name,
    )
    rig = result.rig(
        sonar_right_m=args.sonar_right_m,
        sonar_below_m=args.sonar_below_m,
        sonar_ahead_m=args.sonar_ahead_m,
        beam_width_deg=args.beam_width_deg,
    )
    used = result.used
    width = max(len(f.name) for f in result.fits)
    lines = [
        f"rig from {len(used)} of {len(result.fits)} photos ({board}):",
        f"  {'photo':<{width}}  height_m  pitch_deg  roll_deg  board_at_m  reproj_px",
    ]
    flagged = {f.name for f in result.outliers()}
    for f in result.fits:
        if not f.found:
            lines.append(f"  {f.name:<{width}}  {f.problem} (skipped)")
            continue
        note = "  <- disagrees with the others; check this photo" if f.name in flagged else ""
        lines.append(
            f"  {f.name:<{width}}  {f.height_m:8.4f}  {f.pitch_deg:9.3f}  {f.roll_deg:8.3f}  "
            f"{f.board_distance_m:10.3f}  {f.rms_px:9.3f}{note}"
        )
    lines += [
        f"  {'median':<{width}}  {result.height_m:8.4f}  {result.pitch_deg:9.3f}  "
        f"{result.roll_deg:8.3f}",
        f"camera_height_m = {rig.camera_height_m:g}, camera_pitch_deg = {rig.camera_pitch_deg:g} "
        f"(roll {result.roll_deg:+.2f} deg, not part of the rig)",
        f"sonar: {rig.sonar_below_m:g} m below, {rig.sonar_right_m:g} m right, "
        f"{rig.sonar_ahead_m:g} m ahead of the lens; beam {rig.beam_width_deg:g} deg",
    ]
    warning = result.roll_warning
    if warning is not None:
        print(f"obstacle-fusion calibrate-rig: warning: {warning}", file=sys.stderr)
    _write(rig, out, result.height_m, len(used))
    lines.append(f"wrote {out}")
    print("\n".join(lines))
    return 0


def _write(rig: object, out: Path, height: float, photos: int) -> None:
    """The Rig's own TOML, with a comment saying where it came from; written atomically."""
    from obstacle_fusion.vision.rig import Rig

    assert isinstance(rig, Rig)
    part = out.with_name(f".{out.name}.part")
    try:
        rig.save(part)
        text = part.read_text(encoding="utf-8")
        part.write_text(
            f"# written by obstacle-fusion calibrate-rig from {photos} floor photo(s)\n" + text,
            encoding="utf-8",
        )
        part.replace(out)
    except OSError as exc:
        part.unlink(missing_ok=True)
        raise UserError(f"cannot write {out}: {exc.strerror or exc}") from None
