"""Simulation, apart from the robot's code path: what stands in for a board and a camera.

- ``emulator``          the simavr-based firmware emulator (real firmware ELF, virtual HC-SR04)
- ``scenario``          a scripted world: the obstacle's distance over time
- ``emulated_robot``    the emulator driven by a scenario, with its clock mapping
- ``scene``             the renderer of synthetic rooms with a box obstacle (ground truth)
- ``synthetic_camera``  a frame source filming the scenario's world through the renderer

Importing this package imports nothing heavy; the renderer pulls in OpenCV when used.
"""
