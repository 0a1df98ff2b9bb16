"""The harness's settings: the four tests and its configuration file.

Configuration (``config/animateBehaviourTestConfiguration.ini``): the line format of the node's
configuration file (`cssr_system.topics.key_value_lines`). Harness keys:

- ``tests``: a comma list of ``hands``, ``body``, ``rotation``, ``all`` (any case); run in that order;
- ``testDuration``: seconds each test lets the node animate, >= gestureDuration + 1;
- ``iterations``: rounds of the selected tests (integer >= 1);
- optional ``positionTolerance`` (rad, default 0.001), ``headingTolerance`` (rad, default 0.01),
  ``reportSamples`` (observed positions per part in the report, default 10).

Every other key is a key of the node's configuration (`cssr_system.configuration.KEYS`): the values
the node runs with during the tests, ``platform`` included. Missing node keys take the values of the
shipped configuration. ``behaviour`` is not allowed: each test sets it. Private parameters of the
harness override keys as the node's do. Problems are collected and raised together as one
`ConfigurationError`, each naming the file and line (or the parameter), the key and what is expected.
"""
import os
from collections import OrderedDict
from typing import Dict, List, Mapping, NamedTuple, Optional, Tuple

from cssr_system.animate_behaviour.configuration import (KEYS, Configuration, ConfigurationError,
                                                         InvalidValue, KeySpec, check_override,
                                                         check_required_keys, check_value, integer_at_least,
                                                         number_in, parse_configuration)
from cssr_system.animate_behaviour.key_value_file import key_value_lines, read_key_value_file, unknown_key


class HarnessTest(NamedTuple):
    name: str  # value of the node's behaviour key, and of the harness's tests key
    number: int
    title: str  # as in the report
    movement: str  # "<movement> started/ended"
    behaviours: Tuple[str, ...]  # the node's behaviour set


TESTS: Dict[str, HarnessTest] = OrderedDict((spec.name, spec) for spec in (
    HarnessTest("hands", 1, "Test Flexi Hand Animate behaviour", "Flexi movement", ("hands",)),
    HarnessTest("body", 2, "Test Subtle Body Animate behaviour", "Subtle body movement", ("body",)),
    HarnessTest("rotation", 3, "Test Rotation Animate behaviour", "Rotation movement", ("rotation",)),
    HarnessTest("all", 4, "Test All Animate behaviour", "All movements", ("body", "hands", "rotation")),
))


BASE = "base"  # the base, beside the joint parts, in the oracle and the report


# The node's return to the centre after disabled lasts at most 2 s (README: "The service"); the base may
# first finish a turn under way (a moveTo cannot be interrupted), then turn back.
JOINT_STOP_LIMIT = 2.5  # s from the disabled request until the joints are still


BASE_STOP_LIMIT = 3.5  # s from the disabled request until the base is still


QUIET_WINDOW = 0.5  # s of stillness that count as "stopped"


FIRST_WAYPOINT_MARGIN = 0.1  # s after a goal's first waypoint time before positions are bounded


DISABLE_LATENCY = 0.05  # s a disabled request may take to reach the controllers (README: "The service")


LOG_CLOCK_MARGIN = 0.01  # s: log timestamps have milliseconds; transport takes a little


EXACT = 1e-9  # commanded values are compared with this tolerance


HOME_MAX_DURATION = 2.0  # s (README: "The service")


class HarnessConfiguration(NamedTuple):
    source: str  # the file it was read from
    tests: Tuple[str, ...]  # in TESTS order
    test_duration: float
    iterations: int
    position_tolerance: float
    heading_tolerance: float
    report_samples: int
    node: Configuration  # the node's configuration during the tests (behaviour: all; set per test)

    @property
    def platform(self) -> str:
        return self.node.platform


def _test_names(text: str) -> Tuple[str, ...]:
    names: List[str] = []
    for item in text.split(","):
        name = item.strip(" \t").lower()
        if not name:
            raise InvalidValue("empty name in the list")
        if name not in TESTS:
            raise InvalidValue("unknown test {!r}".format(item.strip(" \t")))
        if name in names:
            raise InvalidValue("{} is listed twice".format(name))
        names.append(name)
    return tuple(name for name in TESTS if name in names)


def _harness_key(name: str, attribute: str, parse, expected: str, description: str,
                 default: object = None, required: bool = False) -> KeySpec:
    return KeySpec(name, attribute, required, default, parse, str, expected, description,
                   "" if required else str(default))


HARNESS_KEYS: Dict[str, KeySpec] = OrderedDict((spec.name, spec) for spec in (
    _harness_key("tests", "tests", _test_names, "a comma list of " + ", ".join(TESTS) + " (any case)",
                 "which tests to run", required=True),
    _harness_key("testDuration", "test_duration", number_in(0.5, 3600.0), "a number of seconds in [0.5, 3600]",
                 "seconds each test lets the node animate before disabling it", required=True),
    _harness_key("iterations", "iterations", integer_at_least(1), "an integer >= 1",
                 "rounds of the selected tests", required=True),
    _harness_key("positionTolerance", "position_tolerance", number_in(0.0, 0.5), "a number in [0, 0.5]",
                 "rad (hands: unit) an observed position may pass a bound by", default=0.001),
    _harness_key("headingTolerance", "heading_tolerance", number_in(0.0, 0.5), "a number in [0, 0.5]",
                 "rad the base heading may pass its bound by", default=0.01),
    _harness_key("reportSamples", "report_samples", integer_at_least(1), "an integer >= 1",
                 "observed positions per part shown in the report", default=10),
))


BEHAVIOUR_KEY = "behaviour"  # node key the tests set themselves


_NODE_KEYS = tuple(key for key in KEYS if key != BEHAVIOUR_KEY)


_KNOWN_KEYS = tuple(HARNESS_KEYS) + _NODE_KEYS


def parse_harness_configuration(text: str, source: str, overrides: Optional[Mapping[str, object]] = None,
                                data_dir: Optional[str] = None) -> HarnessConfiguration:
    """The harness configuration in `text` (module docstring); `overrides` are private parameters
    (key -> value). Raises ConfigurationError listing every problem."""
    problems: List[str] = []
    harness_values: Dict[str, object] = {}
    first_lines: Dict[str, int] = {}  # harness key -> its line in the file; 0 for a parameter
    raw_lines = text.lstrip("\ufeff").replace("\r\n", "\n").replace("\r", "\n").split("\n")
    node_lines = _check_file_lines(text, source, raw_lines, harness_values, first_lines, problems)
    node_overrides = _check_overrides(overrides or {}, harness_values, first_lines, problems)
    check_required_keys(HARNESS_KEYS.values(), first_lines, source, problems)
    node = _parse_node_keys(raw_lines, node_lines, source, node_overrides, data_dir, problems)
    if node is not None and "testDuration" in harness_values:
        _check_test_duration(node, harness_values["testDuration"], first_lines.get("testDuration"), source,
                             problems)
    if problems or node is None:
        raise ConfigurationError(problems)
    values = {spec.attribute: harness_values.get(spec.name, spec.default) for spec in HARNESS_KEYS.values()}
    return HarnessConfiguration(source=source, node=node, **values)  # type: ignore[arg-type]


def _check_file_lines(text: str, source: str, raw_lines: List[str], harness_values: Dict[str, object],
                      first_lines: Dict[str, int], problems: List[str]) -> Dict[int, str]:
    """Put the valid values of the file's harness keys into `harness_values` (and their lines into
    `first_lines`), its problems into `problems`; the lines of the node's keys, by line number, which the
    node's parser reads."""
    node_lines: Dict[int, str] = {}
    for line in key_value_lines(text):
        where = "{}:{}".format(source, line.number)
        if line.key == BEHAVIOUR_KEY:
            problems.append("{}: behaviour is set by each test: remove it and list the tests under "
                            "'tests' (expected {})".format(where, HARNESS_KEYS["tests"].expected))
        elif line.key in KEYS:
            node_lines[line.number] = raw_lines[line.number - 1]
        elif line.key not in HARNESS_KEYS:
            problems.append("{}: {}".format(where, unknown_key(line.key, _KNOWN_KEYS)))
        elif line.key in first_lines:
            problems.append("{}: duplicated key {} (first at line {})".format(where, line.key,
                                                                              first_lines[line.key]))
        else:
            first_lines[line.key] = line.number
            checked = check_value(HARNESS_KEYS[line.key], line.value, where, "{}: {}".format(where, line.key),
                                  repr(line.value), problems)
            if checked is not None:
                harness_values[line.key] = checked.value
    return node_lines


def _check_overrides(overrides: Mapping[str, object], harness_values: Dict[str, object],
                     first_lines: Dict[str, int], problems: List[str]) -> Dict[str, object]:
    """Apply the parameters of harness keys to `harness_values` (an invalid one still removes the file's
    value) and put their problems into `problems`; the parameters of node keys, for the node's parser."""
    node_overrides: Dict[str, object] = {}
    for key, value in overrides.items():
        where = "parameter ~{}".format(key)
        if key in HARNESS_KEYS:
            harness_values.pop(key, None)  # the parameter replaces the file's value
            first_lines[key] = 0
            checked = check_override(HARNESS_KEYS[key], value, where, problems)
            if checked is not None:
                harness_values[key] = checked.value
        elif key == BEHAVIOUR_KEY:
            problems.append("{}: behaviour is set by each test; choose the tests with ~tests".format(where))
        elif key in KEYS:
            node_overrides[key] = value
        else:
            problems.append("{}: {}".format(where, unknown_key(str(key), _KNOWN_KEYS)))
    return node_overrides


def _parse_node_keys(raw_lines: List[str], node_lines: Dict[int, str], source: str,
                     node_overrides: Mapping[str, object], data_dir: Optional[str],
                     problems: List[str]) -> Optional[Configuration]:
    """The node's configuration from its keys in the file and its parameters, or None after adding its
    problems to `problems`."""
    # The node's keys keep their line numbers (other lines blank); missing ones are appended with the
    # shipped values, and behaviour with "all" (each test replaces it).
    node_text = [node_lines.get(number, "") for number in range(1, len(raw_lines) + 1)]
    present = {line.key for line in key_value_lines("\n".join(node_text))}
    node_text.extend("{} {}".format(spec.name, "all" if spec.name == BEHAVIOUR_KEY else spec.shipped)
                     for spec in KEYS.values() if spec.required and spec.name not in present)
    try:
        return parse_configuration("\n".join(node_text), source, node_overrides, data_dir)
    except ConfigurationError as error:
        problems.extend(error.problems)
        return None


def _check_test_duration(node: Configuration, test_duration: object, line: Optional[int], source: str,
                         problems: List[str]) -> None:
    """Add a problem when the test is too short for the node to reach its first random position; `line`:
    where the file sets testDuration, 0 or None when a parameter does."""
    shortest = node.gesture_duration + 1.0
    if test_duration < shortest:  # type: ignore[operator]
        where = "{}:{}: testDuration".format(source, line) if line else "parameter ~testDuration"
        problems.append("{} = {}: expected at least gestureDuration + 1 s = {:g} s, so that the first "
                        "random position is reached".format(where, test_duration, shortest))


def load_harness_configuration(path: str, overrides: Optional[Mapping[str, object]] = None,
                               data_dir: Optional[str] = None) -> HarnessConfiguration:
    """The harness configuration in the file at `path`; ConfigurationError also when it cannot be read."""
    return parse_harness_configuration(read_key_value_file(path, ConfigurationError), path, overrides,
                                       data_dir)


def node_configuration(harness: HarnessConfiguration, test: str) -> Configuration:
    """The node's configuration for one test: the harness's node values with that test's behaviour."""
    return harness.node._replace(behaviour=frozenset(TESTS[test].behaviours))


def check_node_configuration_path(path: str, shipped_path: str) -> None:
    """ValueError if `path` is the package's shipped configuration, which the harness must never
    overwrite."""
    if os.path.realpath(path) == os.path.realpath(shipped_path):
        raise ValueError("refusing to write the test configuration to {}: it is the package's shipped "
                         "configuration; give the node (~configFile) or the harness (~nodeConfigFile) "
                         "another file".format(path))
