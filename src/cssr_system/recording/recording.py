"""Recorded runs of animateBehaviour: the recording file, the allowed bands, motion summaries.

A recording is what the robot (simulated or real) actually did during a run: every joint over time
from ``/joint_states``, the base heading from odometry, and when the node was enabled and disabled;
optionally what the node commanded and labelled intervals such as another node's goals.
``scripts/animateBehaviourRecorder.py`` (`recorder_node`) writes one; ``scripts/plotAnimation.py``
plots any of them.

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
      "heading_bound": 0.3,                    # rad either side of the heading at enable; null: none
      "commanded": {                           # optional: what one node commanded the controllers
        "source": "/animateBehaviour",         # that node
        "joints": ["RShoulderPitch", ...],     # column names
        "times": [0.0, 0.02, ...],             # s since time 0, increasing
        "positions": [[null, ...], [1.54, ...], ...]   # null: nothing of that node in effect
      },
      "marks": [                               # optional: labelled intervals, e.g. another node's goal
        {"start": 5.1, "end": 9.1, "part": "RArm", "label": "/someNode goal: SUCCEEDED"}
      ],
      "band_changes": [                        # optional: a joint's band from a time on (a change of settings)
        {"time": 10.2, "joint": "RShoulderPitch", "lower": 1.44, "upper": 1.65}
      ],
      "modes": [                               # optional: the node's mode from a time on (its status topic)
        {"time": 0.4, "mode": "idle"}, {"time": 3.1, "mode": "listening"}
      ]
    }

Times are seconds relative to ``start_epoch``. ``bands`` holds the joints the node animated (a
joint with ``moving`` false is held at its centre) and may be empty; ``heading_bound`` is null when
the base was not animated. ``commanded`` and ``marks`` may be absent (recordings written before
they existed have neither; readers that do not know them ignore them): ``commanded`` is the
position the controller was told to be at, at every time, by the ``source`` node (`commanded`
module); a mark's ``part`` is a key of ``joint_table.PARTS`` (its panel in the plot) or "" (every
panel). Floats are written exactly (Python's shortest repr).

Bands of a run come from the node's log file (``goal_sent`` entries: ``lower``/``upper`` per joint,
see `bands_from_log`) when it is available, else from the configuration with
``motion_plan.joint_bounds`` (`bands_from_configuration`). The enable and disable instants come
from the log's ``activation_request`` entries (`activations_from_log`).

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


# File names of a recorder's output folder.
RECORDING_FILE_NAME = "animation.json"
PLOT_FILE_NAME = "animation.png"


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
    commanded: Optional["Commanded"] = None
    marks: Tuple["Mark", ...] = ()
    band_changes: Tuple["BandChange", ...] = ()
    modes: Tuple[Tuple[float, str], ...] = ()  # (time, mode) at each change of the node's mode, in time order


class BandChange(NamedTuple):
    """A joint's band from `time` on (optional field ``band_changes``): the live settings change bands during a run."""

    time: float  # s since start_epoch
    joint: str
    lower: float
    upper: float


class Commanded(NamedTuple):
    """What one node commanded the controllers over time (optional field ``commanded``)."""

    joint_names: Tuple[str, ...]
    times: numpy.ndarray  # (K,) s since start_epoch
    positions: numpy.ndarray  # (K, len(joint_names)); NaN where no command of `source` was in effect
    source: str = ""  # the node that commanded


class Mark(NamedTuple):
    """A labelled interval of a run (optional field ``marks``), e.g. another node's goal on a part."""

    start: float  # s since start_epoch
    end: float
    label: str
    part: str = ""  # key of joint_table.PARTS whose panel shows it; "": every panel


def _number_or_none(value: float) -> Optional[float]:
    return None if value is None or not math.isfinite(value) else float(value)


def recording_to_json(recording: Recording) -> Dict[str, Any]:
    """The JSON object of the file format."""
    data = OrderedDict([
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
    if recording.commanded is not None:
        commanded = recording.commanded
        data["commanded"] = OrderedDict([
            ("source", commanded.source),
            ("joints", list(commanded.joint_names)),
            ("times", [float(time) for time in commanded.times]),
            ("positions", [[_number_or_none(value) for value in row] for row in commanded.positions]),
        ])
    if recording.marks:
        data["marks"] = [OrderedDict([("start", float(mark.start)), ("end", float(mark.end)), ("part", mark.part),
                                      ("label", mark.label)]) for mark in recording.marks]
    if recording.band_changes:
        data["band_changes"] = [OrderedDict(change._asdict()) for change in recording.band_changes]
    if recording.modes:
        data["modes"] = [OrderedDict([("time", float(time)), ("mode", mode)]) for time, mode in recording.modes]
    return data


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


def _table(section: Any, name: str, source: str) -> Tuple[Tuple[str, ...], numpy.ndarray, numpy.ndarray]:
    """(joints, times, positions) of a ``{"joints", "times", "positions"}`` section of the file."""
    names = tuple(str(joint) for joint in section["joints"])
    times = _array(section["times"], name + ".times", source)
    rows = section["positions"]
    if len(rows) != len(times):
        raise ValueError("%s: %s has %d times but %d rows of positions" % (source, name, len(times), len(rows)))
    positions = numpy.full((len(times), len(names)), numpy.nan)
    for index, row in enumerate(rows):
        if len(row) != len(names):
            raise ValueError("%s: %s.positions[%d] has %d values for %d joints"
                             % (source, name, index, len(row), len(names)))
        positions[index] = _array(row, "%s.positions[%d]" % (name, index), source)
    return names, times, positions


def _commanded_from_json(section: Any, source: str) -> Optional[Commanded]:
    if section is None:
        return None
    names, times, positions = _table(section, "commanded", source)
    return Commanded(names, times, positions, str(section.get("source") or ""))


def recording_from_json(data: Any, source: str = "recording") -> Recording:
    """The recording of a parsed JSON object; ValueError naming `source` and the field if invalid."""
    if not isinstance(data, dict) or data.get("format") != RECORDING_FORMAT:
        raise ValueError("%s: not an animation recording (expected \"format\": \"%s\")"
                         % (source, RECORDING_FORMAT))
    if data.get("version") != RECORDING_VERSION:
        raise ValueError("%s: unsupported recording version %r (this tool reads version %d)"
                         % (source, data.get("version"), RECORDING_VERSION))
    try:
        names, times, positions = _table(data["joint_states"], "joint_states", source)
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
            commanded=_commanded_from_json(data.get("commanded"), source),
            marks=tuple(sorted(Mark(float(mark["start"]), float(mark["end"]), str(mark["label"]),
                                    str(mark.get("part") or "")) for mark in data.get("marks") or [])),
            band_changes=tuple(BandChange(float(change["time"]), str(change["joint"]), float(change["lower"]),
                                          float(change["upper"])) for change in data.get("band_changes") or []),
            modes=tuple(sorted((float(item["time"]), str(item["mode"])) for item in data.get("modes") or [])),
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
        if entry.event == contract.CONFIGURATION_LOADED:
            # Read before the window too: the configuration is loaded before the run starts.
            configured_bound = _configured_heading_bound(entry.fields)
            continue
        if not _in_window(entry.timestamp, since, until):
            continue
        if entry.event == contract.BEHAVIOUR_STARTED and entry.fields.get("wheels"):
            heading_bound = configured_bound
        for name, band in _animation_goal_bands(entry):
            bands[name] = _hull(bands[name], band) if name in bands else band
    return bands, heading_bound


def _configured_heading_bound(fields: Mapping[str, Any]) -> Optional[float]:
    """The ``headingBound`` of a ``configuration_loaded`` entry's items; None when it has none or it is
    not a number."""
    try:
        return float(fields.get("items", {}).get("headingBound"))
    except (TypeError, ValueError):
        return None


def _animation_goal_bands(entry: Any) -> List[Tuple[str, JointBand]]:
    """(joint, band) for each joint of an animating ``goal_sent`` entry; none for any other entry, and for
    a goal that logs no bounds (homing). The centre is the logged one, else the middle of the band."""
    fields = entry.fields
    purpose = fields.get("purpose", contract.PURPOSE_ANIMATE)
    if entry.event != contract.GOAL_SENT or purpose != contract.PURPOSE_ANIMATE:
        return []
    joints = fields.get("joints") or []
    lower = fields.get("lower") or []
    upper = fields.get("upper") or []
    centre = fields.get("centre") or []
    moving = fields.get("moving") or [True] * len(joints)
    if not (len(joints) == len(lower) == len(upper) == len(moving)):
        return []  # a goal without bounds (homing): nothing to learn
    return [(name, _logged_band(index, lower, upper, centre, moving)) for index, name in enumerate(joints)]


def _logged_band(index: int, lower: Sequence[float], upper: Sequence[float], centre: Sequence[float],
                 moving: Sequence[bool]) -> JointBand:
    """The band of the goal's joint at `index`: its logged centre, else the middle of its bounds."""
    middle = float(centre[index]) if index < len(centre) else (lower[index] + upper[index]) / 2.0
    return JointBand(float(lower[index]), float(upper[index]), middle, bool(moving[index]))


def _hull(known: JointBand, band: JointBand) -> JointBand:
    """The band of a joint whose bounds changed during the run (a reconfiguration): the hull of both, with
    the first centre; moving when either moved."""
    return JointBand(min(known.lower, band.lower), max(known.upper, band.upper), known.centre,
                     known.moving or band.moving)


def activations_from_log(entries: Iterable[Any], since: Optional[float] = None,
                         until: Optional[float] = None) -> List[Tuple[float, str]]:
    """(epoch, ENABLED or DISABLED) of every accepted activation request of the node's log entries
    (``activation_request`` with the success reply) between the epochs `since` and `until`."""
    found = []
    for entry in entries:
        if entry.event != contract.ACTIVATION_REQUEST or not _in_window(entry.timestamp, since, until):
            continue
        if entry.fields.get("reply") != contract.REPLY_SUCCESS:
            continue
        state = contract.parse_activation_state(str(entry.fields.get("state", "")))
        if state is not None:
            found.append((entry.timestamp.timestamp(), state))
    return found


def band_changes_from_log(entries: Iterable[Any], since: Optional[float] = None) -> List[Tuple[float, str, JointBand]]:
    """(epoch, joint, band) wherever a moving joint's band differs from the one before, from the node's animating
    ``goal_sent`` lines (the first band of each joint included)."""
    changes: List[Tuple[float, str, JointBand]] = []
    latest: Dict[str, JointBand] = {}
    for entry in entries:
        if not _in_window(entry.timestamp, since, None):
            continue
        for name, band in _animation_goal_bands(entry):
            if band.moving and latest.get(name) != band:
                latest[name] = band
                changes.append((entry.timestamp.timestamp(), name, band))
    return changes


def goals_sent_from_log(entries: Iterable[Any], since: Optional[float] = None) -> List[Tuple[float, str]]:
    """(epoch, part key) of every ``goal_sent`` of the node's log entries, whatever its purpose: from each, what the
    part's controller executes is the node's command."""
    return [(entry.timestamp.timestamp(), str(entry.fields.get("part", ""))) for entry in entries
            if entry.event == contract.GOAL_SENT and _in_window(entry.timestamp, since, None)]


class LoggedYield(NamedTuple):
    """A part's yield to another node's motion, from the node's log (epochs)."""

    start: float  # part_yielded
    end: Optional[float]  # the part's next part_resumed, or the node's behaviour_ended or node_stopped; None: none
    part: str  # key of joint_table.PARTS (or the wheels')
    caller: str  # the other node
    kind: str  # what it sent: goal, command, twist or joint_angles


YIELD_ENDS = (contract.PART_RESUMED, contract.BEHAVIOUR_ENDED, contract.NODE_STOPPED)


def yields_from_log(entries: Iterable[Any], since: Optional[float] = None) -> List[LoggedYield]:
    """Each ``part_yielded`` of the node's log entries, to the part's next ``part_resumed`` (or the node's
    ``behaviour_ended`` or ``node_stopped``: a disabled node yields no more): from the yield on, another node's motion
    runs on the part."""
    found: List[LoggedYield] = []
    for entry in entries:
        if entry.event not in (contract.PART_YIELDED,) + YIELD_ENDS or not _in_window(entry.timestamp, since, None):
            continue
        epoch, part = entry.timestamp.timestamp(), entry.fields.get("part")
        if entry.event == contract.PART_YIELDED:
            found.append(LoggedYield(epoch, None, str(part), str(entry.fields.get("caller", "")),
                                     str(entry.fields.get("kind", ""))))
            continue
        found = [logged._replace(end=epoch) if logged.end is None and part in (None, logged.part) else logged
                 for logged in found]
    return found


SETTING_MARK_WIDTH = 0.3  # s: a change of live settings is an instant; its mark is drawn this wide
SAME_CHANGE = 0.1  # s: setting_changed lines this close belong to one change


def setting_changes_from_log(entries: Iterable[Any], since: Optional[float] = None,
                             until: Optional[float] = None) -> List[Tuple[float, str]]:
    """(epoch, "intensity 1.0 -> 0.5, turnBase true -> false") of each change of live settings in the node's log
    (``setting_changed`` lines, those of one change joined)."""
    changes: List[Tuple[float, str]] = []
    for entry in entries:
        if entry.event != contract.SETTING_CHANGED or not _in_window(entry.timestamp, since, until):
            continue
        epoch = entry.timestamp.timestamp()
        text = "%s %s -> %s" % (entry.fields.get("key"), entry.fields.get("old"), entry.fields.get("new"))
        if changes and epoch - changes[-1][0] <= SAME_CHANGE:
            changes[-1] = (changes[-1][0], changes[-1][1] + ", " + text)
        else:
            changes.append((epoch, text))
    return changes


def configuration_and_topics(config_file: str, overrides: Optional[Mapping[str, Any]] = None) -> Tuple[Any, Any]:
    """(configuration, topics of its platform: part key -> action namespace or topic) of a
    configuration file with `overrides` of its keys; ValueError with one line when either is invalid."""
    from cssr_system.animate_behaviour.configuration import ConfigurationError, load_configuration, topic_file_path
    from cssr_system.animate_behaviour.topics import TopicFileError, load_topic_map
    try:
        config = load_configuration(config_file, overrides)
        return config, load_topic_map(topic_file_path(config)).topics
    except (ConfigurationError, TopicFileError) as error:
        raise ValueError(str(error)) from None


def bands_from_configuration_file(config_file: str, overrides: Optional[Dict[str, str]] = None
                                  ) -> Tuple["OrderedDict[str, JointBand]", Optional[float]]:
    """The joint bands and the heading bound (None without rotation) of a configuration file, with
    `overrides` of its keys (e.g. platform, behaviour); ValueError with one line when it is invalid."""
    config, parts = configuration_and_topics(config_file, overrides)
    heading_bound = config.heading_bound if "rotation" in config.behaviour else None
    return bands_from_configuration(config, parts), heading_bound


class RunSetting(NamedTuple):
    """What a run of the node uses, as the node resolves it from its private parameters."""

    config_file: str
    log_file: str
    platform: str
    behaviour: str
    topics: Mapping[str, str]  # part key (and Wheels) -> action namespace or topic


# The node's private parameters that decide its platform and topics (the others cannot change them).
SETTING_KEYS = ("platform", "behaviour")


def run_setting(node_parameters: Mapping[str, Any], ros_home: Optional[str],
                node: str = "/" + contract.NODE_NAME) -> RunSetting:
    """The setting of the node `node` (its resolved name) run with `node_parameters` (its private parameters, names
    without its namespace: ``configFile``, ``logFile``, configuration keys), with the node's defaults;
    ValueError with one line when its configuration or topic file cannot be read."""
    from cssr_system.animate_behaviour.configuration import (PLATFORM_TOPICS_KEYS, configuration_items,
                                                             shipped_configuration_path)
    from cssr_system.animate_behaviour.event_log import default_log_path, node_log_file_name
    from cssr_system.package_files import package_dir
    config_file = os.path.abspath(str(node_parameters.get("configFile") or shipped_configuration_path()))
    log_file = os.path.abspath(str(node_parameters.get("logFile")
                                   or default_log_path(package_dir(), ros_home, node_log_file_name(node))))
    keys = SETTING_KEYS + tuple(PLATFORM_TOPICS_KEYS.values())
    overrides = {key: node_parameters[key] for key in keys if key in node_parameters}
    config, topics = configuration_and_topics(config_file, overrides)
    items = configuration_items(config)
    return RunSetting(config_file, log_file, items["platform"], items["behaviour"], topics)


def bands_from_configuration(config: Any, available_parts: Iterable[str]) -> "OrderedDict[str, JointBand]":
    """The joint bands a configuration (``configuration.Configuration``) gives the parts of a
    platform (``available_parts``: keys of its topic file), with ``motion.waypoints``."""
    from cssr_system.motion.waypoints import animated_parts  # numpy only, but keeps imports light
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


def mode_spans(recording: Recording) -> List[Tuple[float, float, str]]:
    """(start, end, mode) of each span of one mode of the node: from a change to the next, the last to the end of
    the recording."""
    end = float(recording.times[-1]) if len(recording.times) else 0.0
    ends = [time for time, _ in recording.modes[1:]] + [end]
    return [(start, max(start, stop), mode) for (start, mode), stop in zip(recording.modes, ends)]


def band_excess(recording: Recording, joint_name: str) -> float:
    """How far the joint went outside its band at worst (0.0: always inside; rad or hand units),
    not counting where another node moved it: during a mark of the joint's part, and after it until
    the joint is back inside its band (`other_node_samples`)."""
    band = recording.bands.get(joint_name)
    if band is None or joint_name not in recording.joint_names:
        return 0.0
    values = recording.positions[:, recording.joint_names.index(joint_name)]
    values = values[numpy.isfinite(values) & ~other_node_samples(recording, joint_name)]
    if len(values) == 0:
        return 0.0
    return float(max(0.0, numpy.max(values) - band.upper, band.lower - numpy.min(values)))


def other_node_samples(recording: Recording, joint_name: str) -> numpy.ndarray:
    """Which samples of the joint (a mask over ``recording.times``) another node's motion explains:
    those during a mark of its part, and those after the mark until the joint is inside its band."""
    excused = numpy.zeros(len(recording.times), dtype=bool)
    band = recording.bands.get(joint_name)
    part = next((key for key, part in PARTS.items() if joint_name in part.joints), None)
    if band is None or part is None or joint_name not in recording.joint_names:
        return excused
    values = recording.positions[:, recording.joint_names.index(joint_name)]
    with numpy.errstate(invalid="ignore"):
        inside = (values >= band.lower - BAND_TOLERANCE) & (values <= band.upper + BAND_TOLERANCE)
    for mark in recording.marks:
        if mark.part != part:
            continue
        excused |= (recording.times >= mark.start) & (recording.times <= mark.end)
        after = numpy.nonzero(recording.times > mark.end)[0]
        if len(after):
            back = after[inside[after]]
            excused[after[0]:back[0] if len(back) else len(excused)] = True
    return excused


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
