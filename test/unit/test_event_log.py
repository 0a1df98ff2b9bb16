"""Unit tests of the event log: format, round trip, rotation, concurrency, default path, faults."""
import datetime
import logging
import multiprocessing
import os
import re
import shutil
import threading
import time

import numpy
import pytest
from hypothesis import given, settings, strategies as st

from cssr_system.animate_behaviour import event_log
from cssr_system.animate_behaviour.contract import NODE_NAME
from cssr_system.animate_behaviour.event_log import (LOG_FILE_NAME, EventLog, LogEntry, default_log_path,
                                                     format_log_line, parse_log_line, read_log)

LINE_PATTERN = re.compile(
    r"\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}\.\d{3}[+-]\d{2}:\d{2} [a-z_]+ \{.*\}\n\Z")


def lines_of(path):
    with open(path, encoding="utf-8", newline="\n") as log_file:
        return log_file.readlines()


@pytest.fixture
def local_zone(monkeypatch):
    """Run with a known local time zone with a non-whole-hour offset (+05:30)."""
    monkeypatch.setenv("TZ", "Asia/Kolkata")
    time.tzset()
    yield
    monkeypatch.undo()
    time.tzset()


# --- format ------------------------------------------------------------------------------------

def test_line_format_and_round_trip(tmp_path, local_zone):
    moment = 1700000000.1239  # 2023-11-14T22:13:20.123 UTC
    log = EventLog(str(tmp_path / "a.log"), clock=lambda: moment)
    log.write("goal_sent", part="RArm", joints=("RShoulderPitch", "RElbowRoll"),
              positions=[[0.1, 0.2], [0.30000000000000004, -1.5]], count=3, done=False,
              note=None, nested={"bounds": (1.0, 2.0)})
    log.close()
    (line,) = lines_of(log.path)
    assert LINE_PATTERN.match(line), line
    assert line.startswith("2023-11-15T03:43:20.123+05:30 goal_sent {\"part\": \"RArm\", ")
    entry = parse_log_line(line)
    assert entry == LogEntry(
        datetime.datetime(2023, 11, 15, 3, 43, 20, 123000,
                          tzinfo=datetime.timezone(datetime.timedelta(hours=5, minutes=30))),
        "goal_sent",
        {"part": "RArm", "joints": ["RShoulderPitch", "RElbowRoll"],
         "positions": [[0.1, 0.2], [0.30000000000000004, -1.5]], "count": 3, "done": False,
         "note": None, "nested": {"bounds": [1.0, 2.0]}})
    assert entry.timestamp.timestamp() == pytest.approx(1700000000.123, abs=1e-9)


def test_numpy_and_sets_are_serialised_sensibly():
    line = format_log_line("2026-11-21T17:03:04.123+00:00", "values", dict(
        array=numpy.array([[1.5, 2.0], [3.25, -4.0]]),
        float32=numpy.float32(0.5),
        integer=numpy.int64(7),
        flag=numpy.bool_(True),
        joints=frozenset({"KneePitch", "HipRoll", "HipPitch"}),
        numbers={3, 1, 2},
        when=datetime.datetime(2026, 1, 2, 3, 4, 5),
    ))
    fields = parse_log_line(line).fields
    assert fields == {"array": [[1.5, 2.0], [3.25, -4.0]], "float32": 0.5, "integer": 7,
                      "flag": True, "joints": ["HipPitch", "HipRoll", "KneePitch"],
                      "numbers": [1, 2, 3], "when": "2026-01-02T03:04:05"}
    assert type(fields["integer"]) is int and type(fields["flag"]) is bool


@pytest.mark.parametrize("fields, named", [
    (dict(angle=float("nan")), "angle"),
    (dict(positions=[0.0, float("inf")]), "positions[1]"),
    (dict(array=numpy.array([0.0, numpy.nan])), "array[1]"),
    (dict(centre={"RArm": (1.0, numpy.float64("nan"))}), "centre.RArm[1]"),
])
def test_nan_and_infinity_are_refused_naming_the_field(fields, named):
    with pytest.raises(ValueError, match=re.escape(repr(named))):
        format_log_line("2026-11-21T17:03:04.123+00:00", "bad", fields)


@pytest.mark.parametrize("event", ["", "two words", "line\nbreak", 3])
def test_event_names_must_be_one_word(event):
    with pytest.raises(ValueError):
        format_log_line("2026-11-21T17:03:04.123+00:00", event, {})


json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-2 ** 62, 2 ** 62)
    | st.floats(allow_nan=False, allow_infinity=False) | st.text(),
    lambda children: st.lists(children, max_size=4)
    | st.dictionaries(st.text(max_size=8), children, max_size=4),
    max_leaves=12)


@settings(max_examples=50, deadline=None)
@given(event=st.from_regex(r"[a-z][a-z_]{0,20}", fullmatch=True),
       fields=st.dictionaries(st.from_regex(r"[a-zA-Z_]\w{0,10}", fullmatch=True), json_values,
                              max_size=6))
def test_any_fields_round_trip(event, fields):
    line = format_log_line("2026-11-21T17:03:04.123-03:00", event, fields)
    assert line.count("\n") == 1 and line.endswith("\n")  # one line whatever the strings hold
    entry = parse_log_line(line)
    assert entry.event == event and entry.fields == fields


@pytest.mark.parametrize("line", [
    "",
    "\n",
    "2026-11-21T17:03:04.123+00:00 event_only",
    "2026-11-21T17:03:04+00:00 no_milliseconds {}",
    "2026-11-21T17:03:04.123 no_offset {}",
    "2026-11-21 17:03:04.123+00:00 space_in_time {}",
    "2026-13-21T17:03:04.123+00:00 bad_month {}",
    "2026-11-21T17:03:04.123+00:00 not_json {\"a\": }",
    "2026-11-21T17:03:04.123+00:00 not_an_object [1, 2]",
    "2026-11-21T17:03:04.123+00:00 nan_field {\"a\": NaN}",
    "2026-11-21T17:03:04.123+00:00  {}",
])
def test_malformed_lines_raise_one_line_errors(line):
    with pytest.raises(ValueError) as error:
        parse_log_line(line)
    assert "\n" not in str(error.value) and "malformed log line" in str(error.value)


# --- files ---------------------------------------------------------------------------------------

def test_read_log_filters_by_time_and_names_bad_lines(tmp_path, local_zone):
    now = [1800000000.0]
    log = EventLog(str(tmp_path / "t.log"), clock=lambda: now[0])
    for index in range(5):
        log.write("tick", index=index)
        now[0] += 1.0
    log.close()
    entries = read_log(log.path)
    assert [entry.fields["index"] for entry in entries] == [0, 1, 2, 3, 4]
    since = entries[2].timestamp
    assert [entry.fields["index"] for entry in read_log(log.path, since=since)] == [2, 3, 4]
    naive_local = since.replace(tzinfo=None)  # a naive `since` is local time
    assert [entry.fields["index"] for entry in read_log(log.path, since=naive_local)] == [2, 3, 4]
    with open(log.path, "a") as log_file:
        log_file.write("garbage\n")
    with pytest.raises(ValueError, match=r"t\.log:6: malformed"):
        read_log(log.path)


def test_missing_folders_are_created_and_lines_append(tmp_path):
    path = tmp_path / "deep" / "er" / "x.log"
    with EventLog(str(path)) as log:
        log.write("first")
    with EventLog(str(path)) as log:  # a second run appends
        log.write("second", a=1)
    assert [entry.event for entry in read_log(str(path))] == ["first", "second"]
    assert read_log(str(path))[0].fields == {}


def test_write_after_close_is_ignored(tmp_path):
    log = EventLog(str(tmp_path / "c.log"))
    log.write("before")
    log.close()
    log.close()  # twice is harmless
    log.write("late")  # e.g. a thread still running while the node exits: never an exception
    assert [entry.event for entry in read_log(log.path)] == ["before"]


def test_rotation_keeps_one_previous_file_and_loses_nothing_since(tmp_path):
    path = str(tmp_path / "r.log")
    max_bytes = 1000
    log = EventLog(path, max_bytes=max_bytes)
    for index in range(300):
        log.write("line", index=index, padding="x" * (index % 17))
    log.close()
    assert sorted(os.listdir(str(tmp_path))) == ["r.log", "r.log.1"]
    assert os.path.getsize(path) <= max_bytes and os.path.getsize(path + ".1") <= max_bytes
    previous, current = read_log(path + ".1"), read_log(path)
    indices = [entry.fields["index"] for entry in previous + current]
    # The two files hold the newest lines, contiguous, ending with the last one written.
    assert indices == list(range(300 - len(indices), 300))
    assert len(previous) > 0 and len(current) > 0
    # The previous file was full: its next line would not have fitted.
    first_current_line = lines_of(path)[0].encode("utf-8")
    assert os.path.getsize(path + ".1") + len(first_current_line) > max_bytes


def test_a_line_longer_than_the_limit_still_goes_whole_into_a_new_file(tmp_path):
    path = str(tmp_path / "big.log")
    log = EventLog(path, max_bytes=100)
    log.write("small")
    log.write("big", text="y" * 500)
    log.write("after")
    log.close()
    assert [entry.event for entry in read_log(path + ".1")] == ["big"]
    assert [entry.event for entry in read_log(path)] == ["after"]


def test_a_writer_follows_a_rotation_done_by_another_writer(tmp_path):
    """Two EventLog objects on one path stand for two processes."""
    path = str(tmp_path / "shared.log")
    first, second = EventLog(path, max_bytes=600), EventLog(path, max_bytes=600)
    second.write("second_before")
    for index in range(20):  # enough to rotate
        first.write("first", index=index)
    assert os.path.exists(path + ".1")
    second.write("second_after")  # its descriptor still names the rotated file
    first.close()
    second.close()
    assert read_log(path)[-1].event == "second_after"
    assert "second_after" not in [entry.event for entry in read_log(path + ".1")]


def test_threads_never_interleave_lines(tmp_path):
    path = str(tmp_path / "threads.log")
    log = EventLog(path)
    threads_count, lines_count = 8, 200

    def writer(number):
        for index in range(lines_count):
            log.write("thread_line", thread=number, index=index, payload="z" * (index % 50))

    threads = [threading.Thread(target=writer, args=(number,)) for number in range(threads_count)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    log.close()
    entries = read_log(path)
    assert len(entries) == threads_count * lines_count
    for number in range(threads_count):
        assert [entry.fields["index"] for entry in entries
                if entry.fields["thread"] == number] == list(range(lines_count))


def test_threads_with_rotation_keep_a_contiguous_tail_per_thread(tmp_path):
    path = str(tmp_path / "rt.log")
    log = EventLog(path, max_bytes=4000)

    def writer(number):
        for index in range(200):
            log.write("thread_line", thread=number, index=index)

    threads = [threading.Thread(target=writer, args=(number,)) for number in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    log.close()
    assert sorted(os.listdir(str(tmp_path))) == ["rt.log", "rt.log.1"]
    entries = read_log(path + ".1") + read_log(path)
    for number in range(8):
        indices = [entry.fields["index"] for entry in entries if entry.fields["thread"] == number]
        assert indices == list(range(200 - len(indices), 200))


def _process_writer(path, number, lines_count, max_bytes, start):
    log = EventLog(path, max_bytes=max_bytes)
    start.wait(10)  # all writers begin together, so their lines really compete
    for index in range(lines_count):
        log.write("process_line", process=number, index=index, payload="p" * (index % 40))
    log.close()


def _run_processes(path, processes_count, lines_count, max_bytes):
    context = multiprocessing.get_context("fork")
    start = context.Event()
    processes = [context.Process(target=_process_writer,
                                 args=(path, number, lines_count, max_bytes, start))
                 for number in range(processes_count)]
    for process in processes:
        process.start()
    start.set()
    for process in processes:
        process.join(20)
        assert process.exitcode == 0


def test_processes_never_interleave_lines(tmp_path):
    path = str(tmp_path / "processes.log")
    _run_processes(path, 2, 500, event_log.DEFAULT_MAX_BYTES)
    entries = read_log(path)  # every line parses: nothing torn
    assert len(entries) == 2 * 500
    for number in range(2):
        assert [entry.fields["index"] for entry in entries
                if entry.fields["process"] == number] == list(range(500))


def test_processes_rotating_together_leave_whole_lines_in_two_files(tmp_path):
    path = str(tmp_path / "prot.log")
    _run_processes(path, 2, 500, 5000)
    assert sorted(os.listdir(str(tmp_path))) == ["prot.log", "prot.log.1"]
    entries = read_log(path + ".1") + read_log(path)
    keys = [(entry.fields["process"], entry.fields["index"]) for entry in entries]
    assert len(keys) == len(set(keys))  # no line written twice
    for number in range(2):  # each writer's lines keep their order across the two files
        indices = [index for process, index in keys if process == number]
        assert indices == sorted(indices)
    assert keys[-1][1] == 499  # the newest line is in the current file


# --- default path ----------------------------------------------------------------------------------

def test_default_path_is_the_package_data_folder(tmp_path):
    (tmp_path / "data").mkdir()
    assert default_log_path(str(tmp_path), "/ros/home") == str(tmp_path / "data" / LOG_FILE_NAME)


def test_default_path_when_the_data_folder_does_not_exist_yet(tmp_path):
    assert default_log_path(str(tmp_path), None) == str(tmp_path / "data" / LOG_FILE_NAME)


def test_default_path_falls_back_to_ros_home_when_data_is_not_writable(tmp_path, monkeypatch):
    data = tmp_path / "data"
    data.mkdir()
    real_access = os.access

    def access(path, mode):
        if os.path.abspath(path) == str(data) and mode & os.W_OK:
            return False
        return real_access(path, mode)

    monkeypatch.setattr(os, "access", access)
    assert default_log_path(str(tmp_path), "/ros/home") == os.path.join("/ros/home", LOG_FILE_NAME)
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    for no_ros_home in (None, ""):
        assert default_log_path(str(tmp_path), no_ros_home) == \
            str(tmp_path / "home" / ".ros" / LOG_FILE_NAME)


def test_default_path_falls_back_when_the_log_file_is_not_writable(tmp_path, monkeypatch):
    data = tmp_path / "data"
    data.mkdir()
    (data / LOG_FILE_NAME).write_text("")
    real_access = os.access
    monkeypatch.setattr(os, "access", lambda path, mode: False
                        if os.path.basename(str(path)) == LOG_FILE_NAME else real_access(path, mode))
    assert default_log_path(str(tmp_path), "/r") == os.path.join("/r", LOG_FILE_NAME)


@pytest.mark.skipif(os.geteuid() == 0, reason="root may write into a read-only folder")
def test_default_path_with_a_really_read_only_folder(tmp_path):
    data = tmp_path / "data"
    data.mkdir()
    data.chmod(0o555)
    try:
        assert default_log_path(str(tmp_path), "/r") == os.path.join("/r", LOG_FILE_NAME)
    finally:
        data.chmod(0o755)


# --- faults (README: "Faults"): the log never raises, reports once, retries, falls back -------------

class Reports:
    """An injected reporter: every (level, text) the log hands over."""

    def __init__(self):
        self.items = []

    def __call__(self, level, text):
        assert "\n" not in text, "one line per report"
        self.items.append((level, text))

    def at(self, level):
        return [text for item_level, text in self.items if item_level == level]


class FakeMonotonic:
    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


class SwitchableOpener:
    """Opens paths normally, except those in `failing`: an exception (`error`), or, in `readonly`,
    a descriptor that cannot be written (as a file system remounted read-only)."""

    def __init__(self):
        self.failing = {}
        self.readonly = set()
        self.calls = []

    def __call__(self, path):
        self.calls.append(path)
        if path in self.failing:
            raise self.failing[path]
        if path in self.readonly:
            return os.open("/dev/null", os.O_RDONLY)
        return event_log.open_for_append(path)


def events_in(path):
    return [entry.event for entry in read_log(path)]


def test_dev_full_at_start_up_falls_back_and_says_so_once(tmp_path):
    reports = Reports()
    fallback = str(tmp_path / "ros_home" / LOG_FILE_NAME)
    log = EventLog("/dev/full", fallback=fallback, report=reports)
    for index in range(20):
        log.write("line", index=index)
    log.close()
    assert log.path == fallback
    assert [entry.fields["index"] for entry in read_log(fallback)] == list(range(20))  # nothing lost
    (warning,) = reports.at(logging.WARNING)
    assert "/dev/full" in warning and fallback in warning and "No space left on device" in warning
    assert reports.at(logging.ERROR) == []


def test_a_directory_as_the_log_file_falls_back(tmp_path):
    reports = Reports()
    fallback = str(tmp_path / "fallback.log")
    log = EventLog(str(tmp_path), fallback=fallback, report=reports)
    log.write("first")
    log.close()
    assert log.path == fallback and events_in(fallback) == ["first"]
    (warning,) = reports.at(logging.WARNING)
    assert "Is a directory" in warning and str(tmp_path) in warning


def test_a_folder_that_cannot_be_made_falls_back(tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    reports = Reports()
    fallback = str(tmp_path / "fallback.log")
    log = EventLog(str(blocker / "sub" / "x.log"), fallback=fallback, report=reports)
    log.write("first")
    assert events_in(fallback) == ["first"]
    assert len(reports.items) == 1 and "Not a directory" in reports.items[0][1]


def test_the_default_fallback_is_ros_home(tmp_path, monkeypatch):
    monkeypatch.setenv("ROS_HOME", str(tmp_path / "rh"))
    log = EventLog(str(tmp_path), report=Reports())
    log.write("first")
    log.close()
    assert log.path == str(tmp_path / "rh" / LOG_FILE_NAME)
    assert events_in(log.path) == ["first"]


def test_nothing_writable_runs_without_a_file_says_so_once_and_never_raises(tmp_path):
    reports = Reports()
    monotonic = FakeMonotonic()
    log = EventLog("/dev/full", fallback="/dev/full/not_a_folder/x.log", report=reports,
                   retry_period=2.0, monotonic=monotonic)
    for index in range(50):
        log.write("line", index=index)
        monotonic.now += 0.5  # several retries of both files happen meanwhile
    assert not log.writing
    (error,) = reports.at(logging.ERROR)
    assert "running without a log file" in error and "/dev/full/not_a_folder/x.log" in error
    assert "trying again every 2 s" in error
    log.close()
    (summary,) = reports.at(logging.WARNING)
    assert "50 line(s) could not be written" in summary


def test_a_failing_file_is_retried_only_every_retry_period_and_recovers(tmp_path):
    path = str(tmp_path / "logs" / "r.log")
    opener, reports, monotonic = SwitchableOpener(), Reports(), FakeMonotonic()
    log = EventLog(path, fallback=None, report=reports, retry_period=5.0, monotonic=monotonic,
                   opener=opener)
    log.write("before")
    opener.failing[path] = PermissionError(13, "Permission denied", path)
    os.unlink(path)  # the next line must open the file again, which now fails
    log.write("lost_1")
    calls = len(opener.calls)
    for _ in range(10):
        monotonic.now += 0.4
        log.write("lost_more")
    assert len(opener.calls) == calls, "no attempt before the retry period has passed"
    monotonic.now += 1.0
    log.write("lost_again")  # 5.0 s after the failure: one attempt, which fails
    assert len(opener.calls) == calls + 1
    del opener.failing[path]
    log.write("lost_until_next_attempt")
    monotonic.now += 5.0
    log.write("after")
    log.close()
    (error,) = reports.at(logging.ERROR)
    assert path in error and "Permission denied" in error
    (recovered,) = reports.at(logging.INFO)
    assert "works again" in recovered and "13 line(s) lost" in recovered
    entries = read_log(path)
    assert [entry.event for entry in entries] == ["error", "after"]  # a new file: the old was removed
    assert entries[0].fields == {"where": "event_log", "message": "13 line(s) lost: Permission denied"}


def test_a_disk_that_fills_while_running_drops_lines_then_recovers(tmp_path):
    """A file system that stops taking writes (full, or remounted read-only) under an open file."""
    path = str(tmp_path / "d.log")
    opener, reports, monotonic = SwitchableOpener(), Reports(), FakeMonotonic()
    log = EventLog(path, fallback=str(tmp_path / "never.log"), report=reports, retry_period=1.0,
                   monotonic=monotonic, opener=opener)
    log.write("before")
    opener.readonly.add(path)
    os.unlink(path)  # reopened read-only: every write fails (EBADF)
    for _ in range(5):
        log.write("dropped")
        monotonic.now += 1.0
    assert not log.writing
    opener.readonly.clear()
    log.write("after")
    assert log.writing
    log.close()
    assert len(reports.at(logging.ERROR)) == 1 and len(reports.at(logging.INFO)) == 1
    assert not os.path.exists(str(tmp_path / "never.log")), "no fallback once a line reached the file"
    assert events_in(path) == ["error", "after"]


def test_a_removed_file_or_folder_is_made_again_with_one_report(tmp_path):
    folder = tmp_path / "logs"
    path = str(folder / "x.log")
    reports = Reports()
    log = EventLog(path, report=reports)
    log.write("one")
    os.unlink(path)
    log.write("two")
    log.write("three")
    shutil.rmtree(str(folder))
    log.write("four")
    log.close()
    assert events_in(path) == ["four"]
    warnings = reports.at(logging.WARNING)
    assert len(warnings) == 2 and all("was removed" in text for text in warnings)
    assert reports.at(logging.ERROR) == []


def test_rotation_still_works_after_a_failure(tmp_path):
    path = str(tmp_path / "rot.log")
    opener, monotonic = SwitchableOpener(), FakeMonotonic()
    log = EventLog(path, max_bytes=600, fallback=None, report=Reports(), retry_period=1.0,
                   monotonic=monotonic, opener=opener)
    log.write("before")
    opener.failing[path] = OSError(28, "No space left on device")
    os.unlink(path)
    log.write("dropped")
    del opener.failing[path]
    monotonic.now += 1.0
    for index in range(40):
        log.write("line", index=index)
    log.close()
    assert os.path.getsize(path) <= 600 and os.path.getsize(path + ".1") <= 600
    indices = [entry.fields["index"] for entry in read_log(path + ".1") + read_log(path)
               if entry.event == "line"]
    assert indices == list(range(40 - len(indices), 40))


def test_unwritable_fields_become_an_error_line_reported_once_per_event(tmp_path):
    reports = Reports()
    log = EventLog(str(tmp_path / "f.log"), report=reports)
    log.write("angle", value=float("nan"))
    log.write("angle", value=float("inf"))
    log.write("two words")
    log.write("fine", value=1.0)
    log.close()
    entries = read_log(log.path)
    assert [entry.event for entry in entries] == ["error", "error", "error", "fine"]
    assert "'angle'" in entries[0].fields["message"] and "nan" in entries[0].fields["message"]
    assert len(reports.at(logging.ERROR)) == 2  # one for 'angle', one for 'two words'


def test_a_broken_reporter_or_clock_never_reaches_the_caller(tmp_path):
    def broken_reporter(level, text):
        raise RuntimeError("reporter down")

    log = EventLog("/dev/full", fallback=None, report=broken_reporter)
    log.write("line")  # the failure report raises inside: swallowed

    def broken_clock():
        raise OSError("clock down")

    reports = Reports()
    log = EventLog(str(tmp_path / "c.log"), clock=broken_clock, report=reports)
    log.write("line")
    assert "clock down" in reports.at(logging.ERROR)[0]


def test_the_default_reporter_is_the_console_logger(caplog):
    with caplog.at_level(logging.INFO, logger=NODE_NAME):
        EventLog("/dev/full", fallback=None).write("line")
    (record,) = caplog.records
    assert record.name == NODE_NAME and record.levelno == logging.ERROR and "/dev/full" in record.getMessage()


def test_threads_writing_to_a_failing_file_never_raise_and_report_once(tmp_path):
    reports = Reports()
    log = EventLog("/dev/full", fallback=None, report=reports, retry_period=0.0)  # retry at every line
    failures = []

    def writer():
        try:
            for index in range(200):
                log.write("line", index=index)
        except Exception as error:  # pragma: no cover - the failure this test looks for
            failures.append(error)

    threads = [threading.Thread(target=writer) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    log.close()
    assert failures == []
    assert len(reports.at(logging.ERROR)) == 1


def test_a_background_log_keeps_the_order_and_the_times_of_its_lines(tmp_path):
    from cssr_system.animate_behaviour.event_log import BackgroundLog
    path = str(tmp_path / "background.log")
    log = BackgroundLog(EventLog(path))
    for number in range(200):
        log.write("numbered", number=number)
    log.close()
    entries = read_log(path)
    assert [entry.fields["number"] for entry in entries] == list(range(200))
    assert all(earlier.timestamp <= later.timestamp for earlier, later in zip(entries, entries[1:]))
    log.write("after", number=-1)  # ignored after close, never raises


# -- several instances (README: "Several robots") --------------------------------------------------------------
@pytest.mark.parametrize("node,name", [
    ("/animateBehaviour", "animateBehaviourLogFile.log"),
    ("/robot1/animateBehaviour", "robot1_animateBehaviourLogFile.log"),
    ("/animate_left", "animate_leftLogFile.log"),
    ("/lab/robot2/animate_left", "lab_robot2_animate_leftLogFile.log")])
def test_the_default_log_file_is_named_after_the_nodes_resolved_name(node, name):
    assert event_log.node_log_file_name(node) == name


def test_a_log_file_held_by_another_instance_is_not_shared(tmp_path):
    asked = str(tmp_path / "animateBehaviourLogFile.log")
    first = event_log.claim_log_file(asked, "/robot1/animateBehaviour")
    assert first == (asked, "")
    second = event_log.claim_log_file(asked, "/robot2/animateBehaviour")
    assert second.path == str(tmp_path / "robot2_animateBehaviourLogFile.log")
    assert "held by another running instance" in second.clash and second.path in second.clash
    assert "/robot2/animateBehaviour" in second.clash and "\n" not in second.clash
    third = event_log.claim_log_file(asked, "/robot2/animateBehaviour")  # the same name twice: its own file still
    assert third.path not in (first.path, second.path) and third.path.startswith(second.path)


def test_a_log_file_in_a_folder_without_write_access_is_used_unclaimed(tmp_path):
    asked = str(tmp_path / "missing" / "animateBehaviourLogFile.log")
    assert event_log.claim_log_file(asked, "/animateBehaviour") == (asked, "")
