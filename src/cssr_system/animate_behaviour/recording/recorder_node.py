"""animateBehaviourRecorder: records a run of animateBehaviour and, when stopped, writes it and its plot.

rosrun cssr_system animateBehaviourRecorder.py [_output_dir:=DIR] [_node:=/animateBehaviour]

From its start until it is stopped (Ctrl-C, or roslaunch ending the launch) it records /joint_states,
the base heading (odometry of the simulated Pepper's platform, ``<namespace>/odom``), the goals,
cancels and results on every part's FollowJointTrajectory action (the namespaces of the node's topic
file) and the setAngles calls on its JointAngles topic. When stopped, it reads the node's log file
for the enable and disable instants and the joints' bands, and writes into ``~output_dir``:

  animation.json   the recording (format: `cssr_system.animate_behaviour.recording.recording`), with
                   ``commanded`` (what the node commanded: its goals replayed as the controller
                   executes them, or its setAngles calls as naoqi_driver executes them, `commanded`)
                   and ``marks`` (every other node's goal on a part, from its receipt to its result,
                   and its bursts of setAngles calls)
  animation.png    its plot (`plot`)

and prints both paths. Nothing recorded (no /joint_states): nothing written.

Parameters: ``~output_dir`` (default ``$ROS_HOME/animateBehaviourDemo``); ``~node`` (the node
recorded, default ``/animateBehaviour``: its parameters give its configuration file, platform,
topics and log file, as the node itself resolves them).
"""
import functools
import math
import os
import threading
import time
from typing import Any, Dict, List, Optional, Tuple

import numpy
import rospy
from actionlib_msgs.msg import GoalID
from control_msgs.msg import FollowJointTrajectoryActionGoal, FollowJointTrajectoryActionResult
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.demo import console
from cssr_system.animate_behaviour.event_log import read_log
from cssr_system.animate_behaviour.recording.commanded import (CancelRequest, GoalResult, Measured, SentCall,
                                                               SentGoal, call_marks, commanded_by, commanded_by_calls,
                                                               controller_pieces, goal_marks)
from cssr_system.animate_behaviour.recording.plot import plot_recording
from cssr_system.animate_behaviour.recording.recording import (PLOT_FILE_NAME, RECORDING_FILE_NAME,
                                                               SETTING_MARK_WIDTH, BandChange, Commanded, Mark,
                                                               Recording, RunSetting, activations_from_log,
                                                               band_changes_from_log, bands_from_configuration_file,
                                                               bands_from_log, run_setting, setting_changes_from_log,
                                                               unwrap_heading, write_recording, yaw_from_quaternion)
from cssr_system.animate_behaviour.node.trajectory_client import goal_state_name
from cssr_system.animate_behaviour.rospy_compat import caller_of
from cssr_system.animate_behaviour.topics import joint_angles_topic
from cssr_system.pepper.joint_table import PARTS, WHEEL_JOINTS
from cssr_system.pepper.simulated_pepper import PLATFORMS, odometry_topic
from cssr_system.pepper.trajectory_interpolation import TrajectoryPoint

NODE_NAME = "animateBehaviourRecorder"
DEFAULT_FOLDER = "animateBehaviourDemo"  # in $ROS_HOME
LOG_MARGIN = 1.0  # s: log entries this long before the recorder started still belong to the run


say = functools.partial(console.say, NODE_NAME)


def goal_id_caller(goal_id: str) -> str:
    """The node that sent a goal, from its id alone: actionlib's ids are "<node>-<count>-<stamp>"."""
    return goal_id.rsplit("-", 2)[0]


class RunRecorder:
    """Keeps what it receives with wall-clock times relative to its start (callbacks run in rospy's
    threads; `recording` in the main thread at the end)."""

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

    def _now(self) -> float:
        return time.time() - self.start_epoch

    def _stamp(self, header_stamp: Any) -> float:
        # The simulated Pepper stamps with wall-clock time; a zero stamp means "now".
        stamp = header_stamp.to_sec()
        return stamp - self.start_epoch if stamp > 0.0 else self._now()

    # -- callbacks ------------------------------------------------------------------------------
    def on_joint_states(self, message: JointState) -> None:
        with self._lock:
            if not self.joint_names:
                self.joint_names = tuple(name for name in message.name if name not in WHEEL_JOINTS)
            value_of = dict(zip(message.name, message.position))
            self.times.append(self._stamp(message.header.stamp))
            self.rows.append([float(value_of.get(name, math.nan)) for name in self.joint_names])

    def on_odometry(self, message: Odometry) -> None:
        orientation = message.pose.pose.orientation
        yaw = yaw_from_quaternion(orientation.x, orientation.y, orientation.z, orientation.w)
        with self._lock:
            previous = self.headings[-1] if self.headings else None
            self.heading_times.append(self._stamp(message.header.stamp))
            self.headings.append(unwrap_heading(previous, yaw))

    def on_goal(self, message: FollowJointTrajectoryActionGoal, part: str) -> None:
        trajectory = message.goal.trajectory
        points = tuple(TrajectoryPoint(point.time_from_start.to_sec(), tuple(point.positions),
                                       tuple(point.velocities), tuple(point.accelerations))
                       for point in trajectory.points)
        # Its publisher, else (a message whose connection header names none) its goal id's prefix.
        sender = caller_of(message) or goal_id_caller(message.goal_id.id)
        goal = SentGoal(self._now(), part, sender, message.goal_id.id, tuple(trajectory.joint_names), points)
        with self._lock:
            self.goals.append(goal)

    def on_cancel(self, message: GoalID, part: str) -> None:
        stamp = message.stamp.to_sec()
        with self._lock:
            self.cancels.append(CancelRequest(self._now(), part, message.id,
                                              stamp - self.start_epoch if stamp > 0.0 else 0.0))

    def on_result(self, message: FollowJointTrajectoryActionResult, part: str) -> None:
        status = message.status
        with self._lock:
            self.results.append(GoalResult(self._now(), part, status.goal_id.id,
                                           goal_state_name(status.status)))

    def on_joint_angles(self, message: JointAnglesWithSpeed) -> None:
        call = SentCall(self._now(), caller_of(message), tuple(message.joint_names), tuple(message.joint_angles),
                        message.speed, message.relative)
        with self._lock:
            self.calls.append(call)

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
            calls = list(self.calls)
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
        if commanded is not None:
            commanded = commanded._replace(times=commanded.times - first)
        end = float(times[-1]) if len(times) else 0.0
        marks = tuple(mark._replace(start=mark.start - first, end=mark.end - first)
                      for mark in goal_marks(goals, results, self.node, end) + call_marks(calls, self.node))
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
                         band_changes=band_changes)

    def _commanded(self, goals, cancels, calls, measured: Measured) -> Optional[Commanded]:
        """What the node commanded: its setAngles calls (actuation joint_angles), else its goals as the
        controllers execute them."""
        times = measured[1]
        by_calls = commanded_by_calls(self.node, calls, times, measured)
        if by_calls is not None:
            return by_calls
        return commanded_by(self.node, controller_pieces(goals, cancels, measured), times)

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
        except OSError as error:
            say("error: cannot write the recording or the plot: %s" % error)
            return 1
        return 0


def node_parameters(node: str) -> Dict[str, Any]:
    """The private parameters of `node` (names without its namespace); none when it has none."""
    try:
        values = rospy.get_param(node)
    except KeyError:
        return {}
    return values if isinstance(values, dict) else {}


def main() -> int:
    rospy.init_node(NODE_NAME)
    ros_home = os.environ.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    output_dir = os.path.abspath(rospy.get_param("~output_dir", os.path.join(ros_home, DEFAULT_FOLDER)))
    node = rospy.get_param("~node", "/" + contract.NODE_NAME)
    parameters = node_parameters(node)
    try:
        setting = run_setting(parameters, os.environ.get("ROS_HOME"))  # type: Optional[RunSetting]
        platform = setting.platform
        topics = setting.topics
    except ValueError as error:
        say("the configuration of %s cannot be read (%s): recording without its goals and log" % (node, error))
        setting, platform, topics = None, str(parameters.get("platform", "robot")), {}
    heading_topic = odometry_topic(PLATFORMS[platform if platform in PLATFORMS else "robot"])
    recorder = RunRecorder(node, setting, heading_topic)
    rospy.Subscriber("/joint_states", JointState, recorder.on_joint_states, queue_size=100)
    rospy.Subscriber(heading_topic, Odometry, recorder.on_odometry, queue_size=100)
    actions = [(key, topics[key]) for key in PARTS if key in topics]
    for key, action in actions:
        rospy.Subscriber(action + "/goal", FollowJointTrajectoryActionGoal, recorder.on_goal, key, queue_size=20)
        rospy.Subscriber(action + "/cancel", GoalID, recorder.on_cancel, key, queue_size=20)
        rospy.Subscriber(action + "/result", FollowJointTrajectoryActionResult, recorder.on_result, key,
                         queue_size=20)
    # With actuation joint_angles the node's commands are setAngles calls; other nodes' calls are marked either way.
    rospy.Subscriber(joint_angles_topic(topics), JointAnglesWithSpeed, recorder.on_joint_angles, queue_size=100)
    rospy.loginfo("%s: recording /joint_states, %s, the goals on %d actions and the calls on %s; output in %s",
                  NODE_NAME, heading_topic, len(actions), joint_angles_topic(topics), output_dir)
    rospy.spin()  # until Ctrl-C or the end of the launch
    return recorder.save(output_dir)
