"""An animated GIF of Pepper's figure from a recording: front and side views, time and enabled/disabled on every
frame (doc/figure.md, README: "See Pepper move").

The figure is `body_model`'s solids on `kinematics`' frames, driven by the recorded joints and base heading: a
model, not the robot's meshes. Every frame's pose is computed at once; each frame then only moves the artists'
data (capsules are thick round-capped lines, boxes polygons), so a 30 s recording renders in seconds. matplotlib
draws, Pillow writes the GIF. Pure Python: no ROS import.
"""
import bisect
from typing import List, NamedTuple, Optional, Sequence, Tuple

import numpy

from cssr_system.figure.body_model import ARMS, BODY, Box, Capsule, box_corners, segment_ends
from cssr_system.figure.clearance import filled
from cssr_system.figure.kinematics import Frames, link_frames

FRAME_RATE = 10.0  # frames a second
FIGURE_SIZE = (6.4, 3.6)  # inches, at DPI: a 512 x 288 GIF
DPI = 80
SPAN = 1.3  # m shown along each axis: equal spans keep the proportions (mplot3d has no box aspect in 3.1)
FACES = ((0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5))  # box_corners' order
COLOURS = {"base": "#8c8c8c", "leg": "#a0a0a0", "hip": "#7a7a7a", "torso": "#e0e0e0", "tablet": "#303030",
           "head": "#ededed"}
ZOOM = 1.5  # the robot fills the view's height
ARM_COLOURS = {"left": "#1f77b4", "right": "#d62728"}
HAND_COLOURS = {"left": "#0b3c5d", "right": "#7f1415"}  # darker: the hands stand out from the forearms
STATE_COLOURS = {"enabled": "#2ca02c", "disabled": "#7f7f7f", "not recorded": "#7f7f7f"}
VIEWS = (("front", 8.0, 0.0), ("side (from its right)", 8.0, -90.0))  # title, elevation, azimuth


class Motion(NamedTuple):
    """What the figure shows at each frame."""

    times: numpy.ndarray  # (F,) s
    frames: Frames  # F instants
    states: Tuple[str, ...]  # "enabled", "disabled" or "not recorded", per frame


def sample_motion(joint_names: Sequence[str], times: numpy.ndarray, positions: numpy.ndarray,
                  heading_times: numpy.ndarray, headings: numpy.ndarray,
                  activations: Sequence[Tuple[float, str]], frame_rate: float = FRAME_RATE) -> Motion:
    """The poses at `frame_rate` from the first to the last joint sample: each joint's last sample at or before the
    frame, the heading interpolated (0 when none was recorded)."""
    if len(times) == 0:
        raise ValueError("the recording has no joint states")
    frame_times = numpy.arange(times[0], times[-1] + 1e-9, 1.0 / frame_rate)
    rows = numpy.clip(numpy.searchsorted(times, frame_times, side="right") - 1, 0, len(times) - 1)
    angles = {name: filled(positions[:, column])[rows] for column, name in enumerate(joint_names)
              if not numpy.all(numpy.isnan(positions[:, column]))}
    heading = (numpy.interp(frame_times, heading_times, headings) - headings[0] if len(heading_times)
               else numpy.zeros(len(frame_times)))
    return Motion(frame_times, link_frames(angles, heading, count=len(frame_times)),
                  tuple(state_at(activations, time) for time in frame_times))


def state_at(activations: Sequence[Tuple[float, str]], time: float) -> str:
    """The last activation at or before `time`; disabled before the first; "not recorded" without any."""
    if not activations:
        return "not recorded"
    index = bisect.bisect_right([moment for moment, _ in activations], time) - 1
    return activations[index][1] if index >= 0 else "disabled"


class _View:
    """One 3D axes: an artist per solid, whose data each frame replaces."""

    def __init__(self, figure, position: int, title: str, elevation: float, azimuth: float) -> None:
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: F401 (registers the 3d projection)
        self.axes = figure.add_subplot(1, 2, position, projection="3d")
        self.axes.view_init(elev=elevation, azim=azimuth)
        self.axes.set_xlim(-SPAN / 2, SPAN / 2)
        self.axes.set_ylim(-SPAN / 2, SPAN / 2)
        self.axes.set_zlim(-0.02, SPAN - 0.02)
        self.axes.set_axis_off()
        if hasattr(self.axes, "set_box_aspect"):  # matplotlib 3.6 and later
            self.axes.set_box_aspect((1, 1, 1), zoom=ZOOM)
        else:  # matplotlib 3.1 (Noetic's): the camera's distance, 10 by default
            self.axes.dist = 10 / ZOOM
        self.axes.set_title(title, fontsize=9)
        self.points_per_metre = 0.45 * ZOOM * FIGURE_SIZE[1] * 72 / SPAN  # a line's width in points for a metre
        floor = SPAN / 2 * 0.9
        self.axes.plot([-floor, floor, floor, -floor, -floor], [-floor, -floor, floor, floor, -floor], [0] * 5,
                       color="#bbbbbb", linewidth=0.8)
        self.boxes, self.capsules = [], []
        for solid in BODY:
            self._add(solid, COLOURS[solid.name])
        for arm, solids in ARMS.items():
            for solid in solids:
                self._add(solid, HAND_COLOURS[arm] if solid.name.endswith("hand") else ARM_COLOURS[arm])

    def _add(self, solid, colour: str) -> None:
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection
        if isinstance(solid, Box):
            collection = Poly3DCollection([numpy.zeros((4, 3))] * len(FACES), facecolor=colour, edgecolor="#555555",
                                          linewidth=0.5, alpha=0.9)
            self.axes.add_collection3d(collection)
            self.boxes.append((solid, collection))
            return
        width = 2 * solid.radius * self.points_per_metre
        line, = self.axes.plot([0, 0], [0, 0], [0, 0], color=colour, linewidth=width, solid_capstyle="round",
                               marker="o" if solid.start == solid.end else None, markersize=width,
                               markeredgecolor="#555555" if solid.start == solid.end else None)
        self.capsules.append((solid, line))

    def update(self, ends, corners, index: int) -> None:
        for solid, collection in self.boxes:
            points = corners[solid.name][index]
            collection.set_verts([points[list(face)] for face in FACES])
        for solid, line in self.capsules:
            start, end = ends[solid.name]
            line.set_data([start[index, 0], end[index, 0]], [start[index, 1], end[index, 1]])
            line.set_3d_properties([start[index, 2], end[index, 2]])


def render_gif(motion: Motion, output: str, title: str = "") -> str:
    """Writes the animated GIF of `motion` to `output`; returns `output`."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as pyplot
    from PIL import Image

    figure = pyplot.figure(figsize=FIGURE_SIZE, dpi=DPI)
    figure.subplots_adjust(left=0, right=1, bottom=0, top=0.88, wspace=0)
    views = [_View(figure, position, *view) for position, view in enumerate(VIEWS, start=1)]
    ends = {solid.name: segment_ends(solid, motion.frames) for solid in _all_solids() if isinstance(solid, Capsule)}
    corners = {solid.name: box_corners(solid, motion.frames) for solid in BODY if isinstance(solid, Box)}
    figure.text(0.01, 0.97, title or "Pepper's figure (a model from kinematics)", fontsize=8, va="top")
    clock = figure.text(0.99, 0.97, "", fontsize=10, ha="right", va="top", family="monospace", color="white",
                        bbox=dict(boxstyle="round", facecolor="white", edgecolor="none"))
    for offset, (state, colour) in enumerate(sorted(STATE_COLOURS.items())[:2]):  # every colour in every frame
        figure.text(0.01 + 0.09 * offset, 0.02, state, fontsize=7, color="white",
                    bbox=dict(boxstyle="round", facecolor=colour, edgecolor="none"))
    images: List = []
    palette = None
    for index, time in enumerate(motion.times):
        for view in views:
            view.update(ends, corners, index)
        state = motion.states[index]
        clock.set_text("t = %5.1f s  %s" % (time, state))
        clock.get_bbox_patch().set_facecolor(STATE_COLOURS.get(state, "black"))
        figure.canvas.draw()
        width, height = figure.canvas.get_width_height()
        image = Image.frombuffer("RGBA", (width, height), figure.canvas.buffer_rgba(), "raw", "RGBA", 0, 1)
        image = image.convert("RGB")
        if palette is None:  # one palette for every frame: small files, no flicker
            palette = image.quantize(colors=64)
        images.append(image.quantize(palette=palette))
    pyplot.close(figure)
    images[0].save(output, save_all=True, append_images=images[1:], duration=int(1000 / FRAME_RATE), loop=0)
    return output


def _all_solids() -> List:
    return list(BODY) + [solid for solids in ARMS.values() for solid in solids]


def render_recording(recording, output: str, title: Optional[str] = None) -> str:
    """The GIF of a `recording.Recording` (its joints, heading and activations)."""
    motion = sample_motion(recording.joint_names, recording.times, recording.positions, recording.heading_times,
                           recording.headings, recording.activations)
    label = title if title is not None else " ".join("%s %s" % item for item in recording.info.items()
                                                     if item[0] in ("platform", "behaviour", "style", "robot"))
    return render_gif(motion, output, label)
