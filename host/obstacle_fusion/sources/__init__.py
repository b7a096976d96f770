"""Frame sources: where camera images come from, each stamped on the host's monotonic clock.

``frames`` holds the :class:`Frame` record and the :class:`FrameSource` base (no OpenCV);
``opencv_sources`` the camera, video-file and image-folder sources built on OpenCV.
"""
