"""`obstacle-fusion calibrate IMAGES...`: a camera file from chessboard photos."""

from __future__ import annotations

import argparse
import math
import statistics
from pathlib import Path

from obstacle_fusion.errors import UserError

#: Printed boards: millimetre squares on a phone screen up to squares a metre wide.
MIN_SQUARE_MM = 0.5
MAX_SQUARE_MM = 1000.0


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "calibrate",
        help="calibrate the camera from chessboard photos (Zhang's method)",
        description="Find a chessboard in each photo, calibrate the camera by Zhang's method "
        "and write an OpenCV FileStorage YAML (camera_matrix, distortion_coefficients, "
        "image_width, image_height, rms) that `measure`, `run` and OpenCV itself read. "
        "Photos with no board found are named and skipped.",
    )
    parser.add_argument("images", nargs="+", metavar="IMAGE", help="chessboard photos")
    parser.add_argument(
        "--board",
        default="9x6",
        help="INNER corners per row x per column, as OpenCV counts them (default 9x6, "
        "i.e. a board of 10x7 squares)",
    )
    parser.add_argument(
        "--square-mm",
        type=float,
        default=25.0,
        help="side of one square in mm (default 25; intrinsics do not depend on it)",
    )
    parser.add_argument(
        "-o", "--output", default="camera.yaml", help="camera file to write (default camera.yaml)"
    )
    parser.add_argument(
        "--ros-yaml",
        type=Path,
        metavar="FILE",
        help="also write the calibration as ROS camera_info YAML (camera_calibration_parsers)",
    )
    parser.add_argument(
        "--fix-k3",
        action="store_true",
        help="fit k1 k2 p1 p2 only (as the paper's MATLAB toolbox); wise with few photos",
    )
    parser.add_argument(
        "--min-boards", type=int, default=3, help="fail unless at least this many boards are found"
    )
    parser.add_argument(
        "--no-progress", action="store_true", help="no progress bar, even on a terminal"
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    # OpenCV is imported here so `obstacle-fusion --help` stays fast.
    import cv2

    from obstacle_fusion.vision.calibration import calibrate_files
    from obstacle_fusion.vision.chessboard import BoardSpec

    if args.min_boards < 1:
        raise UserError("--min-boards must be at least 1")
    if not (MIN_SQUARE_MM <= args.square_mm <= MAX_SQUARE_MM):  # also refuses NaN
        raise UserError(
            f"--square-mm must be a positive size in mm, {MIN_SQUARE_MM:g} to "
            f"{MAX_SQUARE_MM:g}, got {args.square_mm}"
        )
    board = BoardSpec.parse(args.board, args.square_mm / 1000.0)
    out = Path(args.output)
    if out.is_dir():
        raise UserError(f"-o {out} is a directory; give a file name such as {out}/camera.yaml")
    if not out.parent.exists():
        raise UserError(f"cannot write {out}: folder {out.parent} does not exist")
    ros_yaml: Path | None = args.ros_yaml
    if ros_yaml is not None:
        if ros_yaml.is_dir():
            raise UserError(f"--ros-yaml {ros_yaml} is a directory; give a file name")
        if not ros_yaml.parent.exists():
            raise UserError(f"cannot write {ros_yaml}: folder {ros_yaml.parent} does not exist")
        if ros_yaml.resolve() == out.resolve():
            raise UserError("--ros-yaml and -o name the same file; give two names")
    flags = cv2.CALIB_FIX_K3 if args.fix_k3 else 0
    result = calibrate_files(
        args.images,
        board,
        flags=flags,
        min_boards=args.min_boards,
        progress=False if args.no_progress else None,
    )
    cam = result.camera
    cam.save(
        out,
        extra={
            "board_width": board.cols,
            "board_height": board.rows,
            "square_size": board.square_m,
            "nr_of_frames": len(result.used),
            "flags": int(flags),
        },
    )
    if ros_yaml is not None:
        from obstacle_fusion.outputs.ros2_bag import camera_info_yaml

        ros_yaml.write_text(camera_info_yaml(cam), encoding="utf-8")
    _print_summary(result, out)
    if ros_yaml is not None:
        print(f"wrote {ros_yaml} (ROS camera_info)")
    return 0


def _print_summary(result: object, out: Path) -> None:
    from obstacle_fusion.vision.calibration import CalibrationResult

    assert isinstance(result, CalibrationResult)
    cam, sd = result.camera, result.std_dev
    lines = [
        f"camera {cam.width}x{cam.height} from {len(result.used)} of {len(result.images)} "
        f"images ({result.board})",
        f"  fx  {cam.fx:10.2f} px  (+/- {sd['fx']:.2f})",
        f"  fy  {cam.fy:10.2f} px  (+/- {sd['fy']:.2f})",
        f"  cx  {cam.cx:10.2f} px  (+/- {sd['cx']:.2f})",
        f"  cy  {cam.cy:10.2f} px  (+/- {sd['cy']:.2f})",
        f"  fov {math.degrees(cam.fov_x_rad):.2f} x {math.degrees(cam.fov_y_rad):.2f} deg",
        "  dist " + " ".join(f"{v:.6g}" for v in cam.dist_coeffs),
        f"  rms {cam.rms_px:.4f} px",
        "per-image reprojection error (px):",
    ]
    errors = [r.rms_px for r in result.used if r.rms_px is not None]
    median = statistics.median(errors) if errors else 0.0
    width = max(len(r.name) for r in result.images)
    for r in result.images:
        if r.problem is not None:
            lines.append(f"  {r.name:<{width}}  {r.problem} (skipped)")
            continue
        if not r.found:
            lines.append(f"  {r.name:<{width}}  no board found (skipped)")
            continue
        err = r.rms_px or 0.0
        note = (
            "  <- much worse than the others; consider dropping it"
            if (len(errors) > 3 and err > 2.5 * median and err > 0.5)
            else ""
        )
        lines.append(f"  {r.name:<{width}}  {err:.4f}{note}")
    lines.append(f"wrote {out}")
    print("\n".join(lines))
