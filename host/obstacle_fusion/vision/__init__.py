"""Vision: one camera frame and the sonar's range -> the obstacle's height and width.

- ``types``        the shared types every method uses (Measurement, View, Line, Timer)
- ``measure``      the method registry and ``Measurer``, the one entry point
- ``fused``        the sonar-guided method, one module per stage; ``paper`` the paper's pipeline
- ``camera``, ``calibration``, ``chessboard``  the camera model and its calibration
- ``rig``          where the camera and sonar sit on the robot
- ``annotate``     drawing a measurement onto a frame

Submodules pull in OpenCV, so this package imports none of them; import what you need
(``from obstacle_fusion.vision.measure import Measurer``).
"""
