"""Topic files: which action namespace or topic drives each part of the robot, on one platform.

A topic file is a key-value file (`key_value_file`).

In a topic file the keys are ``RArm``, ``LArm``, ``RHand``, ``LHand``, ``Leg`` (the namespaces of
``control_msgs/FollowJointTrajectory`` action servers), ``Wheels`` (a ``geometry_msgs/Twist``
topic) and ``JointAngles`` (naoqi_driver's ``naoqi_bridge_msgs/JointAnglesWithSpeed`` topic, used with the
configuration's ``actuation joint_angles``; default DEFAULT_JOINT_ANGLES_TOPIC), each at most once. A part
whose key is absent is skipped (the simulator has no hands), but a file must name at least one key. The
value is one legal ROS graph name: it starts with ``/`` or a letter and holds only letters, digits, ``_``
and ``/``, with no ``//`` and no trailing ``/``. Dots are not legal in ROS names: write
``pepper_dcm/cmd_moveto``, not ``pepper_dcm/cmd.moveto``. A relative name (the shipped files') resolves in the
node's namespace and follows remapping, as every ROS name does (`resolved_topics`); an absolute one is used as
written, remapping aside.

Every problem of a file is reported, each on one line naming the file and line, and raised together
as one `TopicFileError`.
"""
import re
from collections import OrderedDict
from typing import Callable, Dict, List, Mapping, NamedTuple, Sequence

from cssr_system.animate_behaviour.key_value_file import (BLANKS, distinct_known_lines, join_problems,
                                                          one_line, read_key_value_file)
from cssr_system.pepper.joint_table import PARTS


WHEELS_KEY = "Wheels"
JOINT_ANGLES_KEY = "JointAngles"
DEFAULT_JOINT_ANGLES_TOPIC = "joint_angles"  # where naoqi_driver listens, in the robot's namespace


# The joint parts of joint_table, then the base, then the topic of the joint_angles actuation.
TOPIC_KEYS = tuple(PARTS) + (WHEELS_KEY, JOINT_ANGLES_KEY)


_ROS_GRAPH_NAME = re.compile(r"(?:/|[A-Za-z])[A-Za-z0-9_/]*\Z", re.ASCII)


class TopicFileError(ValueError):
    """A topic file that cannot be used. `.problems`: one line each; str(error) joins them with '; '."""

    def __init__(self, problems: Sequence[str]) -> None:
        self.problems = tuple(one_line(problem) for problem in problems) or ("invalid topic file",)
        super().__init__(join_problems(self.problems))


class TopicMap(NamedTuple):
    """The topics of one platform: key -> topic name, in TOPIC_KEYS order; absent keys are skipped."""

    path: str
    topics: Mapping[str, str]


def topic_name_problem(value: str) -> str:
    """Why `value` is not a legal ROS graph name, or "" when it is."""
    if BLANKS.search(value):
        return "expected one topic name (found several words)"
    if "." in value:
        return "dots are not legal in ROS names; write underscores ({!r})".format(value.replace(".", "_"))
    if not _ROS_GRAPH_NAME.match(value) or "//" in value or value.endswith("/"):
        return ("expected a legal ROS graph name (starts with '/' or a letter; only letters, digits, "
                "'_' and '/'; no '//' and no trailing '/')")
    return ""


def parse_topic_map(text: str, source: str) -> TopicMap:
    """The topic map in `text`; `source` names the file in messages. Raises TopicFileError."""
    problems: List[str] = []
    found: Dict[str, str] = {}
    for where, line in distinct_known_lines(text, source, TOPIC_KEYS, problems):
        if not line.value:
            problems.append("{}: {} has no topic name (expected a ROS graph name)".format(where, line.key))
            continue
        problem = topic_name_problem(line.value)
        if problem:
            problems.append("{}: {} = {!r}: {}".format(where, line.key, line.value, problem))
        else:
            found[line.key] = line.value
    if not problems and not found:
        problems.append("{}: no topics (expected lines 'Key topic' with Key one of: {})".format(
            source, ", ".join(TOPIC_KEYS)))
    if problems:
        raise TopicFileError(problems)
    return TopicMap(source, OrderedDict((key, found[key]) for key in TOPIC_KEYS if key in found))


def load_topic_map(path: str) -> TopicMap:
    """The topic map in the file at `path`. Raises TopicFileError, also when the file cannot be read."""
    return parse_topic_map(read_key_value_file(path, TopicFileError), path)


def joint_angles_topic(topics: Mapping[str, str]) -> str:
    """The topic the joint_angles actuation streams to: the topic file's JointAngles, else the default."""
    return topics.get(JOINT_ANGLES_KEY, DEFAULT_JOINT_ANGLES_TOPIC)


def resolved_topics(topic_map: TopicMap, resolve: Callable[[str], str]) -> Dict[str, str]:
    """The topic map with every name as the node's client library resolves it (`resolve`: its namespace and
    remapping), the JointAngles default included, so that goals, the watch of other nodes, status and log all use one
    name for each controller and topic."""
    names = OrderedDict(topic_map.topics)
    names.setdefault(JOINT_ANGLES_KEY, DEFAULT_JOINT_ANGLES_TOPIC)
    resolved, problems = OrderedDict(), []
    for key, name in names.items():
        try:
            resolved[key] = resolve(name)
        except Exception as error:  # each client library has its own exception for a name it cannot resolve
            problems.append("{}: {} = {!r}: not a name this ROS can resolve ({})".format(
                topic_map.path, key, name, one_line(str(error))))
    if problems:
        raise TopicFileError(problems)
    return resolved
