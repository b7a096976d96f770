"""obstacle-fusion: an HC-SR04 sonar and one camera, fused into obstacle distance, height and width."""

__version__ = "0.1.0"
