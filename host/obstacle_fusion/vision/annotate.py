"""Draw a measurement on its photo: the chosen edges, the face box and the numbers."""

from __future__ import annotations

from typing import Any

import cv2
import numpy.typing as npt

from obstacle_fusion.vision.measure import Measurement


def annotate(image: npt.NDArray[Any], result: Measurement) -> npt.NDArray[Any]:
    out = image.copy() if image.ndim == 3 else cv2.cvtColor(image, cv2.COLOR_GRAY2BGR)
    for x0, y0, x1, y1 in result.lines:
        cv2.line(out, (round(x0), round(y0)), (round(x1), round(y1)), (0, 255, 255), 1, cv2.LINE_AA)
    if result.detected and result.box_px is not None:
        x0, y0, x1, y1 = (round(v) for v in result.box_px)
        cv2.rectangle(out, (x0, y0), (x1, y1), (0, 200, 0), 1)
        text = (
            f"{result.method} H {result.height_m:.3f} m  W {result.width_m:.3f} m  "
            f"L {result.distance_m:.2f} m"
        )
    else:
        text = f"{result.method}: no obstacle ({result.reason[:60]})"
    scale = max(0.35, out.shape[1] / 1400.0)
    cv2.putText(out, text, (5, 15), cv2.FONT_HERSHEY_SIMPLEX, scale, (0, 0, 0), 3, cv2.LINE_AA)
    cv2.putText(
        out, text, (5, 15), cv2.FONT_HERSHEY_SIMPLEX, scale, (255, 255, 255), 1, cv2.LINE_AA
    )
    return out
