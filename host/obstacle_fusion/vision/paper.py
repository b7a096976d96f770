"""The paper's method, reproduced as written (section IV), for comparison.

undistort -> Sobel edge enhancement (Fig. 7 templates) -> binarisation at the threshold of
formula (8) -> Canny with automatic thresholds -> probabilistic Hough, near-horizontal
lines -> h = Ymax - Ymin, w = (w1 + w2) / 2 -> H = 2 L tan(beta/2) h / Y1,
W = 2 L tan(alpha/2) w / X1. The choices where the paper is vague are in vision/README.md.
"""

from __future__ import annotations

import math
from typing import Any

import cv2
import numpy as np
import numpy.typing as npt

from obstacle_fusion.vision.types import Line, Measurement, Timer, View

# Fig. 7 (a) horizontal and (b) vertical templates. The printed (b) reads
# [-1 0 1; -1 0 1; 1 0 1], an evident misprint of the standard Sobel [-1 0 1; -2 0 2; -1 0 1].
SOBEL_H = np.array([[-1, -2, -1], [0, 0, 0], [1, 2, 1]], np.float32)
SOBEL_V = np.array([[-1, 0, 1], [-2, 0, 2], [-1, 0, 1]], np.float32)

GREY_RANGE = (70, 210)  # "the gray scale distribution of obstacles is 70 - 210"
U_ALPHA_2 = 2.807033768  # two-sided normal quantile for 1 - alpha = 99.5 %
MAX_LINE_ANGLE_DEG = 10.0  # "horizontal" lines: within this of the image rows
CENTRE_BAND = 0.05  # half-width of the centre column band, share of the image width


def formula8_threshold(grey: npt.NDArray[Any]) -> tuple[int, int]:
    """The 99.5 % confidence interval of the mean grey level over pixels in 70..210."""
    lo, hi = GREY_RANGE
    hist = cv2.calcHist([grey], [0], None, [256], [0, 256]).ravel()[lo : hi + 1]
    n = float(hist.sum())
    if n < 2:
        return (lo, hi)
    levels = np.arange(lo, hi + 1, dtype=np.float64)
    mean = float((hist * levels).sum() / n)
    var = float((hist * (levels - mean) ** 2).sum() / (n - 1))
    half = U_ALPHA_2 * math.sqrt(var / n)
    return (int(math.floor(mean - half)), int(math.ceil(mean + half)))


class PaperMethod:
    name = "paper"

    def __init__(self, view: View) -> None:
        self.view = view
        h, w = view.camera.height, view.camera.width
        self._gx = np.empty((h, w), np.float32)
        self._gy = np.empty((h, w), np.float32)
        self._binary = np.empty((h, w), np.uint8)
        self.min_line = max(10, int(round(0.05 * w)))
        self.centre_band = max(2.0, CENTRE_BAND * w)  # half-width of the centre column band

    @staticmethod
    def _extent(
        x_lo: npt.NDArray[Any],
        x_hi: npt.NDArray[Any],
        ymid: npt.NDArray[Any],
        central: npt.NDArray[Any],
        y: float,
    ) -> tuple[float, float]:
        """The boundary line on row ``y`` through the centre band, its Hough pieces chained."""
        on_row = np.abs(ymid - y) <= 1.5
        lo = float(x_lo[on_row & central].min())
        hi = float(x_hi[on_row & central].max())
        grown = True
        while grown:  # Hough splits a line at gaps: chain the pieces on the same row
            touch = on_row & (x_hi >= lo - 3.0) & (x_lo <= hi + 3.0)
            new_lo, new_hi = float(x_lo[touch].min()), float(x_hi[touch].max())
            grown = new_lo < lo or new_hi > hi
            lo, hi = new_lo, new_hi
        return lo, hi

    def run(self, image: npt.NDArray[Any], range_m: float, timer: Timer) -> Measurement:
        v = self.view
        grey = v.warp(image)
        timer.lap("undistort")
        cv2.filter2D(grey, cv2.CV_32F, SOBEL_H, dst=self._gy)
        cv2.filter2D(grey, cv2.CV_32F, SOBEL_V, dst=self._gx)
        mag = cv2.magnitude(self._gx, self._gy)
        # edge enhancement: the grey image sharpened by its Sobel magnitude
        enhanced = cv2.convertScaleAbs(cv2.addWeighted(grey.astype(np.float32), 1.0, mag, 0.25, 0))
        timer.lap("sobel")
        _, upper = formula8_threshold(enhanced)
        cv2.threshold(enhanced, upper, 255, cv2.THRESH_BINARY, dst=self._binary)
        timer.lap("threshold")
        # automatic Canny thresholds from the enhanced image's median (0.67 / 1.33 rule)
        med = float(np.median(enhanced[::2, ::2]))
        low, high = max(1.0, 0.67 * med), min(255.0, max(2.0, 1.33 * med))
        edges = cv2.Canny(self._binary, low, high)
        timer.lap("canny")
        found = cv2.HoughLinesP(
            edges,
            1,
            math.pi / 180.0,
            threshold=max(10, self.min_line // 2),
            minLineLength=self.min_line,
            maxLineGap=3,
        )
        timer.lap("hough")
        fail = Measurement(detected=False, method=self.name, range_m=range_m, distance_m=range_m)
        if found is None:
            fail.reason = "no horizontal lines found"
            return fail
        segs = found.reshape(-1, 4).astype(np.float64)
        dx = segs[:, 2] - segs[:, 0]
        dy = segs[:, 3] - segs[:, 1]
        ang = np.degrees(np.abs(np.arctan2(dy, np.abs(dx) + 1e-9)))
        segs = segs[ang <= MAX_LINE_ANGLE_DEG]
        if len(segs) < 2:
            fail.reason = "fewer than two horizontal lines found"
            return fail
        ymid = 0.5 * (segs[:, 1] + segs[:, 3])
        x_lo = np.minimum(segs[:, 0], segs[:, 2])
        x_hi = np.maximum(segs[:, 0], segs[:, 2])
        # The paper's obstacle stands in front of the robot, centred, filling the middle of
        # the frame (its Figs. 8-10): its boundary lines are the horizontal lines crossing
        # the image's centre column band, the upper one the nearest above the image centre,
        # the lower one the nearest below. Ymin/Ymax over the whole image would take floor
        # seams below and wall lines above the obstacle instead.
        xc, yc = 0.5 * (v.camera.width - 1), 0.5 * (v.camera.height - 1)
        band = self.centre_band
        central = (x_lo <= xc + band) & (x_hi >= xc - band)
        above = central & (ymid < yc)
        below = central & (ymid >= yc)
        if not above.any() or not below.any():
            fail.reason = (
                "no pair of horizontal lines encloses the image centre (the paper assumes "
                "the obstacle stands centred in front of the camera)"
            )
            return fail
        y_top = float(ymid[above].max())
        y_bot = float(ymid[below].min())
        h_px = y_bot - y_top
        a1, a2 = self._extent(x_lo, x_hi, ymid, central, y_top)
        b1, b2 = self._extent(x_lo, x_hi, ymid, central, y_bot)
        w_px = 0.5 * ((a2 - a1) + (b2 - b1))
        depth = v.rig.face_depth(range_m)
        cam = v.camera
        # formula (1) and its width twin, with alpha and beta from the calibrated camera
        height_m = 2.0 * depth * math.tan(cam.fov_y_rad / 2.0) * h_px / cam.height
        width_m = 2.0 * depth * math.tan(cam.fov_x_rad / 2.0) * w_px / cam.width
        timer.lap("measure")
        corners = np.array([[a1, y_top], [a2, y_top], [b2, y_bot], [b1, y_bot]])
        pix = v.to_input(corners)
        box = (
            float(pix[:, 0].min()),
            float(pix[:, 1].min()),
            float(pix[:, 0].max()),
            float(pix[:, 1].max()),
        )
        lines: list[Line] = [
            (float(pix[0, 0]), float(pix[0, 1]), float(pix[1, 0]), float(pix[1, 1])),
            (float(pix[3, 0]), float(pix[3, 1]), float(pix[2, 0]), float(pix[2, 1])),
        ]
        return Measurement(
            detected=True,
            method=self.name,
            range_m=range_m,
            distance_m=range_m,
            height_m=height_m,
            width_m=width_m,
            box_px=box,
            confidence=None,  # the paper has no notion of confidence
            lines=lines,
            height_px=h_px,
            width_px=w_px,
            clipped=v.unseen_sides(corners[[3, 2, 1, 0]]),  # (bottom-left first)
        )
