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

Faults (README: "Faults"): ``EventLog`` never raises into its caller, neither when it is made nor
when it writes, because the node's motion and its stopping must not depend on a disk.  A path that
cannot be opened or written at start-up (a read-only or missing folder that cannot be created, a
directory, ``/dev/full``) falls back to ``$ROS_HOME/animateBehaviourLogFile.log`` (``~/.ros`` without
ROS_HOME); when that fails too the log runs without a file.  A file that fails later (full disk,
read-only file system, removed folder that cannot be made again) is not replaced: its lines are
dropped, counted, and the file is tried again every ``retry_period`` seconds.  Each failure is
reported once, and the return to normal once (with the number of lines lost, also written into the
file as an ``error`` event); a file or folder removed while the log runs is made again at the next
line.  Reports go to a ``report(level, text)`` callable (``logging`` levels); the default hands them
to the node's console logger (core/console.py).  A line that cannot be formatted (NaN,
a bad event name) is replaced by an ``error`` event naming the problem.

Readers: ``parse_log_line`` and ``read_log``.
"""
import datetime
import fcntl
import json
import logging
import math
import os
import queue
import re
import stat
import threading
import time
from typing import Any, Callable, Dict, List, NamedTuple, Optional

import numpy

from cssr_system.animate_behaviour.console import console
from cssr_system.animate_behaviour.contract import ERROR, NODE_NAME

LOG_FILE_NAME = "animateBehaviourLogFile.log"
DEFAULT_MAX_BYTES = 10 * 1024 * 1024
ROTATED_SUFFIX = ".1"
RETRY_PERIOD = 5.0  # s between attempts to write again to a log file that failed
ROS_HOME_FALLBACK = "$ROS_HOME"  # EventLog's default fallback: ros_home_log_path() when it is made

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
    if value is None or isinstance(value, (str, bool)):  # bool before int: a bool is an int
        return value
    if isinstance(value, numpy.ndarray):
        return _jsonable_array(value, field)
    if isinstance(value, numpy.generic):  # numpy scalars: float64, int32, bool_, str_ ...
        return _jsonable(value.item(), field)
    if isinstance(value, (int, float)):
        return _jsonable_number(value, field)
    if isinstance(value, (dict, list, tuple, set, frozenset)):
        return _jsonable_collection(value, field)
    if isinstance(value, (datetime.datetime, datetime.date, datetime.time)):
        return value.isoformat()
    return str(value)


def _jsonable_array(value: numpy.ndarray, field: str) -> Any:
    """A numeric array as nested lists of plain numbers, checked in one pass (a goal's 100 points of positions
    are logged at every goal); other arrays item by item."""
    if value.dtype.kind not in "biuf":
        return _jsonable(value.tolist(), field)
    finite = numpy.isfinite(value)
    if not finite.all():
        index = tuple(int(i) for i in numpy.argwhere(~finite)[0])
        _jsonable_number(value[index].item(), field + "".join("[%d]" % i for i in index))
    return value.tolist()


def _jsonable_number(value: Any, field: str) -> Any:
    """An int or float (subclasses included) as a plain int or a finite float; ValueError naming `field`
    for NaN or infinity, which JSON cannot hold."""
    if isinstance(value, int):
        return int(value)  # IntEnum and friends as plain numbers
    if not math.isfinite(value):
        raise ValueError("event log field %r is %r: not allowed in the log" % (field, value))
    return float(value)


def _jsonable_collection(value: Any, field: str) -> Any:
    """A dict as an object with string keys, a list or tuple as a list, a set as a sorted list; each item
    made plain in turn, its field named after the container's (``field.key``, ``field[0]``, ``field{}``)."""
    if isinstance(value, dict):
        return {str(key): _jsonable(item, "%s.%s" % (field, key)) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(item, "%s[%d]" % (field, index)) for index, item in enumerate(value)]
    return _sorted_items([_jsonable(item, "%s{}" % field) for item in value])


def _sorted_items(items: List[Any]) -> List[Any]:
    """The plain items of a set in sorted order: a set has none of its own, and a log should not depend on
    hashing."""
    try:
        return sorted(items)
    except TypeError:  # mixed types: a stable order all the same
        return sorted(items, key=lambda item: json.dumps(item, sort_keys=True))


def format_log_line(timestamp: str, event: str, fields: Dict[str, Any]) -> str:
    """One complete log line, newline included."""
    if not isinstance(event, str) or not _EVENT_PATTERN.match(event):
        raise ValueError("event log event name must be a non-empty word without blanks, got %r"
                         % (event,))
    payload = {name: _jsonable(value, name) for name, value in fields.items()}
    return "%s %s %s\n" % (timestamp, event,
                           json.dumps(payload, ensure_ascii=False, allow_nan=False))


Reporter = Callable[[int, str], None]


def report_to_console(level: int, text: str) -> None:
    """EventLog's default reporter: the node's console logger (core/console.py), which the front-end routes to
    its ROS's console (and Python prints on stderr when none does)."""
    console.log(level, text)


def open_for_append(path: str) -> int:
    """A descriptor appending to `path`, creating the file and its folders as needed."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    return os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND | os.O_CLOEXEC, 0o644)


def _reason(error: BaseException) -> str:
    """An OSError's reason in a few words ("No space left on device"); else its type and text."""
    if isinstance(error, OSError) and error.strerror:
        return error.strerror
    return "{}: {}".format(type(error).__name__, error)


class EventLog:
    """An append-only, size-bounded, thread- and process-safe log file that never raises into its
    caller (module docstring)."""

    def __init__(self, path: str, max_bytes: int = DEFAULT_MAX_BYTES,
                 clock: Callable[[], float] = time.time, fallback: Optional[str] = ROS_HOME_FALLBACK,
                 report: Reporter = report_to_console, retry_period: float = RETRY_PERIOD,
                 monotonic: Callable[[], float] = time.monotonic,
                 opener: Callable[[str], int] = open_for_append) -> None:
        """`fallback`: the file used when `path` cannot be written at start-up (None: none);
        `clock`: the time of the lines; `monotonic`, `retry_period`: when to try a failed file again;
        `opener`: opens a path for appending (tests inject failures here)."""
        if max_bytes <= 0:
            raise ValueError("max_bytes must be positive, got %r" % (max_bytes,))
        self._requested = os.path.abspath(path)
        if fallback == ROS_HOME_FALLBACK:
            fallback = ros_home_log_path(os.environ.get("ROS_HOME"))
        self._fallback = os.path.abspath(fallback) if fallback else None
        if self._fallback == self._requested:
            self._fallback = None
        self._path = self._requested  # the file in use
        self._max_bytes = int(max_bytes)
        self._clock = clock
        self._report = report
        self._retry_period = float(retry_period)
        self._monotonic = monotonic
        self._opener = opener
        self._lock = threading.Lock()
        self._closed = False
        self._fd = None  # type: Optional[int]
        self._settled = False  # a line reached the file in use: it is kept for the whole run
        self._failure = None  # type: Optional[str]  # why lines are being dropped, None when they are not
        self._lost = 0  # lines dropped since the failure began
        self._next_attempt = 0.0
        self._bad_events = set()  # events whose fields could not be written (reported once each)
        self._reports = []  # (level, text) to hand to `report` once the lock is released
        self._reports_lock = threading.Lock()
        with self._lock:
            self._open_at_start()
        self._flush_reports()

    @property
    def path(self) -> str:
        """The file the log writes to: the requested one, or the fallback after a start-up failure."""
        return self._path

    @property
    def writing(self) -> bool:
        """False while lines are dropped (no file could be opened or written)."""
        return self._failure is None and not self._closed

    def write(self, event: str, **fields: Any) -> None:
        """Append one line: timestamp, `event`, `fields` as a JSON object.  Never raises: a failure
        is reported (module docstring) and the line dropped; after close() lines are ignored."""
        try:
            moment = self._clock()
        except Exception as error:  # not expected; still never the caller's problem
            self._report_unexpected(error)
            self._flush_reports()
            return
        self.write_at(moment, event, fields)

    def write_at(self, moment: float, event: str, fields: Dict[str, Any]) -> None:
        """`write`, with the line's time given (seconds since 1970)."""
        try:
            line = self._format(moment, event, fields)
            with self._lock:
                if not self._closed:
                    self._write_line(line)
        except Exception as error:  # not expected; still never the caller's problem
            self._report_unexpected(error)
        self._flush_reports()

    def close(self) -> None:
        """Close the file; later writes are ignored.  Closing twice is harmless."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            self._drop_descriptor()
            if self._failure is not None and self._lost:
                self._report_later(logging.WARNING, "%s: %d line(s) could not be written to the log file %s "
                                   "(%s)." % (NODE_NAME, self._lost, self._path, self._failure))
        self._flush_reports()

    def __enter__(self) -> "EventLog":
        return self

    def __exit__(self, *exc_info: Any) -> None:
        self.close()

    # -- formatting -------------------------------------------------------------------------------
    def _format(self, moment: float, event: str, fields: Dict[str, Any]) -> bytes:
        stamp = format_timestamp(moment)
        try:
            return format_log_line(stamp, event, fields).encode("utf-8")
        except ValueError as error:
            with self._lock:
                first = str(event) not in self._bad_events
                self._bad_events.add(str(event))
            if first:
                self._report_later(logging.ERROR, "%s: a %r line was not logged: %s" % (NODE_NAME, event, error))
            return format_log_line(stamp, ERROR, dict(
                where="event_log", message="a {!r} line was not logged: {}".format(event, error))).encode("utf-8")

    # -- writing (with the lock held) -------------------------------------------------------------
    def _write_line(self, line: bytes) -> None:
        if self._fd is None:
            if self._monotonic() < self._next_attempt:
                self._lost += 1
            else:
                self._retry(line)
            return
        try:
            if not self._is_current():
                self._follow_path()  # rotated by another process, or removed by someone
            self._rotate_if_full(len(line))
            self._write_all(line)
        except Exception as error:
            self._failed(error, line)
            return
        self._settled = True

    def _write_all(self, line: bytes) -> None:
        written = os.write(self._fd, line)
        while written < len(line):  # a short write: only on a nearly full disk or similar
            written += os.write(self._fd, line[written:])

    def _open_at_start(self) -> None:
        try:
            self._fd = self._opener(self._path)
        except Exception as error:
            self._failed(error, None)

    def _failed(self, error: BaseException, line: Optional[bytes]) -> None:
        """The file in use cannot be opened or written.  Before any line reached a file, the fallback
        is tried; otherwise `line` is dropped and the file tried again later.  Reported once."""
        self._drop_descriptor()
        if self._failure is not None:  # already reported: count and wait
            self._lost += int(line is not None)
            self._next_attempt = self._monotonic() + self._retry_period
            return
        reason = _reason(error)
        if self._settled or self._fallback is None or self._path == self._fallback:
            self._begin_failure("cannot write the log file %s (%s): lines are dropped, trying again every %g s"
                                % (self._path, reason, self._retry_period), reason, line)
            return
        failed_path, self._path = self._path, self._fallback
        try:
            self._fd = self._opener(self._path)
            if line is not None:
                self._write_all(line)
                self._settled = True
        except Exception as fallback_error:
            self._drop_descriptor()
            self._path = failed_path
            self._begin_failure("cannot write the log file %s (%s) nor %s (%s): running without a log file, "
                                "trying again every %g s" % (failed_path, reason, self._fallback,
                                                             _reason(fallback_error), self._retry_period),
                                reason, line)
            return
        self._report_later(logging.WARNING, "%s: cannot write the log file %s (%s): logging to %s instead."
                           % (NODE_NAME, failed_path, reason, self._path))

    def _begin_failure(self, text: str, reason: str, line: Optional[bytes]) -> None:
        self._failure = reason
        self._lost = int(line is not None)
        self._next_attempt = self._monotonic() + self._retry_period
        self._report_later(logging.ERROR, "%s: %s." % (NODE_NAME, text))

    def _retry(self, line: bytes) -> None:
        """After a failure: write `line` to the first file that takes it (the one in use once a line
        reached it; before that, the requested file, then the fallback), after an `error` line that
        counts the lines lost; else count `line` as lost too."""
        candidates = [self._path] if self._settled or self._fallback is None else [self._requested, self._fallback]
        note = b""
        if self._lost:
            note = format_log_line(format_timestamp(self._clock()), ERROR, dict(
                where="event_log", message="{} line(s) lost: {}".format(self._lost, self._failure))).encode("utf-8")
        for path in candidates:
            try:
                self._fd = self._opener(path)
                self._path = path
                self._rotate_if_full(len(note) + len(line))
                self._write_all(note + line)
            except Exception:
                self._drop_descriptor()
                continue
            self._settled = True
            self._report_later(logging.INFO, "%s: logging works again, to %s (%d line(s) lost)." % (
                NODE_NAME, self._path, self._lost))
            self._failure, self._lost = None, 0
            return
        self._lost += 1
        self._next_attempt = self._monotonic() + self._retry_period

    def _drop_descriptor(self) -> None:
        if self._fd is not None:
            try:
                os.close(self._fd)
            except OSError:
                pass
            self._fd = None

    def _is_current(self) -> bool:
        """Whether our descriptor is still the file that the path names (True when that cannot
        be told: the descriptor is then still the best place to write)."""
        assert self._fd is not None
        try:
            named = os.stat(self._path)
        except FileNotFoundError:
            return False
        except OSError:
            return True
        opened = os.fstat(self._fd)
        return (named.st_dev, named.st_ino) == (opened.st_dev, opened.st_ino)

    def _follow_path(self) -> None:
        """Open the file the path names now.  A path that no longer exists, and whose file is not the
        one rotated by another writer, was removed: say so, and make it again."""
        assert self._fd is not None
        if not os.path.exists(self._path):
            opened = os.fstat(self._fd)
            try:
                rotated = os.stat(self._path + ROTATED_SUFFIX)
                was_rotated = (rotated.st_dev, rotated.st_ino) == (opened.st_dev, opened.st_ino)
            except OSError:
                was_rotated = False
            if not was_rotated:
                self._report_later(logging.WARNING, "%s: the log file %s was removed; writing to a new one."
                                   % (NODE_NAME, self._path))
        self._drop_descriptor()
        self._fd = self._opener(self._path)

    def _rotate_if_full(self, line_length: int) -> None:
        """Rename the full file to <path>.1 and start a new one.  The flock makes a writer in
        another process that saw the same full file wait, then find it already rotated.  Only
        regular files rotate (never /dev/null or a pipe)."""
        assert self._fd is not None
        opened = os.fstat(self._fd)
        if not stat.S_ISREG(opened.st_mode) or opened.st_size == 0 \
                or opened.st_size + line_length <= self._max_bytes:
            return
        fcntl.flock(self._fd, fcntl.LOCK_EX)
        try:
            if self._is_current() and os.fstat(self._fd).st_size + line_length > self._max_bytes:
                os.replace(self._path, self._path + ROTATED_SUFFIX)
        finally:
            fcntl.flock(self._fd, fcntl.LOCK_UN)
        self._drop_descriptor()
        self._fd = self._opener(self._path)

    def _report_unexpected(self, error: BaseException) -> None:
        """Report an error that no part of writing expects (a bug, not a disk): the caller never sees it."""
        self._report_later(logging.ERROR, "%s: the log file %s: unexpected %s" % (
            NODE_NAME, self._path, _reason(error)))

    def _report_later(self, level: int, text: str) -> None:
        with self._reports_lock:
            self._reports.append((level, text))

    def _flush_reports(self) -> None:
        """Hand the collected reports over, outside the lock (a reporter may write to this log)."""
        if not self._reports:
            return
        with self._reports_lock:
            reports, self._reports = self._reports, []
        for level, text in reports:
            try:
                self._report(level, text)
            except Exception:  # a broken reporter must not break the caller either
                pass


class BackgroundLog:
    """An EventLog written by a thread of its own: `write` takes the time and queues the line, so a caller that
    commands a robot never waits for formatting or the disk. Lines keep their order; `close` writes what is
    queued (at most `close_timeout` seconds) and closes the file.

    The thread lets a burst of lines settle (`settle` seconds after the first) before it formats them: in one
    interpreter the formatting would otherwise take turns with the caller that is still sending goals (the
    five goals of an enable are sent within milliseconds, and their lines hold 100 points each)."""

    def __init__(self, log: EventLog, close_timeout: float = 1.0, settle: float = 0.05) -> None:
        self._log = log
        self._close_timeout = close_timeout
        self._settle = settle
        self._queue = queue.Queue()  # (time, event, fields), None to end
        self._thread = threading.Thread(target=self._run, name="event log", daemon=True)
        self._thread.start()

    @property
    def path(self) -> str:
        return self._log.path

    @property
    def writing(self) -> bool:
        return self._log.writing

    def write(self, event: str, **fields: Any) -> None:
        self._queue.put((time.time(), event, fields))

    def close(self) -> None:
        self._queue.put(None)
        self._thread.join(self._close_timeout)
        self._log.close()

    def _run(self) -> None:
        while True:
            item = self._queue.get()
            if item is not None and self._settle > 0:
                time.sleep(self._settle)
            while True:
                if item is None:
                    return
                self._log.write_at(*item)  # never raises
                try:
                    item = self._queue.get_nowait()
                except queue.Empty:
                    break


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


def node_log_file_name(node: str) -> str:
    """The default log file's name for the node whose resolved name is `node`: LOG_FILE_NAME for
    ``/animateBehaviour``, else the name with its slashes as underscores (``/robot1/animateBehaviour``:
    ``robot1_animateBehaviourLogFile.log``), so that two instances never share a file by default."""
    name = node.strip("/").replace("/", "_")
    return LOG_FILE_NAME if name in ("", NODE_NAME) else name + LOG_FILE_NAME[len(NODE_NAME):]


class LogFileClaim(NamedTuple):
    """The log file a node writes, held with a lock for as long as the node runs (`claim_log_file`)."""

    path: str
    clash: str  # "" or the one line saying that another running instance holds the file asked for


_claims: List[int] = []  # lock files held for the whole run: the kernel releases them when the process ends


def claim_log_file(requested: str, node: str) -> LogFileClaim:
    """`requested`, or, where another running instance already holds it, a file beside it named after `node` (the
    node's resolved name), so that the lines of two nodes never mix. The hold is a lock on ``<file>.lock``; where
    that cannot be made (a read-only folder), the file is used unclaimed and the event log's own fallback applies."""
    requested = os.path.abspath(requested)
    if _hold(requested):
        return LogFileClaim(requested, "")
    beside = os.path.join(os.path.dirname(requested), node_log_file_name(node))
    if beside == requested or not _hold(beside):
        beside = "{}.{}".format(beside, os.getpid())
    return LogFileClaim(beside, "{}: the log file {} is held by another running instance; this node ({}) writes "
                                "beside it, to {}".format(NODE_NAME, requested, node, beside))


def _hold(path: str) -> bool:
    """Whether this process now holds `path` (False only when another process does)."""
    try:
        fd = os.open(path + ".lock", os.O_WRONLY | os.O_CREAT, 0o644)
    except OSError:
        return True  # no lock can be made here: nothing to hold, nothing held by another
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        return False
    _claims.append(fd)
    return True


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
    return ros_home_log_path(ros_home, file_name)


def ros_home_log_path(ros_home: Optional[str], file_name: str = LOG_FILE_NAME) -> str:
    """``<ros_home>/<file_name>``, or ``~/.ros/<file_name>`` when ROS_HOME is not set: where the
    log goes when the package's data folder, or the file asked for, cannot be written."""
    home = ros_home if ros_home else os.path.join(os.path.expanduser("~"), ".ros")
    return os.path.join(home, file_name)


def _refuse_constant(name: str) -> Any:
    """json.loads hook: NaN and Infinity are not JSON and never written by EventLog."""
    raise ValueError("%s is not a JSON number" % name)


def _excerpt(text: str, limit: int = 120) -> str:
    """`text` for an error message: one line, at most `limit` characters."""
    shown = text if len(text) <= limit else text[:limit] + "..."
    return repr(shown)
