"""With no rig file, a run measures with its online rig fit once there is one."""

from __future__ import annotations

import dataclasses

import pytest
from obstacle_fusion.api import LazyMeasurer
from obstacle_fusion.sim.room_scene import RoomRenderer, RoomSpec
from obstacle_fusion.vision.camera import CameraModel

from tests.vision.rooms import plain_room

pytestmark = pytest.mark.cpu_only

CAM = CameraModel.paper(500, 375)


def scene() -> tuple[object, dict[str, object], RoomSpec]:
    spec = plain_room(4001)
    image, truth = RoomRenderer(CAM).render(spec)
    return image, truth, spec


def test_the_online_rig_is_used_once_it_exists_and_labelled_estimated() -> None:
    image, truth, spec = scene()
    fitted = {"rig": None}
    m = LazyMeasurer(CAM, None, "fused")
    m.rig_provider = lambda: fitted["rig"]
    before = m.measure(image, truth["range_m"])
    assert before.rig_source == "estimated"  # the floor contact found in the frame itself
    fitted["rig"] = spec.rig
    after = m.measure(image, truth["range_m"])
    assert after.rig_source == "estimated" and after.detected, after.reason
    assert after.camera_height_m == spec.rig.camera_height_m
    assert abs(after.height_m / truth["height_m"] - 1) <= 0.05


def test_the_maps_are_rebuilt_only_when_the_fit_moves_beyond_its_noise() -> None:
    image, truth, spec = scene()
    fitted = {"rig": spec.rig}
    m = LazyMeasurer(CAM, None, "fused")
    m.rig_provider = lambda: fitted["rig"]
    m.measure(image, truth["range_m"])
    first = m._online[1]
    fitted["rig"] = dataclasses.replace(spec.rig, camera_height_m=spec.rig.camera_height_m + 0.004)
    m.measure(image, truth["range_m"])
    assert m._online[1] is first
    fitted["rig"] = dataclasses.replace(spec.rig, camera_height_m=spec.rig.camera_height_m + 0.006)
    m.measure(image, truth["range_m"])
    assert m._online[1] is not first


def test_a_rig_file_is_never_replaced_by_the_online_fit() -> None:
    image, truth, spec = scene()
    m = LazyMeasurer(CAM, spec.rig, "fused")
    m.rig_provider = lambda: dataclasses.replace(spec.rig, camera_height_m=0.9)
    assert m.measure(image, truth["range_m"]).rig_source == "file"
