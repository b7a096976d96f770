"""Write tools/foxglove/layout.json: the Foxglove layout for obstacle-fusion's topics.

Built with foxglove-sdk's layout types (``foxglove.layouts``): the camera image with its
annotations (box, edges, L/H/W), the 3D view following the robot frame (the obstacle's cube,
the camera and sonar frames), a plot of the sonar range and the fused height and width,
and the link log. A test regenerates it and fails on any difference; run
``.venv/bin/python tools/foxglove/make_layout.py`` after changing it.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import foxglove.layouts as fl
from obstacle_fusion.outputs.foxglove_schemas import (
    FRAME_ROBOT,
    TOPIC_ANNOTATIONS,
    TOPIC_CALIBRATION,
    TOPIC_IMAGE,
    TOPIC_OBSTACLE,
    TOPIC_RANGE,
    TOPIC_SCENE,
)

OUT = Path(__file__).with_name("layout.json")


def layout() -> fl.Layout:
    image = fl.ImagePanel(
        title="camera + annotations",
        config=fl.ImageConfig(
            image_mode=fl.ImageModeConfig(
                image_topic=TOPIC_IMAGE,
                calibration_topic=TOPIC_CALIBRATION,
                annotations={TOPIC_ANNOTATIONS: fl.ImageAnnotationSettings(visible=True)},
                synchronize=False,
            )
        ),
    )
    three_d = fl.ThreeDeePanel(
        title="obstacle in 3D",
        config=fl.ThreeDeeConfig(
            follow_tf=FRAME_ROBOT,
            topics={TOPIC_SCENE: fl.BaseRendererSceneUpdateTopicSettings(visible=True)},
        ),
    )
    plot = fl.PlotPanel(
        title="range and size (m)",
        config=fl.PlotConfig(
            paths=[
                fl.PlotSeries(value=f"{TOPIC_RANGE}.distance_m", label="sonar range", enabled=True),
                fl.PlotSeries(value=f"{TOPIC_OBSTACLE}.height_m", label="height", enabled=True),
                fl.PlotSeries(value=f"{TOPIC_OBSTACLE}.width_m", label="width", enabled=True),
            ],
            show_legend=True,
        ),
    )
    log = fl.LogPanel(title="link events")
    return fl.Layout(
        content=fl.SplitContainer(
            direction="row",
            items=[
                fl.SplitItem(proportion=3, content=image),
                fl.SplitItem(
                    proportion=2,
                    content=fl.SplitContainer(
                        direction="column",
                        items=[
                            fl.SplitItem(proportion=2, content=three_d),
                            fl.SplitItem(proportion=2, content=plot),
                            fl.SplitItem(proportion=1, content=log),
                        ],
                    ),
                ),
            ],
        )
    )


def render() -> str:
    return json.dumps(json.loads(layout().to_json()), indent=2, sort_keys=True) + "\n"


def main() -> int:
    OUT.write_text(render(), encoding="utf-8")
    print(f"wrote {OUT}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
