"""The key-value file format shared by the configuration file, the topic files and the harness's
configuration, and the one-line problem messages of all three.

Format:
- one ``Key value`` pair per line, the key first, then one or more spaces or tabs, then the value;
- blank lines are ignored, and so are lines whose first non-blank character is ``#``;
- a ``#`` preceded by a space or a tab starts a comment that runs to the end of the line (values never
  contain blanks, so this is unambiguous); a ``#`` inside a word is part of the word;
- leading and trailing blanks are ignored; CRLF and CR line ends are accepted, as is a UTF-8 byte
  order mark; keys are case-sensitive.
"""
import difflib
import re
from typing import Dict, Iterable, Iterator, List, NamedTuple, Sequence, Tuple


BLANKS = re.compile(r"[ \t]+")


_TRAILING_COMMENT = re.compile(r"[ \t]#.*\Z", re.DOTALL)


def one_line(problem: str) -> str:
    """`problem` with any line break escaped, so that every problem stays on one line."""
    return problem.replace("\r", "\\r").replace("\n", "\\n")


def join_problems(problems: Iterable[str]) -> str:
    return "; ".join(one_line(problem) for problem in problems)


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
        key_and_value = BLANKS.split(line, maxsplit=1)
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
