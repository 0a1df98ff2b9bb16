"""The animateBehaviour configuration: parsing, validation and the typed result.

File format (``config/animateBehaviourConfiguration.ini``):

- one ``key value`` pair per line: the key, one or more spaces or tabs, the value;
- blank lines are ignored, and so are lines whose first non-blank character is ``#``;
- a ``#`` preceded by a space or a tab starts a comment that runs to the end of the line;
- leading and trailing blanks are ignored; CRLF and CR line ends and a UTF-8 byte order mark are
  accepted; keys are case-sensitive and each may appear once;
- a value contains no blanks, except that list values may have blanks around their commas
  (``0.2, 0.2, 0.2, 0.35, 0.2``);
- numbers are decimal (``1``, ``0.5``, ``.5``, ``1e-3``); ``nan`` and infinities are rejected;
  integers have no decimal point; ``true``/``false``, ``platform``, ``behaviour`` and ``none`` are
  accepted in any letter case.

`KEYS` is the one table of keys: file name, attribute of `Configuration`, required or default, parser
and what is expected. The 14 keys from ``platform`` to ``legRepeatFactor`` are required; the others
(``randomSeed``, ``homeOnDisable``, ``headingBound``, ``yieldQuietTime``, ``motionStyle``,
``breathsPerMinute``, ``breathingAmplitude``, ``actuation``, the live settings, the conversation's keys) are optional
with the defaults in `KEYS`. Any other key is an error.

Cross-key rules: ``legRepeatFactor <= numPoints``; ``numPointsLeg <= floor(numPoints /
legRepeatFactor)`` (the leg chunk size); the topic file of the selected platform (``robotTopics`` for
``robot``, ``simulatorTopics`` for ``simulator``; relative names are relative to the package's
``data`` folder) must exist and be valid (see `topics`). The other platform's file is not
read. Cross-key rules are checked only when the keys involved are valid on their own.

Overrides (private ROS parameters ``~<key>``) replace or supply the value of a key. They may be
strings, booleans, integers, floats or lists/tuples of those (joined with commas), and are validated
exactly like file values. A value in the file is validated even when a parameter overrides it, so a
broken file never goes unnoticed.

Every problem is collected, each as one line naming ``<file>:<line>`` (or ``parameter ~<key>``), the
key, the value found and what was expected; they are raised together as one `ConfigurationError`
whose text joins them with ``; ``. No `Configuration` is built unless there is no problem at all.
For example::

    animateBehaviourConfiguration.ini:7: selectedRange = '1.5': expected a number in [0, 1]
    animateBehaviourConfiguration.ini: missing key numPoints (expected an integer >= 1)
    animateBehaviourConfiguration.ini:16: duplicated key gestureDuration (first at line 11)
    animateBehaviourConfiguration.ini:15: unknown key 'selectedRang' (did you mean selectedRange? ...)
    parameter ~numPoints = 2.5: expected an integer >= 1
    cannot read /path/animateBehaviourConfiguration.ini: No such file or directory
"""
import math
import os
import re
import textwrap
from collections import OrderedDict
from typing import (Callable, Container, Dict, FrozenSet, Iterable, List, Mapping, NamedTuple, Optional, Sequence,
                    Tuple)

from cssr_system.animate_behaviour.key_value_file import (distinct_known_lines, join_problems, one_line,
                                                          read_key_value_file, unknown_key)
from cssr_system.animate_behaviour.topics import TopicFileError, load_topic_map
from cssr_system.package_files import data_dir as data_dir_of_package, package_path
from cssr_system.pepper.joint_table import BASE_MAX_ANGULAR_VELOCITY, PARTS, short_name

CONFIGURATION_FILE_NAME = "animateBehaviourConfiguration.ini"  # the shipped file, in config/
BEHAVIOURS: Tuple[str, ...] = ("body", "hands", "rotation")
PLATFORMS: Tuple[str, ...] = ("robot", "simulator")
ALL_BEHAVIOURS = "all"
MOTION_STYLES = ("random", "breathing")  # motion/styles.py builds the goals of each
# How the joints are driven (README: "Actuation on the robot"): FollowJointTrajectory goals, or the same planned
# motion streamed to naoqi_driver's JointAngles topic (core/joint_angle_stream.py). Read at start-up.
ACTUATIONS = ("trajectory", "joint_angles")
TRAJECTORY_ACTUATION, JOINT_ANGLES_ACTUATION = ACTUATIONS
# The conversation's modes (README: "Modes"): what the robot does; `auto` follows the conversation by itself.
MODES = ("idle", "listening", "speaking")
AUTO_MODE = "auto"
MODE_SETTINGS = MODES + (AUTO_MODE,)
# The conversation's sources (README: "Modes"): the key naming each, what its activity means, and what it is.
CONVERSATION_SOURCES = (("speakingTopic", "speaking", "topic"), ("listeningTopic", "listening", "topic"),
                        ("speakingAction", "speaking", "action"), ("listeningAction", "listening", "action"))
# The key holding the topic file of each platform.
PLATFORM_TOPICS_KEYS: Dict[str, str] = OrderedDict((("robot", "robotTopics"), ("simulator", "simulatorTopics")))
LARGEST_RANDOM_SEED = 2 ** 32 - 1  # numpy's seeds are 32-bit


class Configuration(NamedTuple):
    """A complete, validated configuration. Immutable; built only by `load_configuration`."""

    platform: str  # "robot" or "simulator"
    behaviour: FrozenSet[str]  # non-empty subset of BEHAVIOURS ("all" is all three)
    robot_topics: str
    simulator_topics: str
    verbose_mode: bool
    rot_maximum_range: float
    selected_range: float
    arm_maximum_range: Tuple[float, float, float, float, float]
    hand_maximum_range: float
    leg_maximum_range: Tuple[float, float, float]
    gesture_duration: float
    num_points: int
    num_points_leg: int
    leg_repeat_factor: int
    # Optional keys, with their documented defaults.
    random_seed: Optional[int] = None
    home_on_disable: bool = True
    heading_bound: float = 0.3
    yield_quiet_time: float = 1.0
    motion_style: str = "random"
    breaths_per_minute: float = 12.0
    breathing_amplitude: float = 0.6
    actuation: str = "trajectory"
    # The live settings' starting values (README: "Live settings"): they change while the node runs.
    intensity: float = 1.0
    move_arms: bool = True
    move_hands: bool = True
    move_leg: bool = True
    turn_base: bool = True
    # The conversation (README: "Modes"): the mode setting (a live setting too), the modes' bands and tempo, the
    # sources that say when the robot speaks or listens ("" : not watched), and when a silent source counts no more.
    mode: str = AUTO_MODE
    listening_range: float = 0.3
    speaking_arm_range: Tuple[float, float, float, float, float] = (0.35, 0.4, 0.4, 0.4, 0.4)
    beats_per_minute: float = 60.0
    speaking_topic: str = ""
    listening_topic: str = ""
    speaking_action: str = ""
    listening_action: str = ""
    conversation_timeout: float = 3.0


class ConfigurationError(ValueError):
    """An unusable configuration. `.problems`: one line each; str(error) joins them with '; '."""

    def __init__(self, problems: Sequence[str]) -> None:
        self.problems = tuple(one_line(problem) for problem in problems) or ("invalid configuration",)
        super().__init__(join_problems(self.problems))


class InvalidValue(ValueError):
    """Raised by a key's parser; the optional argument says what exactly is wrong."""


class KeySpec(NamedTuple):
    """Everything about one configuration key."""

    name: str  # as written in the file (camelCase)
    attribute: str  # attribute of Configuration (snake_case)
    required: bool
    default: object  # value used when an optional key is absent (None for required keys)
    parse: Callable[[str], object]  # value text -> typed value; raises InvalidValue
    format: Callable[[object], str]  # typed value -> value text, as written in the file
    expected: str  # what a valid value looks like, for messages and the README
    description: str  # what the key does
    shipped: str  # value text in the shipped configuration file


# ---------------------------------------------------------------------------------------------------
# Value parsers and formatters.

_FLOAT_TEXT = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?\Z", re.ASCII)
_INTEGER_TEXT = re.compile(r"[+-]?\d+\Z", re.ASCII)
_BLANK = re.compile(r"[ \t]")
_BLANKS_AROUND_COMMAS = re.compile(r"[ \t]*,[ \t]*")
_CONTROL_CHARACTER = re.compile(r"[\x00-\x08\x0a-\x1f\x7f]")


def _number(text: str) -> float:
    if not _FLOAT_TEXT.match(text):
        raise InvalidValue()
    value = float(text)
    if not math.isfinite(value):  # e.g. 1e999
        raise InvalidValue("too large")
    return value


def _integer(text: str) -> int:
    if not _INTEGER_TEXT.match(text):
        raise InvalidValue()
    return int(text)


def _format_number(value: object) -> str:
    return repr(float(value))  # shortest text that reads back to the same float


def _format_bound(value: float) -> str:
    return "{:g}".format(value)


def number_in(low: float, high: float) -> Callable[[str], object]:
    def parse(text: str) -> float:
        value = _number(text)
        if not low <= value <= high:
            raise InvalidValue()
        return value
    return parse


def _positive_number(text: str) -> float:
    value = _number(text)
    if not value > 0:
        raise InvalidValue()
    return value


def integer_at_least(low: int) -> Callable[[str], object]:
    def parse(text: str) -> int:
        value = _integer(text)
        if value < low:
            raise InvalidValue()
        return value
    return parse


def _numbers_in(count: int, low: float, high: float) -> Callable[[str], object]:
    def parse(text: str) -> Tuple[float, ...]:
        items = [item.strip(" \t") for item in text.split(",")]
        if len(items) != count:
            raise InvalidValue("found {} value{}".format(len(items), "" if len(items) == 1 else "s"))
        values, wrong = [], []
        for position, item in enumerate(items, start=1):
            try:
                value = _number(item)
            except InvalidValue:
                wrong.append("value {} {!r} is not a number".format(position, item))
                continue
            if not low <= value <= high:
                wrong.append("value {} {!r} is out of range".format(position, item))
            values.append(value)
        if wrong:
            raise InvalidValue(", ".join(wrong))
        return tuple(values)
    return parse


def _format_numbers(values: object) -> str:
    return ",".join(_format_number(value) for value in values)  # type: ignore[attr-defined]


def _boolean(text: str) -> bool:
    lowered = text.lower()
    if lowered not in ("true", "false"):
        raise InvalidValue()
    return lowered == "true"


def _format_boolean(value: object) -> str:
    return "true" if value else "false"


def _one_of(choices: Tuple[str, ...]) -> Callable[[str], str]:
    """A parser of one word of `choices`, accepted in any letter case and returned in lower case."""
    def parse(text: str) -> str:
        lowered = text.lower()
        if lowered not in choices:
            raise InvalidValue()
        return lowered
    return parse


def _behaviour(text: str) -> FrozenSet[str]:
    selected = set()
    for item in text.split(","):
        name = item.strip(" \t").lower()
        if name == ALL_BEHAVIOURS:
            selected.update(BEHAVIOURS)
        elif name in BEHAVIOURS:
            selected.add(name)
        elif not name:
            raise InvalidValue("empty name in the list")
        else:
            raise InvalidValue("unknown name {!r}".format(item.strip(" \t")))
    return frozenset(selected)


def _format_behaviour(value: object) -> str:
    if set(value) == set(BEHAVIOURS):  # type: ignore[call-overload]
        return ALL_BEHAVIOURS
    return ",".join(name for name in BEHAVIOURS if name in value)  # type: ignore[operator]


def _file_name(text: str) -> str:
    if _BLANK.search(text):
        raise InvalidValue("a file name here contains no blanks")
    if text.startswith("#"):  # it would read back as a comment
        raise InvalidValue("a file name here does not start with '#'")
    return text


NOT_WATCHED = "none"  # a source key's value (or an empty one) that watches nothing


def _source_name(text: str) -> str:
    """A topic or action name, or "" for none (`none` in any letter case, or an empty parameter)."""
    if not text or text.lower() == NOT_WATCHED:
        return ""
    if not re.match(r"[~/A-Za-z][\w/~]*\Z", text) or "//" in text:
        raise InvalidValue()
    return text


def _format_source_name(value: object) -> str:
    return str(value) or NOT_WATCHED


def _random_seed(text: str) -> Optional[int]:
    if text.lower() == "none":
        return None
    value = _integer(text)
    if not 0 <= value <= LARGEST_RANDOM_SEED:
        raise InvalidValue()
    return value


def _format_random_seed(value: object) -> str:
    return "none" if value is None else str(value)


# ---------------------------------------------------------------------------------------------------
# The table of keys.

def _short_joint_names(part_key: str) -> Tuple[str, ...]:
    """Joint names of a part without their side letter (RShoulderPitch -> ShoulderPitch)."""
    return tuple(short_name(name) for name in PARTS[part_key].joints)


_ARM_JOINTS = _short_joint_names("RArm")
_LEG_JOINTS = _short_joint_names("Leg")
_UNIT = "a number in [0, 1]"
_AT_LEAST_ONE = "an integer >= 1"
_SOURCE = "a topic or action name, or none (not watched)"
_FILE_NAME = "a file name without blanks, relative to the package's data folder or absolute"


def _list_of_units(joints: Tuple[str, ...]) -> str:
    return "{} numbers in [0, 1] separated by commas, for {}".format(len(joints), ", ".join(joints))


def _key(name: str, attribute: str, parse: Callable[[str], object], format_value: Callable[[object], str],
         expected: str, description: str, shipped: Optional[str] = None, default: object = None) -> KeySpec:
    """A required key (with its shipped value text) or, when `shipped` is None, an optional one."""
    required = shipped is not None
    return KeySpec(name, attribute, required, None if required else default, parse, format_value, expected,
                   description, shipped if required else format_value(default))


KEYS: Dict[str, KeySpec] = OrderedDict((spec.name, spec) for spec in (
    _key("platform", "platform", _one_of(PLATFORMS), str, " or ".join(PLATFORMS),
         "where the node runs (the physical Pepper or the simulator); selects the topic file", "robot"),
    _key("behaviour", "behaviour", _behaviour, _format_behaviour,
         "all or a comma list of " + ", ".join(BEHAVIOURS) + ", in any letter case",
         "what moves: body (arms, hands, leg), hands (hands, elbows, wrists), rotation (base), or all",
         "all"),
    _key("robotTopics", "robot_topics", _file_name, str, _FILE_NAME,
         "topic file of the physical robot", "pepperTopics.dat"),
    _key("simulatorTopics", "simulator_topics", _file_name, str, _FILE_NAME,
         "topic file of the simulator", "simulatorTopics.dat"),
    _key("verboseMode", "verbose_mode", _boolean, _format_boolean, "true or false",
         "print debug-level diagnostics when true", "false"),
    _key("rotMaximumRange", "rot_maximum_range", number_in(0.0, 1.0), _format_number, _UNIT,
         "peak angular speed of the base, as a fraction of its maximum of {} rad/s".format(
             _format_bound(BASE_MAX_ANGULAR_VELOCITY)), "0.3"),
    _key("selectedRange", "selected_range", number_in(0.0, 1.0), _format_number, _UNIT,
         "global scale of the joint motion (not of the rotation)", "0.5"),
    _key("armMaximumRange", "arm_maximum_range", _numbers_in(len(_ARM_JOINTS), 0.0, 1.0), _format_numbers,
         _list_of_units(_ARM_JOINTS), "fraction of each arm joint's full range that the motion may span",
         "0.2,0.2,0.2,0.35,0.2"),
    _key("handMaximumRange", "hand_maximum_range", number_in(0.0, 1.0), _format_number, _UNIT,
         "fraction of the hand's full range (closed to open) that the motion may span", "0.7"),
    _key("legMaximumRange", "leg_maximum_range", _numbers_in(len(_LEG_JOINTS), 0.0, 1.0), _format_numbers,
         _list_of_units(_LEG_JOINTS), "fraction of each leg joint's full range that the motion may span",
         "0.1,0.1,0.08"),
    _key("gestureDuration", "gesture_duration", _positive_number, _format_number, "a number of seconds > 0",
         "seconds between consecutive random positions", "1.0"),
    _key("numPoints", "num_points", integer_at_least(1), str, _AT_LEAST_ONE,
         "random positions per trajectory", "100"),
    _key("numPointsLeg", "num_points_leg", integer_at_least(1), str, _AT_LEAST_ONE,
         "random leg positions at the start of each leg chunk; the rest of the chunk is the centre", "2"),
    _key("legRepeatFactor", "leg_repeat_factor", integer_at_least(1), str, _AT_LEAST_ONE,
         "leg chunks per trajectory; chunk size = floor(numPoints / legRepeatFactor)", "8"),
    _key("randomSeed", "random_seed", _random_seed, _format_random_seed,
         "none or an integer in [0, {}]".format(LARGEST_RANDOM_SEED),
         "seed of the random motion, for reproducible runs; none: seeded from the system", default=None),
    _key("homeOnDisable", "home_on_disable", _boolean, _format_boolean, "true or false",
         "on disable, return smoothly to the rest posture when true, stop where the joints are when false",
         default=True),
    _key("headingBound", "heading_bound", number_in(0.0, 0.5), _format_number,
         "a number of radians in [0, 0.5]",
         "largest turn of the base away from its heading when animation was enabled", default=0.3),
    _key("yieldQuietTime", "yield_quiet_time", number_in(0.0, 10.0), _format_number,
         "a number of seconds in [0, 10]",
         "calm time after another node's motion of a part before the part moves again", default=1.0),
    _key("motionStyle", "motion_style", _one_of(MOTION_STYLES), str, "random or breathing",
         "random: random positions in each joint's band; breathing: a slow breathing rhythm with coherent "
         "variation and rare posture shifts, in the same bands", default="random"),
    _key("breathsPerMinute", "breaths_per_minute", number_in(5.0, 20.0), _format_number,
         "a number in [5, 20]", "the tempo: the breathing style's rhythm; the random style's gestures take "
         "12 / breathsPerMinute times gestureDuration", default=12.0),
    _key("breathingAmplitude", "breathing_amplitude", number_in(0.0, 1.0), _format_number, _UNIT,
         "the breathing style's amplitude, as a fraction of each joint's band", default=0.6),
    _key("actuation", "actuation", _one_of(ACTUATIONS), str, "trajectory or joint_angles",
         "trajectory: FollowJointTrajectory goals to the topic file's controllers; joint_angles: the same motion "
         "streamed to its JointAngles topic (naoqi_driver); read when the node starts", default="trajectory"),
    _key("intensity", "intensity", number_in(0.0, 1.0), _format_number, _UNIT,
         "scales every joint's band about its centre: 1 the bands above, 0 no motion", default=1.0),
    _key("moveArms", "move_arms", _boolean, _format_boolean, "true or false",
         "the arms move (where the behaviour moves them)", default=True),
    _key("moveHands", "move_hands", _boolean, _format_boolean, "true or false",
         "the hands move (where the behaviour moves them)", default=True),
    _key("moveLeg", "move_leg", _boolean, _format_boolean, "true or false",
         "the hip and knee move (where the behaviour moves them)", default=True),
    _key("turnBase", "turn_base", _boolean, _format_boolean, "true or false",
         "the base turns (where the behaviour has rotation); switched off it stops without turning back",
         default=True),
    _key("mode", "mode", _one_of(MODE_SETTINGS), str, ", ".join(MODES) + " or " + AUTO_MODE,
         "what the robot does: idle (waiting), listening (calm, leaning forward), speaking (arm beats); auto "
         "follows the conversation's sources", default=AUTO_MODE),
    _key("listeningRange", "listening_range", number_in(0.0, 1.0), _format_number, _UNIT,
         "while listening, each arm and hand joint's band as a fraction of its idle band", default=0.3),
    _key("speakingArmRange", "speaking_arm_range", _numbers_in(len(_ARM_JOINTS), 0.0, 1.0), _format_numbers,
         _list_of_units(_ARM_JOINTS), "while speaking, fraction of each arm joint's full range its beats may span "
         "(as armMaximumRange)", default=(0.35, 0.4, 0.4, 0.4, 0.4)),
    _key("beatsPerMinute", "beats_per_minute", number_in(30.0, 120.0), _format_number, "a number in [30, 120]",
         "while speaking, the arms' and hands' beats per minute", default=60.0),
    _key("speakingTopic", "speaking_topic", _source_name, _format_source_name, _SOURCE,
         "a std_msgs/Bool topic that is true while the robot speaks; read when the node starts", default=""),
    _key("listeningTopic", "listening_topic", _source_name, _format_source_name, _SOURCE,
         "a std_msgs/Bool topic that is true while the robot listens; read when the node starts", default=""),
    _key("speakingAction", "speaking_action", _source_name, _format_source_name, _SOURCE,
         "an action whose active goals mean the robot speaks (text to speech); read when the node starts", default=""),
    _key("listeningAction", "listening_action", _source_name, _format_source_name, _SOURCE,
         "an action whose active goals mean the robot listens (speech recognition); read when the node starts",
         default=""),
    _key("conversationTimeout", "conversation_timeout", number_in(0.5, 60.0), _format_number,
         "a number of seconds in [0.5, 60]",
         "seconds a source may show no sign of life (no message, no publisher) before it counts as silent",
         default=3.0),
))


# ---------------------------------------------------------------------------------------------------
# Reading and validation.

class _Value(NamedTuple):
    """A valid value and where it came from, for the messages of cross-key rules."""

    where: str  # "<file>:<line>" or "parameter ~<key>"
    subject: str  # "<file>:<line>: <key>" or "parameter ~<key>": what problems start with
    shown: str  # the value as found, quoted
    value: object


def shipped_configuration_path() -> str:
    """The package's own configuration file, ``config/animateBehaviourConfiguration.ini``."""
    return package_path("config", CONFIGURATION_FILE_NAME)


def _resolve_data_file(name: str, data_dir: Optional[str]) -> str:
    if os.path.isabs(name):
        return name
    return os.path.join(data_dir if data_dir is not None else data_dir_of_package(), name)


def topic_file_path(config: Configuration, data_dir: Optional[str] = None) -> str:
    """The topic file of the selected platform: relative names are relative to `data_dir`
    (default: the package's data folder), absolute names are kept."""
    attribute = KEYS[PLATFORM_TOPICS_KEYS[config.platform]].attribute
    return _resolve_data_file(getattr(config, attribute), data_dir)


def _scalar_text(value: object) -> str:
    if isinstance(value, bool):  # before int: bool is an int
        return _format_boolean(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, str):
        return value.strip()
    if value is None:
        return "none"
    raise TypeError(type(value).__name__)


def override_text(value: object) -> str:
    """The text form of a parameter value; TypeError for a type that has none."""
    if isinstance(value, (list, tuple)):
        return ",".join(_scalar_text(item) for item in value)
    return _scalar_text(value)


def check_value(spec: KeySpec, text: str, where: str, subject: str, shown: str,
                problems: List[str]) -> Optional[_Value]:
    """The parsed value, or None after adding the problem to `problems`."""
    if not text and spec.parse is not _source_name:  # an empty parameter names no source
        problems.append("{} has no value (expected {})".format(subject, spec.expected))
        return None
    try:
        if _BLANK.search(_BLANKS_AROUND_COMMAS.sub(",", text)):
            raise InvalidValue("found several words; blanks are allowed only around commas")
        if _CONTROL_CHARACTER.search(text):  # e.g. a line break in a parameter
            raise InvalidValue("found a control character")
        value = spec.parse(text)
    except InvalidValue as invalid:
        detail = " ({})".format(invalid.args[0]) if invalid.args and invalid.args[0] else ""
        problems.append("{} = {}: expected {}{}".format(subject, shown, spec.expected, detail))
        return None
    return _Value(where, subject, shown, value)


def _check_cross_keys(values: Mapping[str, _Value], data_dir: Optional[str], problems: List[str]) -> None:
    num_points = values.get("numPoints")
    repeat = values.get("legRepeatFactor")
    leg_points = values.get("numPointsLeg")
    if num_points is not None and repeat is not None:
        if repeat.value > num_points.value:  # type: ignore[operator]
            problems.append("{} = {}: expected an integer <= numPoints ({}, {})".format(
                repeat.subject, repeat.shown, num_points.value, num_points.where))
        elif leg_points is not None:
            chunk = num_points.value // repeat.value  # type: ignore[operator]
            if leg_points.value > chunk:  # type: ignore[operator]
                problems.append(
                    "{} = {}: expected an integer <= the leg chunk size floor(numPoints / "
                    "legRepeatFactor) = floor({} / {}) = {}".format(
                        leg_points.subject, leg_points.shown, num_points.value, repeat.value, chunk))

    platform = values.get("platform")
    if platform is None:
        return
    topics_key = PLATFORM_TOPICS_KEYS[platform.value]  # type: ignore[index]
    topics = values.get(topics_key)
    if topics is None:
        return
    path = _resolve_data_file(topics.value, data_dir)  # type: ignore[arg-type]
    try:
        load_topic_map(path)
    except TopicFileError as error:
        for problem in error.problems:
            problems.append("{} = {}: topic file of platform {}: {}".format(
                topics.subject, topics.shown, platform.value, problem))


def parse_configuration(text: str, source: str, overrides: Optional[Mapping[str, object]] = None,
                        data_dir: Optional[str] = None) -> Configuration:
    """The configuration in `text`, with `overrides` (file key -> parameter value) applied.

    `source` names the file in messages; `data_dir` is the folder of relative topic file names
    (default: the package's data folder). Raises ConfigurationError listing every problem."""
    problems: List[str] = []
    values: Dict[str, _Value] = {}
    in_file = _check_file_values(text, source, values, problems)
    _check_overrides(overrides or {}, values, problems)
    check_required_keys(KEYS.values(), in_file | set(overrides or {}), source, problems)
    _check_cross_keys(values, data_dir, problems)
    if problems:
        raise ConfigurationError(problems)
    return Configuration(**{
        spec.attribute: values[spec.name].value if spec.name in values else spec.default
        for spec in KEYS.values()})


def _check_file_values(text: str, source: str, values: Dict[str, _Value], problems: List[str]) -> FrozenSet[str]:
    """Put the valid values of the file's lines into `values` and its problems into `problems`; the keys
    the file has, valid or not (a present but invalid key is not also reported missing)."""
    in_file = set()
    for where, line in distinct_known_lines(text, source, tuple(KEYS), problems):
        in_file.add(line.key)
        checked = check_value(KEYS[line.key], line.value, where, "{}: {}".format(where, line.key),
                              repr(line.value), problems)
        if checked is not None:
            values[line.key] = checked
    return frozenset(in_file)


def _check_overrides(overrides: Mapping[str, object], values: Dict[str, _Value], problems: List[str]) -> None:
    """Replace the file's values in `values` by the valid parameters of `overrides`; their problems go into
    `problems`. An invalid parameter still removes the file's value: the parameter was meant to win."""
    for key, override in overrides.items():
        where = "parameter ~{}".format(key)
        spec = KEYS.get(key)
        if spec is None:
            problems.append("{}: {}".format(where, unknown_key(str(key), tuple(KEYS))))
            continue
        values.pop(key, None)  # the parameter replaces the file's value, valid or not
        checked = check_override(spec, override, where, problems)
        if checked is not None:
            values[key] = checked


def check_override(spec: KeySpec, override: object, where: str, problems: List[str]) -> Optional[_Value]:
    """The parsed value of one parameter (`where`: ``parameter ~<key>``), or None after adding its problem
    to `problems`."""
    try:
        text = override_text(override)
    except TypeError as error:
        problems.append("{} = {!r}: expected {} (a parameter of type {} is not accepted)".format(
            where, override, spec.expected, error))
        return None
    return check_value(spec, text, where, where, repr(override), problems)


def check_required_keys(specs: Iterable[KeySpec], supplied: Container[str], source: str,
                        problems: List[str]) -> None:
    """Add a problem for each required key of `specs` that is not `supplied` (neither in the file `source`
    nor among the parameters), in the order of `specs`."""
    for spec in specs:
        if spec.required and spec.name not in supplied:
            problems.append("{}: missing key {} (expected {})".format(source, spec.name, spec.expected))


def load_configuration(path: str, overrides: Optional[Mapping[str, object]] = None,
                       data_dir: Optional[str] = None) -> Configuration:
    """The configuration in the file at `path` (see `parse_configuration`). Raises ConfigurationError,
    also when the file cannot be read."""
    return parse_configuration(read_key_value_file(path, ConfigurationError), path, overrides, data_dir)


# ---------------------------------------------------------------------------------------------------
# Writing.

def configuration_items(config: Configuration) -> "OrderedDict[str, str]":
    """Every key (optional ones included) -> its value written as in the file, in file order."""
    return OrderedDict((spec.name, spec.format(getattr(config, spec.attribute))) for spec in KEYS.values())


_FILE_HEADER = """\
# animateBehaviour configuration.
# One "key value" pair per line, separated by spaces or tabs; keys are case-sensitive. Blank lines,
# lines starting with '#' and the rest of a line after a blank and '#' are ignored. Lists are
# comma-separated. Optional keys at their default are shown commented out.
"""


def format_configuration_file(config: Configuration) -> str:
    """A configuration file that parses back to `config` (optional keys at their default commented out)."""
    width = max(len(name) for name in KEYS) + 4
    lines = [_FILE_HEADER]
    for name, text in configuration_items(config).items():
        spec = KEYS[name]
        at_default = not spec.required and getattr(config, spec.attribute) == spec.default
        comment = "{}{}. Value: {}.".format("Optional, default {}. ".format(text) if at_default else "",
                                            spec.description[0].upper() + spec.description[1:], spec.expected)
        # Keep "[0, 1]" and ">= 1" whole: wrap at the other blanks only.
        kept_together = re.sub(r"\[[^]]*\]|[<>]=? \S", lambda match: match.group().replace(" ", "\0"), comment)
        lines.extend("# " + part.replace("\0", " ") for part in textwrap.wrap(kept_together, width=98))
        lines.append("{}{}{}".format("# " if at_default else "", name.ljust(width), text))
        lines.append("")
    return "\n".join(lines)
