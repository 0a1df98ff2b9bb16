"""What the recorders of both ROS keep of a run, and how they turn it into a recording and its plot.

`RunRecorder` keeps samples and events as each recorder node (`recorder_node` on ROS 1,
``cssr_system.ros2.recorder_node`` on ROS 2) hands them over from its messages, with wall-clock times relative to
its start, and when stopped writes ``animation.json`` and ``animation.png`` (`save`), with the activations, bands
and setting changes of the node's log file and the node's modes from its status topic.

Pure Python and numpy (matplotlib for the plot): no ROS import.
"""
import functools
import math
import os
import threading
import time
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy

from cssr_system.animate_behaviour import console
from cssr_system.animate_behaviour.event_log import read_log
from cssr_system.core.foreign_motion import JOINT_ANGLES
from cssr_system.pepper.joint_table import PARTS, WHEEL_JOINTS
from cssr_system.recording.commanded import (CancelRequest, GoalResult, Measured, ReferenceSample, SentCall,
                                             SentGoal, call_marks, commanded_by, commanded_by_calls,
                                             commanded_by_reference, controller_pieces, goal_marks)
from cssr_system.recording.plot import plot_recording
from cssr_system.recording.recording import (PLOT_FILE_NAME, RECORDING_FILE_NAME,
                                             SETTING_MARK_WIDTH, BandChange, Commanded, Mark,
                                             Recording, RunSetting, activations_from_log,
                                             band_changes_from_log, bands_from_configuration_file,
                                             bands_from_log, goals_sent_from_log, setting_changes_from_log,
                                             unwrap_heading, write_recording, yaw_from_quaternion, yields_from_log)

NODE_NAME = "animateBehaviourRecorder"
DEFAULT_FOLDER = "animateBehaviourDemo"  # in $ROS_HOME
LOG_MARGIN = 1.0  # s: log entries this long before the recorder started still belong to the run


say = functools.partial(console.say, NODE_NAME)


def default_output_dir(namespace: str = "/") -> str:
    """``$ROS_HOME/animateBehaviourDemo`` (ROS_HOME defaults to ~/.ros on both ROS), and the recorder's namespace
    below it (``.../robot1``) where it is not the root: two robots' recordings never share a file."""
    ros_home = os.environ.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    return os.path.join(ros_home, DEFAULT_FOLDER, *filter(None, namespace.split("/")))


class RunRecorder:
    """Keeps what it is given with wall-clock times relative to its start (the `add_` methods run in the ROS
    client's threads; `recording` and `save` in the main thread at the end). `setting` may be set later, when the
    recorder learns the node's parameters."""

    def __init__(self, node: str, setting: Optional[RunSetting], heading_topic: str) -> None:
        self.node = node
        self.setting = setting
        self.heading_topic = heading_topic
        self.start_epoch = time.time()
        self._lock = threading.Lock()
        self.joint_names = ()  # type: Tuple[str, ...]
        self.times = []  # type: List[float]
        self.rows = []  # type: List[List[float]]
        self.heading_times = []  # type: List[float]
        self.headings = []  # type: List[float]
        self.goals = []  # type: List[SentGoal]
        self.cancels = []  # type: List[CancelRequest]
        self.results = []  # type: List[GoalResult]
        self.calls = []  # type: List[SentCall]
        self.references = []  # type: List[ReferenceSample]
        self.modes = []  # type: List[Tuple[float, str]]

    def now(self) -> float:
        """Seconds since the recorder started."""
        return time.time() - self.start_epoch

    def since_start(self, stamp: float) -> float:
        """A message's stamp (epoch seconds) on the recorder's clock: the simulated Pepper stamps with wall-clock
        time; a zero stamp means "now"."""
        return stamp - self.start_epoch if stamp > 0.0 else self.now()

    # -- what the recorder nodes hand over ------------------------------------------------------
    def add_joint_states(self, stamp: float, names: Sequence[str], positions: Sequence[float]) -> None:
        with self._lock:
            if not self.joint_names:
                self.joint_names = tuple(name for name in names if name not in WHEEL_JOINTS)
            value_of = dict(zip(names, positions))
            self.times.append(self.since_start(stamp))
            self.rows.append([float(value_of.get(name, math.nan)) for name in self.joint_names])

    def add_orientation(self, stamp: float, x: float, y: float, z: float, w: float) -> None:
        """The base's orientation (an odometry quaternion) at `stamp`: its heading, unwrapped."""
        yaw = yaw_from_quaternion(x, y, z, w)
        with self._lock:
            previous = self.headings[-1] if self.headings else None
            self.heading_times.append(self.since_start(stamp))
            self.headings.append(unwrap_heading(previous, yaw))

    def add_goal(self, goal: SentGoal) -> None:
        with self._lock:
            self.goals.append(goal)

    def add_cancel(self, cancel: CancelRequest) -> None:
        with self._lock:
            self.cancels.append(cancel)

    def add_result(self, result: GoalResult) -> None:
        with self._lock:
            self.results.append(result)

    def add_call(self, call: SentCall) -> None:
        with self._lock:
            self.calls.append(call)

    def add_reference(self, stamp: float, part: str, joint_names: Sequence[str], positions: Sequence[float]) -> None:
        """A controller's reference at its update stamped `stamp` (ROS 2's controller_state)."""
        with self._lock:
            self.references.append(ReferenceSample(self.since_start(stamp), part, tuple(joint_names),
                                                   tuple(positions)))

    def add_mode(self, mode: str) -> None:
        """The node's mode, from its status topic (published at every change): kept when it changes. Its time is
        the arrival's: the status of a node started before the recorder is no older than the recording."""
        with self._lock:
            if mode and (not self.modes or self.modes[-1][1] != mode):
                self.modes.append((self.now(), mode))

    def has_joint_states(self) -> bool:
        with self._lock:
            return bool(self.rows)

    # -- the recording ---------------------------------------------------------------------------
    def recording(self, log_entries: List[Any]) -> Recording:
        """What was recorded, time 0 moved to the first sample, with the activations and bands of
        `log_entries` (the node's log), what the node commanded and the marks of other nodes' goals."""
        with self._lock:
            times = numpy.array(self.times, dtype=float)
            order = numpy.argsort(times, kind="stable")
            times = times[order]
            positions = numpy.array(self.rows, dtype=float).reshape(-1, len(self.joint_names))[order]
            heading_times = numpy.array(self.heading_times, dtype=float)
            heading_order = numpy.argsort(heading_times, kind="stable")
            heading_times = heading_times[heading_order]
            headings = numpy.array(self.headings, dtype=float)[heading_order]
            goals, cancels, results = list(self.goals), list(self.cancels), list(self.results)
            calls, references, modes = list(self.calls), list(self.references), list(self.modes)
        first = min(times[0] if len(times) else 0.0, heading_times[0] if len(heading_times) else 0.0)
        since = self.start_epoch - LOG_MARGIN
        activations = tuple((epoch - self.start_epoch - first, state)
                            for epoch, state in activations_from_log(log_entries, since=since))
        bands, heading_bound = bands_from_log(log_entries, since=since)
        if not bands and self.setting is not None:
            try:
                bands, heading_bound = bands_from_configuration_file(
                    self.setting.config_file, {"platform": self.setting.platform, "behaviour": self.setting.behaviour})
            except ValueError as error:
                say("no bands in the plot: %s" % error)
        commanded = self._commanded(goals, cancels, calls, (self.joint_names, times, positions))
        if commanded is None and references:
            commanded = self._commanded_by_reference(references, times, log_entries, since)
        if commanded is not None:
            commanded = commanded._replace(times=commanded.times - first)
        end = float(times[-1]) if len(times) else 0.0
        marks = tuple(mark._replace(start=mark.start - first, end=mark.end - first)
                      for mark in goal_marks(goals, results, self.node, end) + call_marks(calls, self.node))
        if references:  # ROS 2: other nodes' goals are unseen; the node's log says when its parts yielded to them
            marks += self._yield_marks(log_entries, since, first, end - first)
        origin = self.start_epoch + first
        marks += tuple(Mark(epoch - origin, epoch - origin + SETTING_MARK_WIDTH, text)
                       for epoch, text in setting_changes_from_log(log_entries, since))
        band_changes = tuple(BandChange(epoch - origin, name, band.lower, band.upper)
                             for epoch, name, band in band_changes_from_log(log_entries, since))
        info = {}  # type: Dict[str, str]
        if self.setting is not None:
            info = {"platform": self.setting.platform, "behaviour": self.setting.behaviour,
                    "log_file": self.setting.log_file, "config_file": self.setting.config_file}
        return Recording(start_epoch=self.start_epoch + first, joint_names=self.joint_names, times=times - first,
                         positions=positions, heading_times=heading_times - first, headings=headings,
                         activations=activations, bands=bands, heading_bound=heading_bound, info=info,
                         heading_topic=self.heading_topic, commanded=commanded, marks=marks,
                         band_changes=band_changes, modes=tuple((moment - first, mode) for moment, mode in modes))

    def _commanded(self, goals, cancels, calls, measured: Measured) -> Optional[Commanded]:
        """What the node commanded: its setAngles calls (actuation joint_angles), else its goals as the
        controllers execute them."""
        times = measured[1]
        by_calls = commanded_by_calls(self.node, calls, times, measured)
        if by_calls is not None:
            return by_calls
        return commanded_by(self.node, controller_pieces(goals, cancels, measured), times)

    def _commanded_by_reference(self, references: List[ReferenceSample], times: numpy.ndarray,
                                log_entries: List[Any], since: float) -> Optional[Commanded]:
        """ROS 2, whose goals no recorder sees: the controllers' references while the node's goals ran, as its log
        tells (`commanded_by_reference`)."""
        goals_sent = [(epoch - self.start_epoch, part) for epoch, part in goals_sent_from_log(log_entries, since)]
        yielded = [(logged.start - self.start_epoch, logged.part) for logged in yields_from_log(log_entries, since)]
        return commanded_by_reference(self.node, references, times, goals_sent, yielded)

    def _yield_marks(self, log_entries: List[Any], since: float, first: float, end: float) -> Tuple[Mark, ...]:
        """A mark on the part's panel for each yield of the node's log to another node's goal or trajectory, to the
        part's resume (else `end`, on the recording's clock); other nodes' setAngles calls are marked from the
        calls themselves."""
        origin = self.start_epoch + first
        return tuple(Mark(logged.start - origin, end if logged.end is None else logged.end - origin,
                          "%s: %s" % (logged.caller, logged.kind), logged.part)
                     for logged in yields_from_log(log_entries, since)
                     if logged.part in PARTS and logged.kind != JOINT_ANGLES)

    def save(self, output_dir: str) -> int:
        """Write the recording and its plot into `output_dir`; 0 when written, 1 when not."""
        if not self.has_joint_states():
            say("nothing recorded (no /joint_states): no recording, no plot")
            return 1
        entries = []  # type: List[Any]
        if self.setting is not None and os.path.exists(self.setting.log_file):
            try:
                entries = read_log(self.setting.log_file)
            except (OSError, ValueError) as error:
                say("cannot read the node's log (%s): no enable/disable marks; bands from the configuration"
                    % error)
        try:
            recording = self.recording(entries)
            recording_path = write_recording(os.path.join(output_dir, RECORDING_FILE_NAME), recording)
            say("recording %s" % recording_path)
            if self.setting is not None:
                say("node log  %s" % self.setting.log_file)
            say("plot      %s" % plot_recording(recording, os.path.join(output_dir, PLOT_FILE_NAME)))
        except (OSError, ImportError) as error:  # ImportError: no matplotlib in this Python
            say("error: cannot write the recording or the plot: %s" % error)
            return 1
        return 0
