"""Recorded runs of animateBehaviour: the recording file, the allowed bands, motion summaries.

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

Pure Python and numpy: no ROS import.
"""
import datetime
import json
import math
import os
from collections import OrderedDict
from typing import Any, Dict, Iterable, List, Mapping, NamedTuple, Optional, Sequence, Tuple

import numpy

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import DISABLED, ENABLED
from cssr_system.pepper.joint_table import PARTS


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
        if entry.event == contract.CONFIGURATION_LOADED:
            # Read before the window too: the configuration is loaded before the run starts.
            try:
                configured_bound = float(fields.get("items", {}).get("headingBound"))
            except (TypeError, ValueError):
                configured_bound = None
            continue
        if not _in_window(entry.timestamp, since, until):
            continue
        if entry.event == contract.BEHAVIOUR_STARTED and fields.get("wheels"):
            heading_bound = configured_bound
        purpose = fields.get("purpose", contract.PURPOSE_ANIMATE)
        if entry.event != contract.GOAL_SENT or purpose != contract.PURPOSE_ANIMATE:
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
    from cssr_system.animate_behaviour.configuration import ConfigurationError, load_configuration, topic_file_path
    from cssr_system.animate_behaviour.topics import TopicFileError, load_topic_map
    try:
        config = load_configuration(config_file, overrides)
        parts = load_topic_map(topic_file_path(config)).topics
    except (ConfigurationError, TopicFileError) as error:
        raise ValueError(str(error)) from None
    heading_bound = config.heading_bound if "rotation" in config.behaviour else None
    return bands_from_configuration(config, parts), heading_bound


def bands_from_configuration(config: Any, available_parts: Iterable[str]) -> "OrderedDict[str, JointBand]":
    """The joint bands a configuration (``configuration.Configuration``) gives the parts of a
    platform (``available_parts``: keys of its topic file), with ``motion.waypoints``."""
    from cssr_system.animate_behaviour.motion.waypoints import animated_parts  # numpy only, but keeps imports light
    bands = OrderedDict()  # type: OrderedDict[str, JointBand]
    for motion in animated_parts(config, available_parts):
        for bound, moves in zip(motion.bounds, motion.moving):
            bands[bound.name] = JointBand(bound.lower, bound.upper, bound.centre, bool(moves))
    return bands


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
        reference = heading_at_time(recording, start)
        inside = (recording.heading_times >= start) & (recording.heading_times <= end)
        if reference is None or not numpy.any(inside):
            continue
        deviation = numpy.max(numpy.abs(recording.headings[inside] - reference))
        worst = max(worst, float(deviation) - recording.heading_bound)
    return worst


def heading_at_time(recording: Recording, time: float) -> Optional[float]:
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
