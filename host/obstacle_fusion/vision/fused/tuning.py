"""The fused method's named tuning constants, each with why it is what it is.

Receives nothing and returns nothing: plain numbers read by the stage modules. Changing one
changes the method's results; the vision benchmark (tools/bench_vision.py) is the check.
"""

from __future__ import annotations

# --- candidate search (search.py)
# floor-contact rows kept from the bottom-edge profile (the predicted row is added on top):
# the true row is almost always among the three strongest near the range's prediction
MAX_BOTTOM_CANDIDATES = 3
# side columns kept per side and floor-contact row: pairs grow as the square of this
MAX_SIDE_CANDIDATES = 3
# smallest face side the method looks for (m): smaller faces are below the sonar's use
MIN_SIZE_M = 0.03
# a side's edge rows count from a quarter of its contrast near the floor, but never need
# more than this many noise levels: the side's contrast higher up may be a fraction of it
PRESENCE_CAP = 5.0

# --- pair and face scoring (scoring.py)
# a gap in the sides longer than this share of the face is no top face (a milder fault)
HOLE_SHARE = 0.2
# a stripe of another shade across the face (a label) at most this share of its height
LABEL_SHARE = 0.35
# a top edge's blur: rows from the top to the face's own shade (a label must start within)
LABEL_BLUR_ROWS = 3
# column bands of a face candidate, each to keep the face's shade (a pair reaching past a
# weak side over floor and wall fails in one band while the whole width still matches)
BANDS = 4
# a band's shade share under this share of the whole face's cuts the face-shade weight
BAND_SHARE = 0.8
# best candidates checked for world-vertical sides (floor seams lean to the vanishing point)
MAX_VERIFIED = 4
# a floor line's lean (du/dv) from which it is told from a vertical: nearer the centre
# column a seam and a box's side look alike
RADIAL_MIN = 0.08
# a fitted side's lean below this is vertical whatever the floor's (noise on a true side)
LEAN_MIN = 0.05

# --- the front top edge (top.py)
# a top edge's blur tail, as a share of the edge, within TAIL_ROWS rows below it: not
# taken for the top face's front edge
TAIL_SHARE = 0.1
TAIL_ROWS = 2
# a top face's front edge: this many noise levels of a row mean (no false fronts in noise)
FRONT_TOP_SIGMAS = 3.0

# --- the confidence decision (confidence.py)
# below this confidence the fused method reports no detection rather than a likely wrong
# size (chosen on generated hard scenes: it turns most gross errors into misses)
DEFAULT_MIN_CONFIDENCE = 0.05
