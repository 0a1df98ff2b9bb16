"""A soak run (doc/soak.md): the churn schedule played on a front-end's driver, the node's process sampled every 10 s
from /proc, its log read as it grows, its output searched for tracebacks, and every goal's end set beside the one
expected. The driver (cssr_system.ros1.soak_driver, cssr_system.ros2.soak_driver) does the ROS I/O:

  driver.node_pid() -> int; driver.log_file, driver.output_file and driver.heap_file (paths; the last written by
      the soak's probe in the node, tools/soak_probe, and read at each sample)
  driver.activate(state) -> bool (the reply was a success); driver.set_setting(name, value) -> bool
  driver.send_animate(goal, detail), driver.cancel_animate(goal), driver.play_gesture(goal): they return at once;
      each goal's end comes back through the `ended(goal, status, reason)` the run gives to driver.attach; the
      gesture leaves at once, whatever the node's goals do
  driver.restart_controllers(): the simulated Pepper stopped and started again (the run calls it on a thread)
  driver.base_listener(present): the base's listener (a subscriber of the base's topic) leaves or comes back

Pure Python: no ROS.
"""
import json
import os
import threading
import time
from typing import Callable, Dict, List, Optional

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.event_log import parse_log_line
from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.core.goals import ABORTED, LOST, REJECTED
from cssr_system.demo.gesture import GESTURE_PART
from cssr_system.soak.process_figures import cpu_seconds, log_bytes, process_figures, resident_kinds
from cssr_system.soak.schedule import (ANIMATE, CANCEL, DISABLE, ENABLE, GESTURE, LISTENER, RESTART, SETTING, Step)

SAMPLE_PERIOD = 10.0  # s between samples of the node's process
PROVOKED_AFTER_RESTART = 15.0  # s after a restart in which a goal's rejection, abort or loss is the restart's doing
SETTLE = 15.0  # s the run waits at its end for goals still under way
# s around another node's gesture falling due in which the end of the node's goal on that part is the gesture's
# doing: on ROS 2 joint_trajectory_controller aborts the goal a newer one replaces.
GESTURE_WINDOW = (-0.5, 2.0)
HEAP_KEYS = ("malloc in use", "malloc free", "python blocks")  # MB, MB, a count (tools/soak_probe)


class LogTail:
    """The node's log read as it grows: every complete line once, across a rotation (the rest of the rotated file
    first)."""

    def __init__(self, path: str) -> None:
        self.path = path
        self._offset = 0
        self._inode = None

    def new_entries(self) -> list:
        try:
            status = os.stat(self.path)
        except OSError:
            return []
        lines = []
        if self._inode is not None and status.st_ino != self._inode:  # rotated: finish the old file first
            lines += self._read(self.path + ".1")
            self._offset = 0
        self._inode = status.st_ino
        lines += self._read(self.path)
        entries = []
        for line in lines:
            try:
                entries.append(parse_log_line(line))
            except ValueError:
                continue  # a line the node could not finish (a full disk): not this run's business
        return entries

    def _read(self, path: str) -> List[str]:
        try:
            with open(path, "rb") as stream:
                stream.seek(self._offset)
                data = stream.read()
        except OSError:
            return []
        complete = data[:data.rfind(b"\n") + 1]
        self._offset += len(complete)
        return complete.decode("utf-8", errors="replace").splitlines()


def read_heap(path: str) -> dict:
    """What the node's allocators hold, as the soak's probe last wrote it (HEAP_KEYS; None where not known)."""
    try:
        with open(path) as stream:
            figures = json.load(stream)
    except (OSError, ValueError):
        figures = {}
    return {key: figures.get(key) for key in HEAP_KEYS}


def count_tracebacks(path: str) -> int:
    try:
        with open(path, encoding="utf-8", errors="replace") as stream:
            return sum(line.startswith("Traceback") for line in stream)
    except OSError:
        return 0


class SoakRun:
    """`schedule` (schedule.churn_schedule) played on `driver` for `seconds`, of which the first `warm_up` are not
    judged; `progress(text)` hears a line per sample, `checkpoint(result so far)` one every 6 samples."""

    def __init__(self, driver, schedule: List[Step], seconds: float, warm_up: float,
                 progress: Callable[[str], None] = print, sample_period: float = SAMPLE_PERIOD,
                 checkpoint: Optional[Callable[[dict], None]] = None) -> None:
        self.driver, self.schedule, self.seconds, self.warm_up = driver, schedule, seconds, warm_up
        self.progress, self.sample_period = progress, sample_period
        self.checkpoint = checkpoint  # hears the result so far once a minute: a run cut short still tells
        self.samples: List[dict] = []
        self.marks: List[list] = []  # [s from the start, action, detail]
        self.replies: List[list] = []  # [s from the start, what, seconds, success]
        self.goals: Dict[str, dict] = {}  # by name: expect, sent, status, reason, ended
        self.node_goals: List[list] = []  # [s from the start, part, state, provoked]: the node's goals gone wrong
        self.errors = 0
        self.base_seen = {contract.CONTROLLER_LOST: 0, contract.CONTROLLER_CONNECTED: 0}  # the node's log, of Wheels
        self._restarts: List[list] = []  # [start, end or None]
        self._gestures: List[float] = []  # when each gesture was sent
        self._lock = threading.Lock()
        self._start = 0.0
        self._wall_start = 0.0
        self._cpu: Optional[tuple] = None
        self._tail = LogTail(driver.log_file)
        self._restart_thread: Optional[threading.Thread] = None
        driver.attach(self.ended)

    def elapsed(self) -> float:
        return time.monotonic() - self._start

    def ended(self, goal: str, status: str, reason: str) -> None:
        with self._lock:
            record = self.goals.setdefault(goal, {"expect": None, "sent": None})
            record.update(status=status, reason=reason, ended=self.elapsed())

    def run(self) -> dict:
        self._start, self._wall_start = time.monotonic(), time.time()
        steps = list(self.schedule)
        next_sample = 0.0
        while self.elapsed() < self.seconds:
            due = min([next_sample] + [step.at for step in steps[:1]])
            time.sleep(max(0.0, due - self.elapsed()))
            if self.elapsed() >= next_sample:
                self.sample()
                next_sample += self.sample_period
                if self.checkpoint is not None and len(self.samples) % 6 == 0:
                    self.checkpoint(self.result())
            while steps and steps[0].at <= self.elapsed() and self.elapsed() < self.seconds:
                self.perform(steps.pop(0))
        self._settle()
        if self.elapsed() - self.samples[-1]["t"] >= self.sample_period / 2.0:
            self.sample()
        return self.result()

    def _settle(self) -> None:
        """Waits for the restart under way and the goals still under way (at most SETTLE s)."""
        if self._restart_thread is not None:
            self._restart_thread.join()
        deadline = time.monotonic() + SETTLE
        while time.monotonic() < deadline and any("status" not in goal for goal in self._goal_copy().values()):
            time.sleep(0.2)

    def _goal_copy(self) -> Dict[str, dict]:
        with self._lock:
            return {name: dict(goal) for name, goal in self.goals.items()}

    def perform(self, step: Step) -> None:
        at = self.elapsed()
        self.marks.append([at, step.action, step.detail])
        if step.action in (ENABLE, DISABLE):
            self._timed(step.action, lambda: self.driver.activate(
                contract.ENABLED if step.action == ENABLE else contract.DISABLED))
        elif step.action == SETTING:
            self._timed("setting", lambda: self.driver.set_setting(step.detail["name"], step.detail["value"]))
        elif step.action in (ANIMATE, GESTURE):
            with self._lock:
                self.goals.setdefault(step.detail["goal"], {}).update(
                    expect=step.detail.get("expect", "SUCCEEDED"), sent=at)
            if step.action == ANIMATE:
                self.driver.send_animate(step.detail["goal"], step.detail)
            else:
                self._gestures.append(at)
                self.driver.play_gesture(step.detail["goal"])
        elif step.action == CANCEL:
            self.driver.cancel_animate(step.detail["goal"])
        elif step.action == RESTART:
            self._restart()
        elif step.action == LISTENER:
            self.driver.base_listener(step.detail["present"])

    def _timed(self, what: str, call: Callable[[], bool]) -> None:
        sent = time.monotonic()
        try:
            success = bool(call())
        except Exception as error:  # noqa: BLE001 - a failed call is a figure of the run, said in one line
            self.progress("soak: %s failed: %s" % (what, error))
            success = False
        self.replies.append([sent - self._start, what, time.monotonic() - sent, success])

    def _restart(self) -> None:
        if self._restart_thread is not None:
            self._restart_thread.join()
        record = [self.elapsed(), None]
        self._restarts.append(record)

        def restart() -> None:
            self.driver.restart_controllers()
            record[1] = self.elapsed()
        self._restart_thread = threading.Thread(target=restart, name="restart", daemon=True)
        self._restart_thread.start()

    def provoked(self, at: float, part: str) -> bool:
        """Whether the goal of `part` that went wrong at `at` is the churn's doing: a restart's (a controller shutting
        down aborts its goal and rejects the next; one gone leaves its goals without a result) or a gesture's."""
        return any(start - 1.0 <= at <= (end if end is not None else at) + PROVOKED_AFTER_RESTART
                   for start, end in self._restarts) or (part == GESTURE_PART and any(
                       sent + GESTURE_WINDOW[0] <= at <= sent + GESTURE_WINDOW[1] for sent in self._gestures))

    def sample(self) -> None:
        pid = self.driver.node_pid()
        figures = process_figures(pid)
        now, used = time.monotonic(), cpu_seconds(pid)
        cpu = None if self._cpu is None else 100.0 * (used - self._cpu[1]) / max(1e-6, now - self._cpu[0])
        self._cpu = (now, used)
        self._read_log()
        sample = {"t": now - self._start, "resident memory": figures["resident memory"],
                  "threads": figures["threads"], "open files": figures["open files"], "cpu": cpu,
                  "log bytes": log_bytes(self.driver.log_file)}
        sample.update(resident_kinds(pid))
        sample.update(read_heap(self.driver.heap_file))
        self.samples.append(sample)
        self.progress("soak %6.0f s: RSS %.1f MB, %d threads, %d open files, CPU %s, log %.1f MB" % (
            sample["t"], sample["resident memory"], sample["threads"], sample["open files"],
            "-" if cpu is None else "%.1f %%" % cpu, sample["log bytes"] / 1e6))

    def _read_log(self) -> None:
        for entry in self._tail.new_entries():
            if entry.event == contract.ERROR:
                self.errors += 1
            elif entry.event in self.base_seen and entry.fields.get("part") == WHEELS_KEY and self._listener_left(
                    entry.timestamp.timestamp() - self._wall_start):
                self.base_seen[entry.event] += 1
            elif entry.event == contract.GOAL_FINISHED and entry.fields.get("state") in (ABORTED, REJECTED, LOST):
                at = entry.timestamp.timestamp() - self._wall_start
                part = entry.fields.get("part")
                self.node_goals.append([at, part, entry.fields["state"], self.provoked(at, part)])

    def _listener_left(self, at: float) -> bool:
        """Whether the base's listener had left on its own by `at` (s from the start): the node's first connection
        to the base is not a return."""
        return any(mark[0] <= at + 1.0 and mark[1] == LISTENER for mark in self.marks)

    def result(self) -> dict:
        return {"seconds": self.seconds, "warm up": self.warm_up, "sample period": self.sample_period,
                "samples": self.samples, "marks": self.marks, "replies": self.replies, "goals": self._goal_copy(),
                "node goals gone wrong": self.node_goals, "restarts": self._restarts, "log errors": self.errors,
                "base listener seen": {"left": self.base_seen[contract.CONTROLLER_LOST],
                                       "back": self.base_seen[contract.CONTROLLER_CONNECTED]},
                "tracebacks": count_tracebacks(self.driver.output_file),
                "started": time.strftime("%Y-%m-%dT%H:%M:%S%z", time.localtime(self._wall_start))}


def write_json(path: str, document: dict) -> None:
    with open(path, "w") as stream:
        json.dump(document, stream, indent=1)
