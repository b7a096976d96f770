"""Draw a measurement on its photo: the face box, the chosen edges and the numbers."""

from __future__ import annotations

from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.types import Measurement


def annotate(image: npt.NDArray[Any], result: Measurement) -> npt.NDArray[Any]:
    out = image.copy() if image.ndim == 3 else cv2.cvtColor(image, cv2.COLOR_GRAY2BGR)
    if result.detected and result.box_px is not None:
        x0, y0, x1, y1 = (round(v) for v in result.box_px)
        cv2.rectangle(out, (x0 - 2, y0 - 2), (x1 + 2, y1 + 2), (0, 200, 0), 1)
    for ax, ay, bx, by in result.lines:  # the edges the method chose, on top of the box
        p0 = (int(round(ax * 16)), int(round(ay * 16)))
        p1 = (int(round(bx * 16)), int(round(by * 16)))
        cv2.line(out, p0, p1, (0, 255, 255), 1, cv2.LINE_AA, 4)
    if result.detected:
        conf = "n/a" if result.confidence is None else f"{result.confidence:.2f}"
        lines = [
            f"{result.method}: H {result.height_m:.3f} m  W {result.width_m:.3f} m",
            f"L {result.distance_m:.3f} m  conf {conf}  {result.timings_ms.get('total', 0):.1f} ms",
        ]
    else:
        lines = [f"{result.method}: no obstacle", result.reason[:70]]
    scale = max(0.45, out.shape[1] / 1100.0)
    step = int(22 * scale / 0.45)
    cv2.rectangle(out, (0, 0), (out.shape[1], step * len(lines) + 6), (0, 0, 0), -1)
    for i, text in enumerate(lines):
        org = (6, step * (i + 1))
        cv2.putText(
            out, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, (255, 255, 255), 1, cv2.LINE_AA
        )
    return np.ascontiguousarray(out)
