"""Unit tests of cssr_system.animate_behaviour.configuration: the configuration file, its checks and its overrides."""
import os
import shutil
from collections import OrderedDict

import pytest
from hypothesis import given, settings, strategies as st

from cssr_system import package_files
from cssr_system.animate_behaviour.configuration import (BEHAVIOURS, KEYS, PLATFORMS, Configuration,
                                                         ConfigurationError, configuration_items,
                                                         format_configuration_file, load_configuration,
                                                         parse_configuration, topic_file_path)

PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA_DIR = os.path.join(PACKAGE_ROOT, "data")
SHIPPED_FILE = os.path.join(PACKAGE_ROOT, "config", "animateBehaviourConfiguration.ini")
SOURCE = "animateBehaviourConfiguration.ini"

# The README's configuration table, written out independently of the module's table.
SHIPPED_VALUES = OrderedDict([
    ("platform", "robot"),
    ("behaviour", "all"),
    ("robotTopics", "pepperTopics.dat"),
    ("simulatorTopics", "simulatorTopics.dat"),
    ("verboseMode", "false"),
    ("rotMaximumRange", "0.3"),
    ("selectedRange", "0.5"),
    ("armMaximumRange", "0.2,0.2,0.2,0.35,0.2"),
    ("handMaximumRange", "0.7"),
    ("legMaximumRange", "0.1,0.1,0.08"),
    ("gestureDuration", "1.0"),
    ("numPoints", "100"),
    ("numPointsLeg", "2"),
    ("legRepeatFactor", "8"),
])
LINE = {key: number for number, key in enumerate(SHIPPED_VALUES, start=1)}  # line of each key in config_text()
SHIPPED_DEFAULTS = Configuration(
    platform="robot", behaviour=frozenset({"body", "hands", "rotation"}), robot_topics="pepperTopics.dat",
    simulator_topics="simulatorTopics.dat", verbose_mode=False, rot_maximum_range=0.3, selected_range=0.5,
    arm_maximum_range=(0.2, 0.2, 0.2, 0.35, 0.2), hand_maximum_range=0.7, leg_maximum_range=(0.1, 0.1, 0.08),
    gesture_duration=1.0, num_points=100, num_points_leg=2, leg_repeat_factor=8,
    random_seed=None, home_on_disable=True, heading_bound=0.3)


def config_text(changes=None, remove=(), extra=""):
    """The 14 required keys, one per line in the README's order (see LINE), with values changed or keys removed."""
    values = OrderedDict(SHIPPED_VALUES)
    values.update(changes or {})
    lines = ["{} {}".format(key, value) for key, value in values.items() if key not in remove]
    return "\n".join(lines) + "\n" + extra


def parse(text, overrides=None, data_dir=DATA_DIR):
    return parse_configuration(text, SOURCE, overrides, data_dir)


def problems_of(text, overrides=None, data_dir=DATA_DIR):
    with pytest.raises(ConfigurationError) as raised:
        parse(text, overrides, data_dir)
    error = raised.value
    assert isinstance(error, ValueError)
    assert "\n" not in str(error) and str(error) == "; ".join(error.problems)
    return error.problems


def only_problem(text, overrides=None, data_dir=DATA_DIR):
    problems = problems_of(text, overrides, data_dir)
    assert len(problems) == 1, problems
    return problems[0]


def at(key):
    return "{}:{}: {} = ".format(SOURCE, LINE[key], key)


# --- the shipped files and the table ----------------------------------------------------------------

def test_shipped_configuration_has_the_spec_defaults():
    config = load_configuration(SHIPPED_FILE)
    assert config == SHIPPED_DEFAULTS
    assert type(config.num_points) is int and type(config.rot_maximum_range) is float
    assert type(config.verbose_mode) is bool and isinstance(config.behaviour, frozenset)


def test_shipped_configuration_is_written_from_the_table():
    with open(SHIPPED_FILE) as stream:
        assert stream.read() == format_configuration_file(SHIPPED_DEFAULTS)


def test_shipped_configuration_comments_every_key():
    with open(SHIPPED_FILE) as stream:
        lines = stream.read().splitlines()
    for key in KEYS:
        (index,) = [i for i, line in enumerate(lines) if line.lstrip("# ").split(" ")[0] == key]
        assert lines[index - 1].startswith("# "), key


def test_table_matches_the_configuration_fields():
    assert [spec.attribute for spec in KEYS.values()] == list(Configuration._fields)
    assert [name for name, spec in KEYS.items() if spec.required] == list(SHIPPED_VALUES)
    for spec in KEYS.values():
        assert spec.name and spec.expected and spec.description
        if not spec.required:
            assert spec.default == Configuration._field_defaults[spec.attribute]
        assert spec.shipped == configuration_items(SHIPPED_DEFAULTS)[spec.name]
    assert BEHAVIOURS == ("body", "hands", "rotation") and PLATFORMS == ("robot", "simulator")


def test_configuration_items_are_written_as_in_the_file():
    items = configuration_items(SHIPPED_DEFAULTS)
    expected = OrderedDict(SHIPPED_VALUES)
    expected.update(randomSeed="none", homeOnDisable="true", headingBound="0.3", yieldQuietTime="1.0",
                    motionStyle="random", breathsPerMinute="12.0", breathingAmplitude="0.6", actuation="trajectory",
                    intensity="1.0",
                    moveArms="true", moveHands="true", moveLeg="true", turnBase="true", mode="auto",
                    listeningRange="0.3", speakingArmRange="0.35,0.4,0.4,0.4,0.4", beatsPerMinute="60.0",
                    speakingTopic="none", listeningTopic="none", speakingAction="none", listeningAction="none",
                    conversationTimeout="3.0")
    assert items == expected and list(items) == list(expected)
    items = configuration_items(SHIPPED_DEFAULTS._replace(behaviour=frozenset({"rotation", "body"}), random_seed=7))
    assert items["behaviour"] == "body,rotation" and items["randomSeed"] == "7"


def test_optional_keys_take_their_defaults():
    assert parse(config_text()) == SHIPPED_DEFAULTS


def test_optional_keys_can_be_set():
    text = config_text(extra="randomSeed 42\nhomeOnDisable FALSE\nheadingBound 0.5\nyieldQuietTime 2.5\n")
    config = parse(text)
    assert (config.random_seed, config.home_on_disable, config.heading_bound, config.yield_quiet_time) == \
        (42, False, 0.5, 2.5)
    assert parse(config_text(extra="randomSeed NONE\n")).random_seed is None


def test_the_conversation_keys_are_validated_and_none_watches_nothing():
    config = parse(config_text(extra="mode Listening\nspeakingAction /tts\nlisteningTopic NONE\n"))
    assert (config.mode, config.speaking_action, config.listening_topic) == ("listening", "/tts", "")
    assert parse(config_text(), {"speakingTopic": ""}).speaking_topic == "", "an empty parameter watches nothing"
    for extra in ("mode talking\n", "beatsPerMinute 200\n", "speakingArmRange 0.3,0.3\n", "listeningRange 2\n",
                  "speakingTopic a//b\n", "conversationTimeout 0\n"):
        with pytest.raises(ConfigurationError, match=extra.split()[0]):
            parse(config_text(extra=extra))


# --- round trip -----------------------------------------------------------------------------------------

unit = st.floats(min_value=0.0, max_value=1.0)


@st.composite
def configurations(draw):
    num_points = draw(st.integers(1, 500))
    repeat = draw(st.integers(1, num_points))
    return Configuration(
        platform=draw(st.sampled_from(PLATFORMS)),
        behaviour=draw(st.frozensets(st.sampled_from(BEHAVIOURS), min_size=1)),
        robot_topics=draw(st.sampled_from(["pepperTopics.dat", "copy of robot.dat".replace(" ", "_"),
                                           os.path.join(DATA_DIR, "pepperTopics.dat")])),
        simulator_topics=draw(st.sampled_from(["simulatorTopics.dat", "sim,#1.dat"])),
        verbose_mode=draw(st.booleans()),
        rot_maximum_range=draw(unit), selected_range=draw(unit),
        arm_maximum_range=tuple(draw(st.lists(unit, min_size=5, max_size=5))),
        hand_maximum_range=draw(unit),
        leg_maximum_range=tuple(draw(st.lists(unit, min_size=3, max_size=3))),
        gesture_duration=draw(st.floats(min_value=0.0, exclude_min=True, allow_infinity=False)),
        num_points=num_points, leg_repeat_factor=repeat,
        num_points_leg=draw(st.integers(1, num_points // repeat)),
        random_seed=draw(st.none() | st.integers(0, 2 ** 32 - 1)),
        home_on_disable=draw(st.booleans()),
        heading_bound=draw(st.floats(min_value=0.0, max_value=0.5)),
        yield_quiet_time=draw(st.floats(min_value=0.0, max_value=10.0)),
        motion_style=draw(st.sampled_from(["random", "breathing"])),
        breaths_per_minute=draw(st.floats(min_value=5.0, max_value=20.0)),
        breathing_amplitude=draw(st.floats(min_value=0.0, max_value=1.0)),
        actuation=draw(st.sampled_from(["trajectory", "joint_angles"])))


@pytest.fixture(scope="module")
def round_trip_data_dir(tmp_path_factory):
    folder = tmp_path_factory.mktemp("data")
    for source, copies in (("pepperTopics.dat", ["pepperTopics.dat", "copy_of_robot.dat"]),
                           ("simulatorTopics.dat", ["simulatorTopics.dat", "sim,#1.dat"])):
        for name in copies:
            shutil.copy(os.path.join(DATA_DIR, source), str(folder / name))
    return str(folder)


# The data folder is a module-scoped fixture: shared by every example, as hypothesis wants.
@settings(max_examples=300, deadline=None)
@given(configurations())
def test_format_configuration_file_round_trips(round_trip_data_dir, config):
    text = format_configuration_file(config)
    assert parse_configuration(text, "written.ini", data_dir=round_trip_data_dir) == config


def test_round_trip_through_a_file(tmp_path):
    config = SHIPPED_DEFAULTS._replace(platform="simulator", behaviour=frozenset({"hands"}), random_seed=3)
    path = tmp_path / "node.ini"
    path.write_text(format_configuration_file(config))
    assert load_configuration(str(path), data_dir=DATA_DIR) == config


# --- file format ---------------------------------------------------------------------------------------

def test_crlf_comments_blanks_and_tabs():
    text = ("\ufeff# header\r\n\r\n  # indented comment\r\n" + config_text(
        {"platform": "simulator   # trailing comment", "armMaximumRange": "0.1, 0.2 ,0.3 , 0.4,\t0.5",
         "verboseMode": "TRUE\t#x"}).replace(" ", "\t", 1).replace("\n", "\r\n"))
    config = parse(text)
    assert config.platform == "simulator" and config.verbose_mode is True
    assert config.arm_maximum_range == (0.1, 0.2, 0.3, 0.4, 0.5)


def test_lines_are_counted_with_crlf():
    problem = only_problem(config_text({"numPoints": "x"}).replace("\n", "\r\n"))
    assert problem.startswith(at("numPoints"))


@pytest.mark.parametrize("text, expected", [("true", True), ("TRUE", True), ("True", True), ("tRuE", True),
                                            ("false", False), ("FALSE", False), ("False", False)])
def test_booleans_in_any_case(text, expected):
    assert parse(config_text({"verboseMode": text})).verbose_mode is expected


@pytest.mark.parametrize("text, expected", [
    ("all", set(BEHAVIOURS)), ("ALL", set(BEHAVIOURS)), ("All", set(BEHAVIOURS)), ("body", {"body"}),
    ("Hands", {"hands"}), ("ROTATION", {"rotation"}), ("body,hands", {"body", "hands"}),
    ("Body, Rotation", {"body", "rotation"}), ("hands , body ,rotation", set(BEHAVIOURS)),
    ("body,body", {"body"}), ("body,all", set(BEHAVIOURS))])
def test_behaviour_in_any_case(text, expected):
    assert parse(config_text({"behaviour": text})).behaviour == frozenset(expected)


def test_platform_in_any_case_is_stored_lower_case():
    assert parse(config_text({"platform": "Simulator"})).platform == "simulator"
    assert parse(config_text({"platform": "ROBOT"})).platform == "robot"


@pytest.mark.parametrize("text, expected", [("1", 1.0), (".5", 0.5), ("1.", 1.0), ("+0.25", 0.25), ("5e-1", 0.5),
                                            ("0", 0.0), ("-0", 0.0)])
def test_number_forms(text, expected):
    assert parse(config_text({"selectedRange": text})).selected_range == expected


# --- one problem per invalid value ---------------------------------------------------------------------

def test_missing_file(tmp_path):
    path = str(tmp_path / "absent.ini")
    with pytest.raises(ConfigurationError) as raised:
        load_configuration(path)
    assert raised.value.problems == ("cannot read {}: No such file or directory".format(path),)
    with pytest.raises(ConfigurationError, match="cannot read"):
        load_configuration(str(tmp_path))


def test_missing_key():
    problem = only_problem(config_text(remove=["numPoints"]))
    assert problem == "{}: missing key numPoints (expected an integer >= 1)".format(SOURCE)


def test_all_missing_keys_of_an_empty_file():
    problems = problems_of("# nothing\n")
    assert [problem.split(" ")[3] for problem in problems] == list(SHIPPED_VALUES)


def test_unknown_key():
    problem = only_problem(config_text(extra="selectedRang 0.5\n"))
    assert problem.startswith("{}:15: unknown key 'selectedRang'".format(SOURCE))
    assert "did you mean selectedRange?" in problem
    assert "expected one of: " + ", ".join(KEYS) in problem


def test_unknown_key_in_other_case_and_with_equals():
    problems = problems_of(config_text(extra="NumPoints 3\nrandomSeed=3\n"))
    assert "did you mean numPoints?" in problems[0]
    assert "did you mean randomSeed?" in problems[1] and "separated by blanks" in problems[1]


def test_duplicated_key():
    problem = only_problem(config_text(extra="\ngestureDuration 2.0\n"))
    assert problem == "{}:16: duplicated key gestureDuration (first at line {})".format(SOURCE, LINE["gestureDuration"])


def test_key_without_value():
    problem = only_problem(config_text({"selectedRange": ""}))
    assert problem.startswith("{}:{}: selectedRange has no value (expected a number in [0, 1])".format(
        SOURCE, LINE["selectedRange"]))


@pytest.mark.parametrize("key", ["rotMaximumRange", "selectedRange", "handMaximumRange", "gestureDuration",
                                 "numPoints", "numPointsLeg", "legRepeatFactor"])
@pytest.mark.parametrize("value", ["abc", "nan", "inf", "-inf", "1e999", "0x1", "1_0", "", "0.5 0.5", "١"])
def test_non_numbers(key, value):
    problem = only_problem(config_text({key: value}))
    if value:
        assert problem.startswith("{}{!r}: expected ".format(at(key), value))
    else:
        assert "{} has no value".format(key) in problem
    assert KEYS[key].expected in problem


@pytest.mark.parametrize("key, value", [
    ("rotMaximumRange", "1.01"), ("rotMaximumRange", "-0.1"), ("selectedRange", "1.5"), ("selectedRange", "-1e-9"),
    ("handMaximumRange", "2"), ("handMaximumRange", "-0.5"), ("gestureDuration", "0"), ("gestureDuration", "-1"),
    ("numPoints", "0"), ("numPointsLeg", "0"), ("numPointsLeg", "-2"), ("legRepeatFactor", "0"),
    ("numPoints", "2.5"), ("numPoints", "1e2"), ("numPoints", "100.0")])
def test_out_of_range_and_non_integers(key, value):
    problem = only_problem(config_text({key: value}))
    assert problem == "{}{!r}: expected {}".format(at(key), value, KEYS[key].expected)


def test_range_expectations_are_stated():
    assert "[0, 1]" in only_problem(config_text({"selectedRange": "1.5"}))
    assert "> 0" in only_problem(config_text({"gestureDuration": "0"}))
    assert ">= 1" in only_problem(config_text({"numPoints": "0"}))


@pytest.mark.parametrize("line, expected", [
    ("headingBound 0.6", "[0, 0.5]"), ("headingBound -0.1", "[0, 0.5]"), ("randomSeed -1", "none or an integer"),
    ("randomSeed 4294967296", "4294967295"), ("randomSeed 1.5", "none or an integer"),
    ("homeOnDisable yes", "true or false"), ("yieldQuietTime -1", "[0, 10]"), ("yieldQuietTime 11", "[0, 10]"),
    ("motionStyle calm", "random or breathing"), ("breathsPerMinute 30", "[5, 20]"), ("breathsPerMinute 4", "[5, 20]"),
    ("breathingAmplitude 1.5", "[0, 1]"), ("actuation setAngles", "trajectory or joint_angles")])
def test_optional_keys_are_checked(line, expected):
    problem = only_problem(config_text(extra=line + "\n"))
    key, value = line.split(" ")
    assert problem.startswith("{}:15: {} = {!r}: expected ".format(SOURCE, key, value)) and expected in problem


@pytest.mark.parametrize("key, value, detail", [
    ("armMaximumRange", "0.2,0.2,0.2,0.35", "found 4 values"),
    ("armMaximumRange", "0.2,0.2,0.2,0.35,0.2,0.2", "found 6 values"),
    ("legMaximumRange", "0.1,0.1", "found 2 values"),
    ("legMaximumRange", "0.1", "found 1 value"),
    ("legMaximumRange", "0.1,,0.1", "value 2 '' is not a number"),
    ("legMaximumRange", "0.1 0.1 0.1", "several words"),
    ("armMaximumRange", "0.2,1.2,0.2,x,0.2", "value 2 '1.2' is out of range, value 4 'x' is not a number"),
    ("legMaximumRange", "0.1,0.1,-0.08", "value 3 '-0.08' is out of range"),
    ("legMaximumRange", "0.1,0.1,nan", "value 3 'nan' is not a number")])
def test_lists(key, value, detail):
    problem = only_problem(config_text({key: value}))
    assert problem.startswith("{}{!r}: expected {} numbers in [0, 1] separated by commas".format(
        at(key), value, 5 if key == "armMaximumRange" else 3))
    assert detail in problem


def test_list_expectation_names_the_joints_in_order():
    assert "ShoulderPitch, ShoulderRoll, ElbowRoll, ElbowYaw, WristYaw" in KEYS["armMaximumRange"].expected
    assert "HipPitch, HipRoll, KneePitch" in KEYS["legMaximumRange"].expected


@pytest.mark.parametrize("key, value, detail", [
    ("platform", "robots", "robot or simulator"), ("platform", "sim", "robot or simulator"),
    ("behaviour", "dance", "unknown name 'dance'"), ("behaviour", "body,,hands", "empty name"),
    ("behaviour", "body,", "empty name"), ("behaviour", "body hands", "several words"),
    ("verboseMode", "yes", "true or false"), ("verboseMode", "1", "true or false"),
    ("robotTopics", "my topics.dat", "several words")])
def test_words(key, value, detail):
    problem = only_problem(config_text({key: value}))
    assert problem.startswith("{}{!r}: expected {}".format(at(key), value, KEYS[key].expected))
    assert detail in problem


def test_leg_repeat_factor_larger_than_num_points():
    problem = only_problem(config_text({"numPoints": "5", "legRepeatFactor": "6", "numPointsLeg": "9"}))
    assert problem.startswith(at("legRepeatFactor") + "'6': expected an integer <= numPoints (5,")
    assert "{}:{}".format(SOURCE, LINE["numPoints"]) in problem


def test_num_points_leg_larger_than_the_chunk():
    assert parse(config_text({"numPointsLeg": "12"})).num_points_leg == 12
    problem = only_problem(config_text({"numPointsLeg": "13"}))
    assert problem.startswith(at("numPointsLeg") + "'13': expected an integer <= the leg chunk size")
    assert "floor(100 / 8) = 12" in problem


def test_no_cross_key_cascade_from_invalid_keys():
    problem = only_problem(config_text({"numPoints": "many", "numPointsLeg": "500"}))
    assert problem.startswith(at("numPoints"))
    problem = only_problem(config_text({"platform": "robots", "robotTopics": "absent.dat"}))
    assert problem.startswith(at("platform"))


def test_missing_topic_file_of_the_selected_platform(tmp_path):
    problem = only_problem(config_text({"robotTopics": "absent.dat"}))
    assert problem.startswith(at("robotTopics") + "'absent.dat': topic file of platform robot: cannot read ")
    assert os.path.join(DATA_DIR, "absent.dat") in problem and "No such file" in problem
    problem = only_problem(config_text({"platform": "simulator", "simulatorTopics": "/absent/sim.dat"}))
    assert problem.startswith(at("simulatorTopics") + "'/absent/sim.dat': topic file of platform simulator")


def test_missing_topic_file_of_the_other_platform_is_fine():
    assert parse(config_text({"simulatorTopics": "absent.dat"})).simulator_topics == "absent.dat"
    assert parse(config_text({"platform": "simulator", "robotTopics": "absent.dat"})).platform == "simulator"


def test_invalid_topic_file_of_the_selected_platform(tmp_path):
    (tmp_path / "dotted.dat").write_text("RArm /a\nWheels /pepper_dcm/cmd.moveto\n")
    problem = only_problem(config_text({"robotTopics": "dotted.dat"}), data_dir=str(tmp_path))
    assert problem.startswith(at("robotTopics") + "'dotted.dat': topic file of platform robot: ")
    assert "dotted.dat:2: Wheels" in problem and "underscores" in problem


def test_every_problem_is_reported_in_one_error():
    text = config_text({"platform": "moon", "selectedRange": "2", "armMaximumRange": "0.1"},
                       remove=["numPoints"], extra="bogus 1\nverboseMode true\n")
    problems = problems_of(text, overrides={"gestureDuration": -1.0, "nonsense": 1})
    assert len(problems) == 8, problems
    located = [problem.split(" ")[0] for problem in problems]
    assert located == ["{}:{}:".format(SOURCE, LINE["platform"]), "{}:{}:".format(SOURCE, LINE["selectedRange"]),
                       "{}:{}:".format(SOURCE, LINE["armMaximumRange"]), "{}:14:".format(SOURCE),
                       "{}:15:".format(SOURCE), "parameter", "parameter", SOURCE + ":"]


# --- overrides -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("key, value, attribute, expected", [
    ("behaviour", "hands", "behaviour", frozenset({"hands"})),
    ("behaviour", ["body", "Rotation"], "behaviour", frozenset({"body", "rotation"})),
    ("platform", "simulator", "platform", "simulator"),
    ("verboseMode", True, "verbose_mode", True),
    ("verboseMode", "True", "verbose_mode", True),
    ("homeOnDisable", False, "home_on_disable", False),
    ("numPoints", 50, "num_points", 50),
    ("numPoints", "50", "num_points", 50),
    ("selectedRange", 1, "selected_range", 1.0),
    ("selectedRange", 0.25, "selected_range", 0.25),
    ("selectedRange", " 0.25 ", "selected_range", 0.25),
    ("armMaximumRange", [0.1, 0.2, 0.3, 0.4, 0.5], "arm_maximum_range", (0.1, 0.2, 0.3, 0.4, 0.5)),
    ("armMaximumRange", (0, 1, 0, 1, 0), "arm_maximum_range", (0.0, 1.0, 0.0, 1.0, 0.0)),
    ("legMaximumRange", "0.1, 0.1, 0.1", "leg_maximum_range", (0.1, 0.1, 0.1)),
    ("randomSeed", 7, "random_seed", 7),
    ("randomSeed", None, "random_seed", None),
    ("randomSeed", "none", "random_seed", None),
    ("headingBound", 0.1, "heading_bound", 0.1),
    ("yieldQuietTime", 0, "yield_quiet_time", 0.0),
    ("motionStyle", "Breathing", "motion_style", "breathing"),
    ("actuation", "Joint_Angles", "actuation", "joint_angles"),
    ("breathsPerMinute", 6, "breaths_per_minute", 6.0),
    ("robotTopics", os.path.join(DATA_DIR, "pepperTopics.dat"), "robot_topics",
     os.path.join(DATA_DIR, "pepperTopics.dat"))])
def test_overrides_of_every_type(key, value, attribute, expected):
    config = parse(config_text(), overrides={key: value})
    assert getattr(config, attribute) == expected
    assert config._replace(**{attribute: getattr(SHIPPED_DEFAULTS, attribute)}) == SHIPPED_DEFAULTS


def test_override_supplies_a_missing_key():
    assert parse(config_text(remove=["numPoints"]), overrides={"numPoints": 100}) == SHIPPED_DEFAULTS


@pytest.mark.parametrize("key, value, shown", [
    ("selectedRange", 1.5, "1.5"), ("selectedRange", "1.5", "'1.5'"), ("selectedRange", True, "True"),
    ("numPoints", 2.5, "2.5"), ("numPoints", False, "False"), ("verboseMode", 1, "1"),
    ("armMaximumRange", [0.2, 0.2], "[0.2, 0.2]"), ("behaviour", [], "[]"), ("behaviour", "", "''"),
    ("platform", "robot\nplatform simulator", "'robot\\nplatform simulator'"),
    ("robotTopics", "a\nb", "'a\\nb'"), ("robotTopics", "#a", "'#a'"), ("gestureDuration", float("nan"), "nan")])
def test_invalid_overrides_are_located_at_the_parameter(key, value, shown):
    problem = only_problem(config_text(), overrides={key: value})
    if problem.startswith("parameter ~{} has no value".format(key)):
        assert value in ([], "")
    else:
        assert problem.startswith("parameter ~{} = {}: expected {}".format(key, shown, KEYS[key].expected))


def test_override_of_an_unsupported_type():
    problem = only_problem(config_text(), overrides={"numPoints": {"a": 1}})
    assert problem.startswith("parameter ~numPoints = {'a': 1}: expected an integer >= 1")
    assert "dict" in problem


def test_unknown_override_key():
    problem = only_problem(config_text(), overrides={"numpoints": 3})
    assert problem.startswith("parameter ~numpoints: unknown key 'numpoints' (did you mean numPoints?")


def test_invalid_file_value_is_reported_even_when_overridden():
    problem = only_problem(config_text({"selectedRange": "x"}), overrides={"selectedRange": 0.5})
    assert problem.startswith(at("selectedRange"))


def test_override_takes_part_in_cross_key_rules():
    problem = only_problem(config_text(), overrides={"numPoints": 10})
    assert problem.startswith("parameter ~legRepeatFactor") is False
    assert problem.startswith(at("numPointsLeg") + "'2': expected an integer <= the leg chunk size")
    assert "floor(10 / 8) = 1" in problem
    problem = only_problem(config_text(), overrides={"legRepeatFactor": 200})
    assert problem.startswith("parameter ~legRepeatFactor = 200: expected an integer <= numPoints (100, "
                              "{}:{})".format(SOURCE, LINE["numPoints"]))


def test_override_of_the_platform_checks_the_other_topic_file():
    problem = only_problem(config_text({"simulatorTopics": "absent.dat"}), overrides={"platform": "simulator"})
    assert problem.startswith(at("simulatorTopics") + "'absent.dat': topic file of platform simulator")


# --- topic file paths --------------------------------------------------------------------------------

def test_topic_file_path():
    assert topic_file_path(SHIPPED_DEFAULTS, "/d") == os.path.join("/d", "pepperTopics.dat")
    simulator = SHIPPED_DEFAULTS._replace(platform="simulator")
    assert topic_file_path(simulator, "/d") == os.path.join("/d", "simulatorTopics.dat")
    absolute = simulator._replace(simulator_topics="/elsewhere/sim.dat")
    assert topic_file_path(absolute, "/d") == "/elsewhere/sim.dat"
    # The package may be imported through a workspace link to this folder: compare real paths.
    assert os.path.realpath(topic_file_path(SHIPPED_DEFAULTS, None)) == os.path.realpath(
        os.path.join(DATA_DIR, "pepperTopics.dat"))
    assert os.path.samefile(package_files.data_dir(), DATA_DIR)


def test_default_data_dir_is_the_package_data_folder():
    assert parse_configuration(config_text(), SOURCE) == SHIPPED_DEFAULTS


# --- robustness --------------------------------------------------------------------------------------

def configuration_or_error(text, overrides=None):
    try:
        return parse(text, overrides)
    except ConfigurationError as error:
        assert error.problems and all("\n" not in problem and "\r" not in problem for problem in error.problems)
        return error


lines_of_keys = st.lists(st.tuples(st.sampled_from(list(KEYS) + ["bogus", "#", ""]),
                                   st.text(alphabet=" \t,.#0123456789-+eE/abnlrtu\r\n", max_size=12)),
                         max_size=20)


@settings(max_examples=300, deadline=None)
@given(lines_of_keys)
def test_any_key_value_text_gives_a_configuration_or_one_line_problems(lines):
    configuration_or_error("\n".join("{} {}".format(key, value) for key, value in lines))


@settings(max_examples=200, deadline=None)
@given(st.text())
def test_any_text_gives_a_configuration_or_one_line_problems(text):
    configuration_or_error(text)


scalars = st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=10)


@settings(max_examples=300, deadline=None)
@given(st.dictionaries(st.sampled_from(list(KEYS) + ["configFile"]),
                       scalars | st.lists(scalars, max_size=6) | st.dictionaries(st.text(), st.integers()),
                       max_size=4))
def test_any_overrides_give_a_configuration_or_one_line_problems(overrides):
    result = configuration_or_error(config_text(), overrides)
    if isinstance(result, ConfigurationError):
        assert all(problem.startswith("parameter ~") or problem.startswith(SOURCE) for problem in result.problems)
