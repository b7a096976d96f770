"""obstacle-fusion: an HC-SR04 sonar and one camera, fused into obstacle range, height, width."""

__version__ = "0.1.0"
