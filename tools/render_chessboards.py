"""Render chessboard photos through a known camera, to try `obstacle-fusion calibrate`
and `obstacle-fusion calibrate-rig`.

    python tools/render_chessboards.py OUT_DIR [--size 1280x720] [--count 12] [--board 9x6]
    python tools/render_chessboards.py OUT_DIR --floor 0.25,5,0.5 [--count 3] [--size ...]

Writes OUT_DIR/board_NN.png and OUT_DIR/truth.yaml (the camera the boards were rendered
with), so a calibration can be compared with the answer. With ``--floor H,PITCH,ROLL``
(metres, degrees down, degrees right side down) the board lies on the floor in front of a
camera mounted so, at the nearest distance (0.4-1 m) it is wholly in view, then shifted
and turned a little photo by photo; OUT_DIR/truth_rig.toml holds that mounting.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import cv2
import numpy as np
from obstacle_fusion.errors import UserError
from obstacle_fusion.sim.floor_boards import FloorRig, nearest_placement, render_floor_board
from obstacle_fusion.vision.camera import CameraModel
from obstacle_fusion.vision.chessboard import BoardRenderer, BoardSpec, default_poses
from obstacle_fusion.vision.rig import Rig


def _floor(text: str) -> FloorRig:
    try:
        parts = [float(v) for v in text.split(",")]
        if len(parts) not in (2, 3):
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError("give HEIGHT_M,PITCH_DEG[,ROLL_DEG]") from None
    return FloorRig(*parts)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out_dir", type=Path)
    parser.add_argument("--size", default="1280x720", help="WIDTHxHEIGHT (default 1280x720)")
    parser.add_argument("--count", type=int, default=12, help="number of views (default 12)")
    parser.add_argument("--board", default="9x6", help="inner corners (default 9x6)")
    parser.add_argument("--square-mm", type=float, default=25.0, help="square side (25)")
    parser.add_argument("--noise", type=float, default=2.0, help="pixel noise sigma")
    parser.add_argument("--paper", action="store_true", help="use the paper's camera")
    parser.add_argument(
        "--floor", type=_floor, help="HEIGHT_M,PITCH_DEG[,ROLL_DEG]: boards on the floor"
    )
    args = parser.parse_args(argv)
    try:
        w_text, _, h_text = args.size.lower().partition("x")
        width, height = int(w_text), int(h_text)
        board = BoardSpec.parse(args.board, args.square_mm / 1000.0)
        if args.paper:
            camera = CameraModel.paper(width, height)
        else:
            f = 0.9 * width
            k = np.array([[f, 0, width / 2 + 3.3], [0, f * 0.998, height / 2 - 2.1], [0, 0, 1]])
            camera = CameraModel(k, np.array([-0.18, 0.09, 0.0008, -0.0006, -0.01]), width, height)
    except (ValueError, UserError) as exc:
        print(f"render_chessboards: error: {exc}", file=sys.stderr)
        return 2
    args.out_dir.mkdir(parents=True, exist_ok=True)
    renderer = BoardRenderer(camera, board, supersample=2)
    rng = np.random.default_rng(0)
    if args.floor is not None:
        written = 0
        for i in range(args.count):
            right, yaw = 0.02 * ((i % 3) - 1), 4.0 * ((i % 5) - 2)
            dist = nearest_placement(camera, board, args.floor, right_m=right, yaw_deg=yaw)
            if dist is None:
                continue
            dist += 0.03 * (i % 2)
            view = render_floor_board(
                renderer, args.floor, dist, right_m=right, yaw_deg=yaw, rng=rng
            )
            cv2.imwrite(str(args.out_dir / f"board_{i:02d}.png"), view.image)
            written += 1
        if written == 0:
            print(
                "render_chessboards: error: the board is nowhere wholly in view 0.4-1 m ahead; "
                "use a smaller board or another mounting",
                file=sys.stderr,
            )
            return 2
        Rig(camera_height_m=args.floor.height_m, camera_pitch_deg=args.floor.pitch_deg).save(
            args.out_dir / "truth_rig.toml"
        )
        camera.save(args.out_dir / "truth.yaml")
        print(
            f"wrote {written} floor views, truth.yaml and truth_rig.toml (roll "
            f"{args.floor.roll_deg:g} deg) to {args.out_dir}"
        )
        return 0
    for i, pose in enumerate(default_poses(camera, board, args.count)):
        view = renderer.render(pose, noise_sigma=args.noise, blur_sigma=0.5, rng=rng)
        cv2.imwrite(str(args.out_dir / f"board_{i:02d}.png"), view.image)
    camera.save(args.out_dir / "truth.yaml")
    print(f"wrote {args.count} views and truth.yaml to {args.out_dir}: {camera}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
