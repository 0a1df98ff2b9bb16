"""The node's log file, ``animateBehaviourLogFile.log``: writing, rotating, parsing.

Format: UTF-8 text, one event per line, three fields separated by single spaces::

    <timestamp> <event> <JSON object>
    2026-11-21T17:03:04.123+01:00 goal_sent {"part": "RArm", "joints": ["RShoulderPitch", ...]}

- timestamp: ISO-8601 local time with milliseconds and the UTC offset,
  ``YYYY-MM-DDTHH:MM:SS.mmm+HH:MM`` (Python ``datetime.fromisoformat`` reads it);
- event: a name chosen by the writer (snake_case by convention), without blanks;
- JSON object: the event's fields on one line (strings escaped as JSON does, so no line break
  can appear inside).  Floats are written with full precision (shortest repr that reads back to
  the same value); NaN and infinities are refused (ValueError naming the field).  numpy arrays
  and tuples become lists, numpy scalars numbers, sets and frozensets sorted lists, datetimes
  ISO-8601 strings; any other object its ``str()``.

Each line is written with one ``os.write`` on an ``O_APPEND`` descriptor, so lines from threads
and processes writing to the same file never interleave, and every line reaches the file (the
kernel) as soon as it is written: there is no user-space buffer to flush.  When a line would take
the file beyond ``max_bytes`` (10 MB by default), the file is renamed to ``<path>.1``, replacing
any previous one, and a new file is started: at most one previous file is kept.  A single line
longer than ``max_bytes`` still goes into an empty file whole.  Writers in other processes notice
the rename and reopen ``<path>``; a line they write in that instant lands at the end of
``<path>.1``, never lost and never torn.  Rotation among processes is serialised with an advisory
``flock`` on the current file.

Readers: ``parse_log_line`` and ``read_log``.
"""
import datetime
import fcntl
import json
import math
import os
import re
import threading
import time
from typing import Any, Callable, Dict, List, NamedTuple, Optional

import numpy

LOG_FILE_NAME = "animateBehaviourLogFile.log"
DEFAULT_MAX_BYTES = 10 * 1024 * 1024
ROTATED_SUFFIX = ".1"

_TIMESTAMP_PATTERN = re.compile(r"\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}\.\d{3}[+-]\d{2}:\d{2}\Z")
_EVENT_PATTERN = re.compile(r"\S+\Z")


class LogEntry(NamedTuple):
    """One parsed line of the log."""

    timestamp: datetime.datetime  # aware (carries the writer's UTC offset)
    event: str
    fields: Dict[str, Any]


def format_timestamp(epoch_seconds: float) -> str:
    """Local time of `epoch_seconds` as ISO-8601 with milliseconds and UTC offset."""
    moment = datetime.datetime.fromtimestamp(epoch_seconds, tz=datetime.timezone.utc).astimezone()
    return moment.isoformat(timespec="milliseconds")


def _jsonable(value: Any, field: str) -> Any:
    """`value` as plain JSON types; ValueError naming `field` for NaN or infinity."""
    if value is None or isinstance(value, (str, bool)):
        return value
    if isinstance(value, numpy.ndarray):
        return _jsonable(value.tolist(), field)
    if isinstance(value, numpy.generic):  # numpy scalars: float64, int32, bool_, str_ ...
        return _jsonable(value.item(), field)
    if isinstance(value, int):
        return int(value)  # IntEnum and friends as plain numbers
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError("event log field %r is %r: not allowed in the log" % (field, value))
        return float(value)
    if isinstance(value, dict):
        return {str(key): _jsonable(item, "%s.%s" % (field, key)) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(item, "%s[%d]" % (field, index)) for index, item in enumerate(value)]
    if isinstance(value, (set, frozenset)):
        items = [_jsonable(item, "%s{}" % field) for item in value]
        try:
            return sorted(items)
        except TypeError:  # mixed types: a stable order all the same
            return sorted(items, key=lambda item: json.dumps(item, sort_keys=True))
    if isinstance(value, (datetime.datetime, datetime.date, datetime.time)):
        return value.isoformat()
    return str(value)


def format_log_line(timestamp: str, event: str, fields: Dict[str, Any]) -> str:
    """One complete log line, newline included."""
    if not isinstance(event, str) or not _EVENT_PATTERN.match(event):
        raise ValueError("event log event name must be a non-empty word without blanks, got %r"
                         % (event,))
    payload = {name: _jsonable(value, name) for name, value in fields.items()}
    return "%s %s %s\n" % (timestamp, event,
                           json.dumps(payload, ensure_ascii=False, allow_nan=False))


class EventLog:
    """An append-only, size-bounded, thread- and process-safe log file (module docstring)."""

    def __init__(self, path: str, max_bytes: int = DEFAULT_MAX_BYTES,
                 clock: Callable[[], float] = time.time) -> None:
        if max_bytes <= 0:
            raise ValueError("max_bytes must be positive, got %r" % (max_bytes,))
        self._path = os.path.abspath(path)
        self._max_bytes = int(max_bytes)
        self._clock = clock
        self._lock = threading.Lock()
        folder = os.path.dirname(self._path)
        os.makedirs(folder, exist_ok=True)
        self._fd = self._open()  # type: Optional[int]

    @property
    def path(self) -> str:
        return self._path

    def write(self, event: str, **fields: Any) -> None:
        """Append one line: timestamp, `event`, `fields` as a JSON object."""
        line = format_log_line(format_timestamp(self._clock()), event, fields).encode("utf-8")
        with self._lock:
            if self._fd is None:
                raise ValueError("event log %s is closed" % self._path)
            if not self._is_current():
                self._reopen()  # another process rotated (or someone removed) the file
            size = os.fstat(self._fd).st_size
            if size > 0 and size + len(line) > self._max_bytes:
                self._rotate(len(line))
            written = os.write(self._fd, line)
            if written < len(line):  # only on a full disk or similar: keep what we can
                os.write(self._fd, line[written:])

    def close(self) -> None:
        """Close the file; later writes raise ValueError.  Closing twice is harmless."""
        with self._lock:
            if self._fd is not None:
                os.close(self._fd)
                self._fd = None

    def __enter__(self) -> "EventLog":
        return self

    def __exit__(self, *exc_info: Any) -> None:
        self.close()

    def _open(self) -> int:
        return os.open(self._path, os.O_WRONLY | os.O_CREAT | os.O_APPEND | os.O_CLOEXEC, 0o644)

    def _reopen(self) -> None:
        assert self._fd is not None
        os.close(self._fd)
        self._fd = self._open()

    def _is_current(self) -> bool:
        """Whether our descriptor is still the file that `path` names."""
        assert self._fd is not None
        try:
            named = os.stat(self._path)
        except FileNotFoundError:
            return False
        opened = os.fstat(self._fd)
        return (named.st_dev, named.st_ino) == (opened.st_dev, opened.st_ino)

    def _rotate(self, line_length: int) -> None:
        """Rename the full file to <path>.1 and start a new one.  The flock makes a writer in
        another process that saw the same full file wait, then find it already rotated."""
        assert self._fd is not None
        fcntl.flock(self._fd, fcntl.LOCK_EX)
        try:
            if self._is_current() and os.fstat(self._fd).st_size + line_length > self._max_bytes:
                os.replace(self._path, self._path + ROTATED_SUFFIX)
        finally:
            fcntl.flock(self._fd, fcntl.LOCK_UN)
        self._reopen()


def parse_log_line(line: str) -> LogEntry:
    """The entry of one log line (trailing newline optional); ValueError if it is malformed."""
    text = line[:-1] if line.endswith("\n") else line
    parts = text.split(" ", 2)
    if len(parts) != 3:
        raise ValueError("malformed log line (expected '<timestamp> <event> <JSON object>'): %s"
                         % _excerpt(text))
    stamp, event, payload = parts
    if not _TIMESTAMP_PATTERN.match(stamp):
        raise ValueError("malformed log line (timestamp is not YYYY-MM-DDTHH:MM:SS.mmm+HH:MM): %s"
                         % _excerpt(text))
    try:
        timestamp = datetime.datetime.fromisoformat(stamp)
    except ValueError:
        raise ValueError("malformed log line (invalid timestamp %r): %s" % (stamp, _excerpt(text))) \
            from None
    if not event:
        raise ValueError("malformed log line (empty event name): %s" % _excerpt(text))
    try:
        fields = json.loads(payload, parse_constant=_refuse_constant)
    except ValueError as error:
        raise ValueError("malformed log line (fields are not JSON: %s): %s"
                         % (error, _excerpt(text))) from None
    if not isinstance(fields, dict):
        raise ValueError("malformed log line (fields are not a JSON object): %s" % _excerpt(text))
    return LogEntry(timestamp, event, fields)


def read_log(path: str, since: Optional[datetime.datetime] = None) -> List[LogEntry]:
    """Every entry of the log file at `path`, in file order; only those at or after `since` when
    given (a naive `since` is local time).  A malformed line raises ValueError naming its line."""
    if since is not None and since.tzinfo is None:
        since = since.astimezone()
    entries = []
    with open(path, "r", encoding="utf-8", newline="\n") as log_file:
        for number, line in enumerate(log_file, start=1):
            try:
                entry = parse_log_line(line)
            except ValueError as error:
                raise ValueError("%s:%d: %s" % (path, number, error)) from None
            if since is None or entry.timestamp >= since:
                entries.append(entry)
    return entries


def default_log_path(package_dir: str, ros_home: Optional[str], file_name: str = LOG_FILE_NAME) -> str:
    """``<package_dir>/data/<file_name>`` when it can be written (the folder, or the package when
    the folder does not exist yet, and the file when it exists); otherwise
    ``<ros_home or ~/.ros>/<file_name>``.  Decided with ``os.access``. The file name defaults to
    the node's log file; the test harness puts its report in the same place."""
    data_dir = os.path.join(package_dir, "data")
    preferred = os.path.join(data_dir, file_name)
    if os.path.isdir(data_dir):
        writable = os.access(data_dir, os.W_OK) and \
            (not os.path.exists(preferred) or os.access(preferred, os.W_OK))
    else:
        writable = os.path.isdir(package_dir) and os.access(package_dir, os.W_OK)
    if writable:
        return preferred
    home = ros_home if ros_home else os.path.join(os.path.expanduser("~"), ".ros")
    return os.path.join(home, file_name)


def _refuse_constant(name: str) -> Any:
    """json.loads hook: NaN and Infinity are not JSON and never written by EventLog."""
    raise ValueError("%s is not a JSON number" % name)


def _excerpt(text: str, limit: int = 120) -> str:
    """`text` for an error message: one line, at most `limit` characters."""
    shown = text if len(text) <= limit else text[:limit] + "..."
    return repr(shown)
