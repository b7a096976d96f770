"""The fused method: the sonar's range tells the image where to look and what to expect.

Working view: undistorted and levelled (see :class:`View`), so the face square to the robot
is an exact scaled copy, its vertical edges are image columns, and a point on the floor at
depth z sits on row cy + fy * camera_height / z. From the range L (face depth D):

1. the floor-contact edge must lie near row cy + fy h / D (band from the range's error);
2. the beam (about 15 degrees) bounds where the face is horizontally: it must reach into
   the beam's columns at depth D;
3. the face's vertical edges stand on that floor-contact edge and run straight up to the
   front top edge, where they stop (top-face edges slant away, background lines do not
   stop at the box's sides, a stripe on the face does not end the vertical edges), and
   the face keeps its own shade between them (books on a shelf behind it do not).

Candidates for each edge come from gradient profiles; every (bottom, left, right) triple
is scored with its best top; the winner's four edges are refined to sub-pixel lines, and
height/width follow from the pinhole model at depth D (per-edge depths from the floor
geometry correct a few degrees of yaw).

The stages, one module each (each module's docstring says what it receives and returns):

- ``tuning``      the named tuning constants, each with why
- ``profiles``    small array helpers: means, sub-pixel peaks, running counts, line fits
- ``search``      candidate search: floor-contact rows, side columns, presence tables
- ``scoring``     pair and face scoring, and the vanishing-point test of the sides
- ``extent``      the chosen face's top raised past a label's edge, its sides widened
                  past seams (its top and bottom edges run on across them)
- ``confidence``  the confidence figure and the min-confidence decision
- ``top``         the chosen face's front top edge (a top face's front, not its back)
- ``refine``      sub-pixel refinement of the chosen edges and the measurement
- ``method``      :class:`FusedMethod`: the working view, the gradients, the stages in order
- ``channel``     the frame's channel turned towards the face's colour against the floor
- ``floor_contact`` the floor-contact rows found in the image when no rig is given
- ``undistort``   the levelled grey view's remap by a per-view table (OpenCV's values)

Debug logging goes to the loggers under ``obstacle_fusion.vision.fused``.
"""

from __future__ import annotations

from obstacle_fusion.vision.fused.method import FusedMethod
from obstacle_fusion.vision.fused.tuning import DEFAULT_MIN_CONFIDENCE, MIN_SIZE_M

__all__ = ["DEFAULT_MIN_CONFIDENCE", "MIN_SIZE_M", "FusedMethod"]
