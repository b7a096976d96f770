"""`obstacle-fusion measure IMAGE --range-m L`: one obstacle's height and width from one photo."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from obstacle_fusion.cli._args import float_within
from obstacle_fusion.errors import UserError


def register(subparsers: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    parser = subparsers.add_parser(
        "measure",
        help="measure an obstacle's height and width from a photo and the sonar range",
        description="Measure the obstacle in front from one photo and the sonar's range. "
        "Without --calib the paper's camera (calibrated at 2592x1944) is scaled to the "
        "photo's size, which needs the photo to have its 4:3 aspect; give --calib for any "
        "other camera. A calibration of another resolution is scaled when the aspect "
        "matches, else refused. Exit 0 when measured, 1 when no obstacle was found, "
        "2 for bad input.",
    )
    parser.add_argument("image", metavar="IMAGE", help="photo (any format OpenCV reads)")
    parser.add_argument(
        "--range-m", type=float, required=True, help="sonar range to the obstacle in metres"
    )
    parser.add_argument("--calib", help="camera file from `obstacle-fusion calibrate`")
    parser.add_argument("--rig", help="rig TOML (camera height/pitch, sonar offset, beam)")
    parser.add_argument("--method", choices=("fused", "paper"), default="fused")
    parser.add_argument(
        "--min-confidence",
        type=float_within(0.0, 1.0),
        default=None,
        metavar="C",
        help="fused: report no detection below this confidence, 0..1 (default 0.05; 0 reports "
        "every best guess)",
    )
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--annotate", metavar="OUT.png", help="write the photo with the result")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import cv2

    from obstacle_fusion.vision.annotate import annotate
    from obstacle_fusion.vision.camera import CameraModel, CameraModelError
    from obstacle_fusion.vision.measure import Measurer
    from obstacle_fusion.vision.rig import Rig, check_range

    check_range(args.range_m)
    path = Path(args.image)
    if path.is_dir():
        raise UserError(
            f"{path} is a folder, not an image: give one photo (a folder of frames plays with "
            "`obstacle-fusion run --camera FOLDER`)"
        )
    if not path.is_file():
        raise UserError(f"image {path} does not exist")
    try:  # OpenCV says only "None" for a file it may not open: ask the system first
        with open(path, "rb") as fh:
            fh.read(1)
    except PermissionError:
        raise UserError(f"cannot read image {path}: permission denied") from None
    except OSError as exc:
        raise UserError(f"cannot read image {path}: {exc.strerror or exc}") from None
    image = cv2.imread(str(path), cv2.IMREAD_COLOR)
    if image is None:
        raise UserError(f"cannot read image {path}: not an image format OpenCV can decode")
    if args.annotate:
        out = Path(args.annotate)
        if not out.parent.exists():
            raise UserError(f"cannot write {out}: folder {out.parent} does not exist")
        if out.suffix.lower() not in (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff"):
            raise UserError(f"--annotate {out}: use a .png or .jpg file name")
    if args.calib:
        camera = CameraModel.load(args.calib).for_image(image)  # scales, or explains the aspect
    else:
        try:
            camera = CameraModel.paper().for_image(image)
        except CameraModelError:
            h, w = image.shape[:2]
            raise UserError(
                f"no --calib given, and {path.name} is {w}x{h}: the default camera is the "
                "paper's 4:3 one, which cannot measure another aspect; calibrate this camera "
                "(obstacle-fusion calibrate) and pass --calib FILE"
            ) from None
    rig = Rig.load(args.rig) if args.rig else None
    result = Measurer(camera, rig, args.method, args.min_confidence).measure(image, args.range_m)
    if args.annotate:
        if not cv2.imwrite(str(args.annotate), annotate(image, result)):
            raise UserError(f"could not write {args.annotate}")
    if args.json:
        print(json.dumps(result.to_dict(), allow_nan=False, default=_clean))
    elif result.detected:
        conf = "n/a" if result.confidence is None else f"{result.confidence:.2f}"
        print(
            f"{result.method}: height {result.height_m:.3f} m, width {result.width_m:.3f} m, "
            f"distance {result.distance_m:.3f} m, confidence {conf}, "
            f"{result.timings_ms['total']:.2f} ms"
        )
    else:
        print(f"{result.method}: no obstacle found ({result.reason})")
    return 0 if result.detected else 1


def _clean(value: object) -> object:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    raise TypeError(f"not JSON serialisable: {value!r}")
