"""Recorded runs of animateBehaviour: the recording file, the allowed bands, and the plot.

A recording is what the robot (simulated or real) actually did during a run: every joint over time
from ``/joint_states``, the base heading from odometry, and when the node was enabled and disabled.
``scripts/animateBehaviourDemo.py`` writes one; ``scripts/plotAnimation.py`` plots any of them.

Recording file format: one UTF-8 JSON object (extension ``.json``)::

    {
      "format": "cssr_system/animation-recording",
      "version": 1,
      "start_epoch": 1763740984.12,            # wall-clock time (s since 1970) of time 0
      "info": {"platform": "robot", "behaviour": "all", ...},   # free text, shown in the title
      "activations": [{"time": 1.0, "state": "enabled"}, {"time": 31.0, "state": "disabled"}],
      "joint_states": {
        "joints": ["HeadYaw", "HeadPitch", "HipPitch", ...],    # column names
        "times": [0.0, 0.02, ...],                               # s since time 0, increasing
        "positions": [[0.0, 0.0, -0.11, ...], ...]               # one row per time; null: not measured
      },
      "heading": {"topic": "/pepper_dcm/odom", "times": [...], "values": [...]},  # rad, unwrapped
      "bands": {"RShoulderPitch": {"lower": 1.33, "upper": 1.75, "centre": 1.54, "moving": true}, ...},
      "heading_bound": 0.3                     # rad either side of the heading at enable; null: none
    }

Times are seconds relative to ``start_epoch``. ``bands`` holds the joints the node animated (a
joint with ``moving`` false is held at its centre) and may be empty; ``heading_bound`` is null when
the base was not animated. Floats are written exactly (Python's shortest repr).

Bands of a run come from the node's log file (``goal_sent`` entries: ``lower``/``upper`` per joint,
see `bands_from_log`) when it is available, else from the configuration with
``motion_plan.joint_bounds`` (`bands_from_configuration`).

The plot (`plot_recording`, matplotlib's Agg backend, a PNG): one panel per animated part (each
joint a line, its allowed band [lower, upper] shaded in the line's colour), one panel of the base
heading with its bound around the heading at enable, and the enable/disable instants as vertical
lines in every panel. Each panel's title says whether every sample stayed in its band.

Pure Python, numpy and matplotlib: no ROS import.
"""
import datetime
import json
import math
import os
from collections import OrderedDict
from typing import Any, Dict, Iterable, List, Mapping, NamedTuple, Optional, Sequence, Tuple

import numpy

from cssr_system import log_events
from cssr_system.activation import DISABLED, ENABLED
from cssr_system.joint_table import PARTS

RECORDING_FORMAT = "cssr_system/animation-recording"
RECORDING_VERSION = 1
BASE_LABEL = "base"
# A joint (rad, or hand opening 0..1) or the heading (rad) "moves" when it spans more than this in
# a window: well above the simulator's numerical noise, well below the smallest gesture.
MOTION_THRESHOLD = 0.01
# Samples further than this outside their band are reported in the plot (rad; absorbs float noise).
BAND_TOLERANCE = 1e-3


class JointBand(NamedTuple):
    """The interval a joint was allowed to move in (LB, UB of the design's Table 1)."""

    lower: float
    upper: float
    centre: float
    moving: bool  # False: the joint was held at its centre (lower == upper == centre)


class Recording(NamedTuple):
    """A recorded run (module docstring: file format)."""

    start_epoch: float
    joint_names: Tuple[str, ...]
    times: numpy.ndarray  # (N,) s since start_epoch
    positions: numpy.ndarray  # (N, len(joint_names)); NaN where a joint was not measured
    heading_times: numpy.ndarray  # (M,)
    headings: numpy.ndarray  # (M,) rad, unwrapped
    activations: Tuple[Tuple[float, str], ...] = ()  # (time, ENABLED or DISABLED), in time order
    bands: Mapping[str, JointBand] = {}
    heading_bound: Optional[float] = None
    info: Mapping[str, str] = {}
    heading_topic: str = ""


# ---------------------------------------------------------------------------------------------------
# Reading and writing.

def _number_or_none(value: float) -> Optional[float]:
    return None if value is None or not math.isfinite(value) else float(value)


def recording_to_json(recording: Recording) -> Dict[str, Any]:
    """The JSON object of the file format."""
    return OrderedDict([
        ("format", RECORDING_FORMAT),
        ("version", RECORDING_VERSION),
        ("start_epoch", float(recording.start_epoch)),
        ("info", OrderedDict((str(key), str(value)) for key, value in recording.info.items())),
        ("activations", [OrderedDict([("time", float(time)), ("state", state)])
                         for time, state in recording.activations]),
        ("joint_states", OrderedDict([
            ("joints", list(recording.joint_names)),
            ("times", [float(time) for time in recording.times]),
            ("positions", [[_number_or_none(value) for value in row] for row in recording.positions]),
        ])),
        ("heading", OrderedDict([
            ("topic", recording.heading_topic),
            ("times", [float(time) for time in recording.heading_times]),
            ("values", [float(value) for value in recording.headings]),
        ])),
        ("bands", OrderedDict((name, OrderedDict([("lower", band.lower), ("upper", band.upper),
                                                  ("centre", band.centre), ("moving", band.moving)]))
                              for name, band in recording.bands.items())),
        ("heading_bound", recording.heading_bound),
    ])


def write_recording(path: str, recording: Recording) -> str:
    """Write `recording` to `path` (JSON, module docstring); returns the absolute path."""
    path = os.path.abspath(path)
    folder = os.path.dirname(path)
    os.makedirs(folder, exist_ok=True)
    temporary = path + ".tmp"
    with open(temporary, "w", encoding="utf-8") as output:
        json.dump(recording_to_json(recording), output, allow_nan=False)
        output.write("\n")
    os.replace(temporary, path)  # a reader never sees half a file
    return path


def _array(values: Any, what: str, source: str) -> numpy.ndarray:
    try:
        return numpy.array([numpy.nan if value is None else float(value) for value in values], dtype=float)
    except (TypeError, ValueError):
        raise ValueError("%s: %s must be a list of numbers" % (source, what)) from None


def recording_from_json(data: Any, source: str = "recording") -> Recording:
    """The recording of a parsed JSON object; ValueError naming `source` and the field if invalid."""
    if not isinstance(data, dict) or data.get("format") != RECORDING_FORMAT:
        raise ValueError("%s: not an animation recording (expected \"format\": \"%s\")"
                         % (source, RECORDING_FORMAT))
    if data.get("version") != RECORDING_VERSION:
        raise ValueError("%s: unsupported recording version %r (this tool reads version %d)"
                         % (source, data.get("version"), RECORDING_VERSION))
    try:
        joint_states = data["joint_states"]
        names = tuple(str(name) for name in joint_states["joints"])
        times = _array(joint_states["times"], "joint_states.times", source)
        rows = joint_states["positions"]
        if len(rows) != len(times):
            raise ValueError("%s: joint_states has %d times but %d rows of positions"
                             % (source, len(times), len(rows)))
        positions = numpy.full((len(times), len(names)), numpy.nan)
        for index, row in enumerate(rows):
            if len(row) != len(names):
                raise ValueError("%s: joint_states.positions[%d] has %d values for %d joints"
                                 % (source, index, len(row), len(names)))
            positions[index] = _array(row, "joint_states.positions[%d]" % index, source)
        heading = data.get("heading") or {}
        heading_times = _array(heading.get("times", []), "heading.times", source)
        headings = _array(heading.get("values", []), "heading.values", source)
        if len(heading_times) != len(headings):
            raise ValueError("%s: heading has %d times but %d values"
                             % (source, len(heading_times), len(headings)))
        activations = tuple((float(item["time"]), str(item["state"]))
                            for item in data.get("activations", []))
        for _, state in activations:
            if state not in (ENABLED, DISABLED):
                raise ValueError("%s: activation state %r (expected %r or %r)"
                                 % (source, state, ENABLED, DISABLED))
        bands = OrderedDict(
            (str(name), JointBand(float(band["lower"]), float(band["upper"]), float(band["centre"]),
                                  bool(band["moving"])))
            for name, band in (data.get("bands") or {}).items())
        bound = data.get("heading_bound")
        return Recording(
            start_epoch=float(data["start_epoch"]),
            joint_names=names,
            times=times,
            positions=positions,
            heading_times=heading_times,
            headings=headings,
            activations=tuple(sorted(activations)),
            bands=bands,
            heading_bound=None if bound is None else float(bound),
            info=OrderedDict((str(key), str(value)) for key, value in (data.get("info") or {}).items()),
            heading_topic=str(heading.get("topic", "")),
        )
    except KeyError as error:
        raise ValueError("%s: missing field %s" % (source, error)) from None
    except (TypeError, AttributeError) as error:
        raise ValueError("%s: malformed recording (%s)" % (source, error)) from None


def read_recording(path: str) -> Recording:
    """The recording in the file at `path`; ValueError (or OSError) with a clear message."""
    with open(path, "r", encoding="utf-8") as source_file:
        try:
            data = json.load(source_file)
        except ValueError as error:
            raise ValueError("%s: not JSON (%s)" % (path, error)) from None
    return recording_from_json(data, path)


# ---------------------------------------------------------------------------------------------------
# Bands.

def _in_window(entry_time: datetime.datetime, since: Optional[float], until: Optional[float]) -> bool:
    moment = entry_time.timestamp()
    return (since is None or moment >= since) and (until is None or moment <= until)


def bands_from_log(entries: Iterable[Any], since: Optional[float] = None,
                   until: Optional[float] = None) -> Tuple["OrderedDict[str, JointBand]", Optional[float]]:
    """The joint bands and the heading bound of a run, from the node's log entries
    (``event_log.read_log``) between the epochs `since` and `until` (None: no limit).

    Bands: the ``lower``/``upper`` of every animating ``goal_sent`` (``purpose`` "animate"); a
    reconfiguration during the run widens a band to the hull of all its bands. Heading bound: the
    ``headingBound`` of the last ``configuration_loaded`` before the last ``behaviour_started``
    whose ``wheels`` is set; None when the base was not animated (or the log does not say).
    """
    bands = OrderedDict()  # type: OrderedDict[str, JointBand]
    heading_bound = None  # type: Optional[float]
    configured_bound = None  # type: Optional[float]
    for entry in entries:
        fields = entry.fields
        if entry.event == log_events.CONFIGURATION_LOADED:
            # Read before the window too: the configuration is loaded before the run starts.
            try:
                configured_bound = float(fields.get("items", {}).get("headingBound"))
            except (TypeError, ValueError):
                configured_bound = None
            continue
        if not _in_window(entry.timestamp, since, until):
            continue
        if entry.event == log_events.BEHAVIOUR_STARTED and fields.get("wheels"):
            heading_bound = configured_bound
        purpose = fields.get("purpose", log_events.PURPOSE_ANIMATE)
        if entry.event != log_events.GOAL_SENT or purpose != log_events.PURPOSE_ANIMATE:
            continue
        joints = fields.get("joints") or []
        lower = fields.get("lower") or []
        upper = fields.get("upper") or []
        centre = fields.get("centre") or []
        moving = fields.get("moving") or [True] * len(joints)
        if not (len(joints) == len(lower) == len(upper) == len(moving)):
            continue  # a goal without bounds (homing): nothing to learn
        for index, name in enumerate(joints):
            middle = float(centre[index]) if index < len(centre) else (lower[index] + upper[index]) / 2.0
            band = JointBand(float(lower[index]), float(upper[index]), middle, bool(moving[index]))
            if name in bands:
                known = bands[name]
                band = JointBand(min(known.lower, band.lower), max(known.upper, band.upper),
                                 known.centre, known.moving or band.moving)
            bands[name] = band
    return bands, heading_bound


def bands_from_configuration_file(config_file: str, overrides: Optional[Dict[str, str]] = None
                                  ) -> Tuple["OrderedDict[str, JointBand]", Optional[float]]:
    """The joint bands and the heading bound (None without rotation) of a configuration file, with
    `overrides` of its keys (e.g. platform, behaviour); ValueError with one line when it is invalid."""
    from cssr_system.configuration import ConfigurationError, load_configuration, topic_file_path
    from cssr_system.topics import TopicFileError, load_topic_map
    try:
        config = load_configuration(config_file, overrides)
        parts = load_topic_map(topic_file_path(config)).topics
    except (ConfigurationError, TopicFileError) as error:
        raise ValueError(str(error)) from None
    heading_bound = config.heading_bound if "rotation" in config.behaviour else None
    return bands_from_configuration(config, parts), heading_bound


def bands_from_configuration(config: Any, available_parts: Iterable[str]) -> "OrderedDict[str, JointBand]":
    """The joint bands a configuration (``configuration.Configuration``) gives the parts of a
    platform (``available_parts``: keys of its topic file), with ``motion_plan``."""
    from cssr_system.motion_plan import animated_parts  # numpy only, but keeps imports light
    bands = OrderedDict()  # type: OrderedDict[str, JointBand]
    for motion in animated_parts(config, available_parts):
        for bound, moves in zip(motion.bounds, motion.moving):
            bands[bound.name] = JointBand(bound.lower, bound.upper, bound.centre, bool(moves))
    return bands


# ---------------------------------------------------------------------------------------------------
# Motion summaries (used by the live demo output and by the plot).

def yaw_from_quaternion(x: float, y: float, z: float, w: float) -> float:
    """Rotation about the vertical axis (rad, in (-pi, pi]) of an orientation quaternion."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def unwrap_heading(previous: Optional[float], yaw: float) -> float:
    """`yaw` shifted by whole turns to be closest to the unwrapped `previous` heading."""
    if previous is None:
        return yaw
    return previous + math.remainder(yaw - previous, 2.0 * math.pi)


def moving_parts(joint_names: Sequence[str], positions: numpy.ndarray,
                 threshold: float = MOTION_THRESHOLD) -> List[str]:
    """Labels of the parts (``joint_table.PARTS`` order) of which some joint spans more than
    `threshold` in `positions` (rows: samples of a time window, columns: `joint_names`)."""
    positions = numpy.asarray(positions, dtype=float)
    if positions.ndim != 2 or positions.shape[0] < 2:
        return []
    with numpy.errstate(invalid="ignore"):
        spans = numpy.nanmax(positions, axis=0) - numpy.nanmin(positions, axis=0) \
            if not numpy.all(numpy.isnan(positions)) else numpy.zeros(positions.shape[1])
    span_of = {name: span for name, span in zip(joint_names, spans)}
    labels = []
    for part in PARTS.values():
        if any(span_of.get(name, 0.0) > threshold for name in part.joints):
            labels.append(part.label)
    return labels


def enabled_intervals(recording: Recording) -> List[Tuple[float, float]]:
    """(start, end) of each time the node was enabled; an open end is the end of the recording."""
    end = max([float(recording.times[-1]) if len(recording.times) else 0.0,
               float(recording.heading_times[-1]) if len(recording.heading_times) else 0.0]
              + [time for time, _ in recording.activations])
    intervals = []
    started = None
    for time, state in recording.activations:
        if state == ENABLED and started is None:
            started = time
        elif state == DISABLED and started is not None:
            intervals.append((started, time))
            started = None
    if started is not None:
        intervals.append((started, end))
    return intervals


def band_excess(recording: Recording, joint_name: str) -> float:
    """How far the joint went outside its band at worst (0.0: always inside; rad or hand units)."""
    band = recording.bands.get(joint_name)
    if band is None or joint_name not in recording.joint_names:
        return 0.0
    values = recording.positions[:, recording.joint_names.index(joint_name)]
    values = values[numpy.isfinite(values)]
    if len(values) == 0:
        return 0.0
    return float(max(0.0, numpy.max(values) - band.upper, band.lower - numpy.min(values)))


def heading_excess(recording: Recording) -> float:
    """How far the heading went beyond its bound around the heading at each enable (0.0: never)."""
    if recording.heading_bound is None or len(recording.headings) == 0:
        return 0.0
    worst = 0.0
    for start, end in enabled_intervals(recording):
        reference = _heading_at(recording, start)
        inside = (recording.heading_times >= start) & (recording.heading_times <= end)
        if reference is None or not numpy.any(inside):
            continue
        deviation = numpy.max(numpy.abs(recording.headings[inside] - reference))
        worst = max(worst, float(deviation) - recording.heading_bound)
    return worst


def _heading_at(recording: Recording, time: float) -> Optional[float]:
    if len(recording.headings) == 0:
        return None
    return float(numpy.interp(time, recording.heading_times, recording.headings))


def plotted_parts(recording: Recording) -> List[Tuple[str, Tuple[str, ...]]]:
    """(label, joints) of the parts to plot: those with a band (animated), in ``PARTS`` order; when
    the recording has no bands, the parts that moved."""
    if recording.bands:
        return [(part.label, part.joints) for part in PARTS.values()
                if any(name in recording.bands for name in part.joints)]
    moved = set(moving_parts(recording.joint_names, recording.positions))
    return [(part.label, part.joints) for part in PARTS.values() if part.label in moved]


# ---------------------------------------------------------------------------------------------------
# The plot.

def _title_of(recording: Recording) -> str:
    moment = datetime.datetime.fromtimestamp(recording.start_epoch).strftime("%Y-%m-%d %H:%M:%S")
    details = ", ".join("%s %s" % (key, value) for key, value in recording.info.items()
                        if key in ("behaviour", "platform"))
    return "animateBehaviour: joints and base heading over time" + \
        ("  (%s; %s)" % (details, moment) if details else "  (%s)" % moment)


def _draw_activations(axis: Any, recording: Recording) -> None:
    for time, state in recording.activations:
        if state == ENABLED:
            axis.axvline(time, color="tab:green", linewidth=1.6)
        else:
            axis.axvline(time, color="tab:red", linewidth=1.6, linestyle="--")


def time_origin(recording: Recording) -> float:
    """Time shown as 0 in the plot: the first enable, else the start of the recording."""
    enables = [time for time, state in recording.activations if state == ENABLED]
    return enables[0] if enables else 0.0


def plot_recording(recording: Recording, output_path: str, title: Optional[str] = None) -> str:
    """Plot `recording` into the PNG `output_path` (module docstring); returns its absolute path."""
    import matplotlib
    matplotlib.use("Agg")  # no display needed; safe when pyplot was not imported before
    import matplotlib.pyplot as pyplot
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    origin = time_origin(recording)
    shifted = recording._replace(times=recording.times - origin,
                                 heading_times=recording.heading_times - origin,
                                 activations=tuple((time - origin, state) for time, state in recording.activations))
    parts = plotted_parts(shifted)
    panels = len(parts) + 1  # the base heading last
    columns = 2 if panels > 3 else 1
    rows = int(math.ceil(panels / float(columns)))
    figure, axes = pyplot.subplots(rows, columns, figsize=(8.0 * columns, 3.4 * rows + 1.0),
                                   sharex=True, squeeze=False)
    flat_axes = [axis for row in axes for axis in row]
    colours = pyplot.rcParams["axes.prop_cycle"].by_key()["color"]
    for index, (label, joints) in enumerate(parts):
        _plot_part(flat_axes[index], shifted, label, joints, colours)
    _plot_heading(flat_axes[len(parts)], shifted)
    for axis in flat_axes[panels:]:
        axis.set_visible(False)
    enabled = any(state == ENABLED for _, state in recording.activations)
    x_label = "time since enabled (s)" if enabled else "time since the recording started (s)"
    for column in range(columns):  # x labels under the lowest visible panel of each column
        for row in reversed(range(rows)):
            if row * columns + column < panels:
                axes[row][column].set_xlabel(x_label)
                axes[row][column].tick_params(labelbottom=True)
                break
    figure.suptitle(title or _title_of(recording), fontsize=13)
    key = [Line2D([], [], color="tab:green", linewidth=1.6, label="enabled"),
           Line2D([], [], color="tab:red", linewidth=1.6, linestyle="--", label="disabled"),
           Patch(facecolor="grey", alpha=0.25, label="allowed band of the joint of the same colour"),
           Line2D([], [], color="grey", linewidth=0.8, linestyle=":", label="band edges; alone: joint held")]
    figure.legend(handles=key, loc="upper center", ncol=4, fontsize=9, frameon=False,
                  bbox_to_anchor=(0.5, 0.965))
    figure.tight_layout(rect=(0, 0, 1, 0.94))
    output_path = os.path.abspath(output_path)
    os.makedirs(os.path.dirname(output_path), exist_ok=True)
    figure.savefig(output_path, dpi=100)
    pyplot.close(figure)
    return output_path


def _plot_part(axis: Any, recording: Recording, label: str, joints: Sequence[str],
               colours: Sequence[str]) -> None:
    worst_joint, worst = "", 0.0
    for index, name in enumerate(joints):
        colour = colours[index % len(colours)]
        band = recording.bands.get(name)
        if band is not None and band.moving:
            axis.axhspan(band.lower, band.upper, color=colour, alpha=0.13, linewidth=0)
            axis.axhline(band.lower, color=colour, alpha=0.6, linewidth=0.8, linestyle=":")
            axis.axhline(band.upper, color=colour, alpha=0.6, linewidth=0.8, linestyle=":")
        elif band is not None:
            axis.axhline(band.centre, color=colour, alpha=0.6, linewidth=0.8, linestyle=":")
        if name in recording.joint_names:
            values = recording.positions[:, recording.joint_names.index(name)]
            shown = name + ("" if band is None or band.moving else " (held)")
            axis.plot(recording.times, values, color=colour, linewidth=1.3, label=shown)
        excess = band_excess(recording, name)
        if excess > worst:
            worst_joint, worst = name, excess
    _draw_activations(axis, recording)
    verdict = "every joint within its band" if worst <= BAND_TOLERANCE else \
        "%s %.3f beyond its band" % (worst_joint, worst)
    axis.set_title("%s: %s" % (label, verdict), fontsize=11,
                   color="black" if worst <= BAND_TOLERANCE else "tab:red")
    hand = all(name.endswith("Hand") for name in joints)
    axis.set_ylabel("opening (0 closed, 1 open)" if hand else "angle (rad)")
    axis.grid(True, alpha=0.3)
    _leave_room_for_legend(axis)
    axis.legend(loc="upper left", fontsize=8, ncol=min(len(joints), 5), framealpha=0.85,
                handlelength=1.5, columnspacing=1.0)


def _leave_room_for_legend(axis: Any) -> None:
    bottom, top = axis.get_ylim()
    axis.set_ylim(bottom, top + 0.22 * (top - bottom))


def _plot_heading(axis: Any, recording: Recording) -> None:
    if len(recording.headings):
        axis.plot(recording.heading_times, recording.headings, color="tab:blue", linewidth=1.4,
                  label="heading")
    if recording.heading_bound is not None:
        labelled = False
        for start, end in enabled_intervals(recording):
            reference = _heading_at(recording, start)
            if reference is None:
                continue
            axis.fill_between([start, end], reference - recording.heading_bound,
                              reference + recording.heading_bound, color="tab:blue", alpha=0.12,
                              linewidth=0,
                              label=None if labelled else "bound: heading at enable \u00b1 %.2f rad"
                              % recording.heading_bound)
            labelled = True
        excess = heading_excess(recording)
        verdict = "within its bound" if excess <= BAND_TOLERANCE else "%.3f rad beyond its bound" % excess
    else:
        verdict = "base not animated (no bound)"
    _draw_activations(axis, recording)
    topic = " (%s)" % recording.heading_topic if recording.heading_topic else ""
    axis.set_title("base heading%s: %s" % (topic, verdict), fontsize=11)
    axis.set_ylabel("heading (rad)")
    axis.grid(True, alpha=0.3)
    bottom, top = axis.get_ylim()
    if top - bottom < 0.2:  # a still base: show a readable scale, not float noise
        middle = (top + bottom) / 2.0
        axis.set_ylim(middle - 0.1, middle + 0.1)
    _leave_room_for_legend(axis)
    axis.legend(loc="upper left", fontsize=8, ncol=2, framealpha=0.85)
