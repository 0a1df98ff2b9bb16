"""Unit tests of cssr_system.animate_behaviour.topics: the topic file format and the shipped topic files."""
import os

import pytest
from hypothesis import given, settings, strategies as st

from cssr_system.animate_behaviour.key_value_file import key_value_lines
from cssr_system.animate_behaviour.topics import (TOPIC_KEYS, TopicFileError, TopicMap, joint_angles_topic,
                                                  load_topic_map, parse_topic_map, resolved_topics)
from cssr_system.pepper.joint_table import CONTROLLER_NAMES, PARTS

DATA_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "data")


def action_namespace(namespace, key):
    return "{}/{}/follow_joint_trajectory".format(namespace, CONTROLLER_NAMES[key])


def problems_of(text, source="topics.dat"):
    with pytest.raises(TopicFileError) as raised:
        parse_topic_map(text, source)
    error = raised.value
    assert "\n" not in str(error)
    assert str(error) == "; ".join(error.problems)
    return error.problems


def test_topic_keys_are_the_parts_then_the_wheels_then_the_joint_angles():
    assert TOPIC_KEYS == ("RArm", "LArm", "RHand", "LHand", "Leg", "Wheels", "JointAngles")
    assert TOPIC_KEYS[:-2] == tuple(PARTS)


def test_the_joint_angles_topic_defaults_to_naoqi_drivers():
    assert joint_angles_topic({"RArm": "/a"}) == "joint_angles"
    assert joint_angles_topic({"JointAngles": "/robot/joint_angles"}) == "/robot/joint_angles"


def test_shipped_robot_topics():
    path = os.path.join(DATA_DIR, "pepperTopics.dat")
    topic_map = load_topic_map(path)
    expected = {key: action_namespace("pepper_dcm", key) for key in ("RArm", "LArm", "RHand", "LHand", "Leg")}
    expected["Wheels"] = "pepper_dcm/cmd_moveto"
    expected["JointAngles"] = "joint_angles"
    assert topic_map == TopicMap(path, expected)
    assert list(topic_map.topics) == list(TOPIC_KEYS)


def test_shipped_simulator_topics_have_no_hands():
    path = os.path.join(DATA_DIR, "simulatorTopics.dat")
    topic_map = load_topic_map(path)
    expected = {key: action_namespace("pepper", key) for key in ("RArm", "LArm", "Leg")}
    expected["Wheels"] = "pepper/cmd_vel"
    expected["JointAngles"] = "joint_angles"
    assert dict(topic_map.topics) == expected
    assert topic_map.path == path


def test_shipped_topic_files_have_one_pair_per_line_and_no_dots():
    for name in ("pepperTopics.dat", "simulatorTopics.dat"):
        with open(os.path.join(DATA_DIR, name)) as stream:
            lines = stream.read().splitlines()
        assert all(len(line.split()) == 2 and "." not in line for line in lines), name


def test_blank_lines_comments_tabs_crlf_and_byte_order_mark():
    text = ("\ufeff# robot topics\r\n\r\n   # indented comment\r\n"
            "RArm\t/a/b_c   # trailing comment\r\n"
            "  Wheels  \t  cmd_vel  \r\n"
            "\t#Leg /commented/out\r\n")
    topic_map = parse_topic_map(text, "t.dat")
    assert dict(topic_map.topics) == {"RArm": "/a/b_c", "Wheels": "cmd_vel"}


def test_hash_inside_a_word_is_not_a_comment_and_is_not_a_legal_name():
    (problem,) = problems_of("Leg /x#y\n")
    assert "topics.dat:1" in problem and "Leg" in problem and "'/x#y'" in problem
    assert "legal ROS graph name" in problem


def test_lines_are_numbered_from_one_with_crlf_and_cr():
    lines = key_value_lines("# c\r\nA 1\r\rB\r\n  C  x y  # z")
    assert [(line.number, line.key, line.value) for line in lines] == [(2, "A", "1"), (4, "B", ""),
                                                                       (5, "C", "x y")]


def test_dots_are_reported_with_a_suggestion_of_underscores():
    (problem,) = problems_of("RArm /a/b\nWheels /pepper_dcm/cmd.moveto\n", "pepperTopics.dat")
    assert problem.startswith("pepperTopics.dat:2: Wheels")
    assert "'/pepper_dcm/cmd.moveto'" in problem
    assert "dots are not legal" in problem and "underscores" in problem and "'/pepper_dcm/cmd_moveto'" in problem


@pytest.mark.parametrize("name", ["1abc", "/a//b", "/a/", "/a-b", "~private", "/a/b c", "/é"])
def test_illegal_names(name):
    (problem,) = problems_of("RArm {}\n".format(name))
    assert problem.startswith("topics.dat:1: RArm = ")
    assert "expected" in problem


@pytest.mark.parametrize("name", ["/a/b_1/C", "relative/name", "a"])
def test_legal_names(name):
    assert parse_topic_map("RArm {}\n".format(name), "t").topics == {"RArm": name}


def test_a_bare_slash_is_not_a_topic():
    (problem,) = problems_of("Wheels /\n")
    assert "Wheels" in problem


def test_unknown_key_suggests_the_close_one():
    (problem,) = problems_of("RArm /a\nrarm /b\n")
    assert problem.startswith("topics.dat:2: unknown key 'rarm'")
    assert "did you mean RArm?" in problem
    assert "expected one of: RArm, LArm, RHand, LHand, Leg, Wheels, JointAngles" in problem


def test_duplicated_key_names_the_first_line():
    (problem,) = problems_of("Leg /a\n\nLeg /b\n")
    assert problem == "topics.dat:3: duplicated key Leg (first at line 1)"


def test_key_without_topic():
    (problem,) = problems_of("Leg\n")
    assert problem.startswith("topics.dat:1: Leg has no topic name")


def test_several_words():
    (problem,) = problems_of("Leg /a /b\n")
    assert "'/a /b'" in problem and "one topic name" in problem


def test_an_empty_file_is_an_error():
    (problem,) = problems_of("# nothing\n\n")
    assert problem.startswith("topics.dat: no topics")


def test_all_problems_are_reported_together():
    problems = problems_of("Arm /a\nLeg /a.b\nLeg /c\nRHand\n")
    assert [problem.split(":")[1] for problem in problems] == ["1", "2", "3", "4"]


def test_missing_file(tmp_path):
    path = str(tmp_path / "absent.dat")
    with pytest.raises(TopicFileError) as raised:
        load_topic_map(path)
    assert raised.value.problems == ("cannot read {}: No such file or directory".format(path),)


def test_directory_and_binary_file(tmp_path):
    with pytest.raises(TopicFileError, match="cannot read"):
        load_topic_map(str(tmp_path))
    binary = tmp_path / "binary.dat"
    binary.write_bytes(b"RArm \xff\xfe\n")
    with pytest.raises(TopicFileError, match="not UTF-8"):
        load_topic_map(str(binary))


def test_load_reads_crlf_files(tmp_path):
    path = tmp_path / "crlf.dat"
    path.write_bytes(b"RArm /a\r\nWheels /b\r\n")
    assert dict(load_topic_map(str(path)).topics) == {"RArm": "/a", "Wheels": "/b"}


@settings(max_examples=300, deadline=None)
@given(st.text())
def test_any_text_gives_a_map_or_one_line_error(text):
    try:
        topic_map = parse_topic_map(text, "fuzz.dat")
    except TopicFileError as error:
        assert error.problems and all("\n" not in problem and "\r" not in problem for problem in error.problems)
    else:
        assert set(topic_map.topics) <= set(TOPIC_KEYS) and topic_map.topics


names = st.from_regex(r"/?[A-Za-z][A-Za-z0-9_]{0,8}(/[A-Za-z][A-Za-z0-9_]{0,8}){0,3}", fullmatch=True)


@settings(max_examples=200, deadline=None)
@given(st.dictionaries(st.sampled_from(TOPIC_KEYS), names, min_size=1))
def test_written_maps_read_back(topics):
    text = "".join("{}\t{}\n".format(key, name) for key, name in topics.items())
    assert dict(parse_topic_map(text, "t").topics) == topics


def test_the_shipped_topic_files_use_relative_names_so_that_a_namespace_applies():
    for name in ("pepperTopics.dat", "simulatorTopics.dat", "naoqiDriver2Topics.dat"):
        topics = load_topic_map(os.path.join(DATA_DIR, name)).topics
        assert [topic for topic in topics.values() if topic.startswith("/")] == [], name


def test_every_name_is_resolved_by_the_client_library_the_joint_angles_default_included():
    def resolve(name):  # as a node in /robot1 with one remapping
        resolved = name if name.startswith("/") else "/robot1/" + name
        return {"/robot1/pepper/cmd_vel": "/base/cmd_vel"}.get(resolved, resolved)
    topic_map = TopicMap("t.dat", {"RArm": "pepper/RightArm_controller/follow_joint_trajectory",
                                   "LArm": "/elsewhere/LeftArm", "Wheels": "pepper/cmd_vel"})
    assert resolved_topics(topic_map, resolve) == {
        "RArm": "/robot1/pepper/RightArm_controller/follow_joint_trajectory", "LArm": "/elsewhere/LeftArm",
        "Wheels": "/base/cmd_vel", "JointAngles": "/robot1/joint_angles"}


def test_a_name_the_client_library_cannot_resolve_is_one_line_naming_the_file_and_the_key():
    def resolve(name):
        if name == "pepper/2nd":
            raise ValueError("Invalid topic name:\n  token must not start with a number")
        return "/" + name
    with pytest.raises(TopicFileError) as raised:
        resolved_topics(TopicMap("t.dat", {"RArm": "pepper/2nd", "Wheels": "cmd_vel"}), resolve)
    (problem,) = raised.value.problems
    assert problem.startswith("t.dat: RArm = 'pepper/2nd': not a name this ROS can resolve (Invalid topic name:")
    assert "\n" not in problem
