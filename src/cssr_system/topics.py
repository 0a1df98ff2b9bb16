"""Topic files: which action namespace or topic drives each part of the robot, on one platform.

Format of a topic file (``data/pepperTopics.dat``, ``data/simulatorTopics.dat``), which is also the
line format of the configuration file:

- one ``Key value`` pair per line, the key first, then one or more spaces or tabs, then the value;
- blank lines are ignored, and so are lines whose first non-blank character is ``#``;
- a ``#`` preceded by a space or a tab starts a comment that runs to the end of the line (values never
  contain blanks, so this is unambiguous); a ``#`` inside a word is part of the word;
- leading and trailing blanks are ignored; CRLF and CR line ends are accepted, as is a UTF-8 byte
  order mark; keys are case-sensitive.

In a topic file the keys are ``RArm``, ``LArm``, ``RHand``, ``LHand``, ``Leg`` (the namespaces of
``control_msgs/FollowJointTrajectory`` action servers) and ``Wheels`` (a ``geometry_msgs/Twist``
topic), each at most once. A part whose key is absent is skipped (the simulator has no hands), but a
file must name at least one. The value is one legal ROS graph name: it starts with ``/`` or a letter
and holds only letters, digits, ``_`` and ``/``, with no ``//`` and no trailing ``/``. Dots are not
legal in ROS names: write ``/pepper_dcm/cmd_moveto``, not ``/pepper_dcm/cmd.moveto``.

Every problem of a file is reported, each on one line naming the file and line, and raised together
as one `TopicFileError`.
"""
import difflib
import re
from collections import OrderedDict
from typing import Dict, Iterable, Iterator, List, Mapping, NamedTuple, Sequence, Tuple

from cssr_system.joint_table import PARTS

WHEELS_KEY = "Wheels"
# The joint parts of joint_table, then the base.
TOPIC_KEYS = tuple(PARTS) + (WHEELS_KEY,)

_BLANKS = re.compile(r"[ \t]+")
_TRAILING_COMMENT = re.compile(r"[ \t]#.*\Z", re.DOTALL)
_ROS_GRAPH_NAME = re.compile(r"(?:/|[A-Za-z])[A-Za-z0-9_/]*\Z", re.ASCII)


def one_line(problem: str) -> str:
    """`problem` with any line break escaped, so that every problem stays on one line."""
    return problem.replace("\r", "\\r").replace("\n", "\\n")


def join_problems(problems: Iterable[str]) -> str:
    return "; ".join(one_line(problem) for problem in problems)


class TopicFileError(ValueError):
    """A topic file that cannot be used. `.problems`: one line each; str(error) joins them with '; '."""

    def __init__(self, problems: Sequence[str]) -> None:
        self.problems = tuple(one_line(problem) for problem in problems) or ("invalid topic file",)
        super().__init__(join_problems(self.problems))


class TopicMap(NamedTuple):
    """The topics of one platform: part key -> topic name, in TOPIC_KEYS order; absent parts are skipped."""

    path: str
    topics: Mapping[str, str]


class KeyValueLine(NamedTuple):
    """One meaningful line of a key-value file: its 1-based number, its key and its value text."""

    number: int
    key: str
    value: str  # the rest of the line, stripped, comment removed; "" when the line holds only a key


def key_value_lines(text: str) -> List[KeyValueLine]:
    """The key-value lines of `text`, in the format of this module's docstring."""
    if text.startswith("\ufeff"):
        text = text[1:]
    lines = []
    for number, raw in enumerate(text.replace("\r\n", "\n").replace("\r", "\n").split("\n"), start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        line = _TRAILING_COMMENT.sub("", line).strip()
        key_and_value = _BLANKS.split(line, maxsplit=1)
        value = key_and_value[1].strip() if len(key_and_value) > 1 else ""
        lines.append(KeyValueLine(number, key_and_value[0], value))
    return lines


def read_text_file(path: str) -> str:
    """The text of a UTF-8 file. Raises OSError, UnicodeError or ValueError (e.g. a NUL in the path)."""
    with open(path, "r", encoding="utf-8-sig", newline="") as stream:
        return stream.read()


def read_key_value_file(path: str, error_type) -> str:
    """The text of the file at `path`; when it cannot be read, raises `error_type` (an error class
    taking a list of problems) with the one problem that says so."""
    try:
        return read_text_file(path)
    except (OSError, UnicodeError, ValueError, TypeError) as error:
        raise error_type([cannot_read(path, error)]) from None


def distinct_known_lines(text: str, source: str, known: Sequence[str],
                         problems: List[str]) -> Iterator[Tuple[str, KeyValueLine]]:
    """Yields (location ``source:line``, line) for every line whose key is in `known` and appears
    for the first time; each unknown or duplicated key adds its problem to `problems` as it comes,
    so that problems stay in line order."""
    first_lines: Dict[str, int] = {}
    for line in key_value_lines(text):
        where = "{}:{}".format(source, line.number)
        if line.key not in known:
            problems.append("{}: {}".format(where, unknown_key(line.key, known)))
        elif line.key in first_lines:
            problems.append("{}: duplicated key {} (first at line {})".format(
                where, line.key, first_lines[line.key]))
        else:
            first_lines[line.key] = line.number
            yield where, line


def cannot_read(path: object, error: Exception) -> str:
    """The one-line problem for a file that cannot be read."""
    if isinstance(error, UnicodeError):
        reason = "not UTF-8 text"
    elif isinstance(error, OSError) and error.strerror:
        reason = error.strerror
    else:
        reason = str(error) or type(error).__name__
    return "cannot read {}: {}".format(path, reason)


def unknown_key(key: str, known: Sequence[str]) -> str:
    """The explanation for a key that is not in `known`, with a suggestion for a likely typo."""
    close = difflib.get_close_matches(key, known, n=1, cutoff=0.6)
    if not close:  # a wrong letter case is a likely typo too
        close = [name for name in known if name.lower() == key.lower()][:1]
    suggestion = "did you mean {}? ".format(close[0]) if close else ""
    separator_hint = "key and value are separated by blanks; " if ("=" in key or ":" in key) else ""
    return "unknown key {!r} ({}{}expected one of: {})".format(key, separator_hint, suggestion, ", ".join(known))


def topic_name_problem(value: str) -> str:
    """Why `value` is not a legal ROS graph name, or "" when it is."""
    if _BLANKS.search(value):
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
