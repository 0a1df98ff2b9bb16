"""The goals a part stream sends (node/part_stream.py): the action client, the FollowJointTrajectory message built
from a planned trajectory, and what the stream keeps of each goal it has sent (README: "Controllers: what each
goal carries")."""
import io
import time
from typing import NamedTuple, Optional

import actionlib
import numpy
import rospy
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryActionGoal, FollowJointTrajectoryGoal
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.event_log import format_log_line, format_timestamp
from cssr_system.animate_behaviour.motion.planners import GOAL_TIME_TOLERANCE, Planner, settled
from cssr_system.animate_behaviour.motion.trajectory_timing import TimedTrajectory, to_points
from cssr_system.animate_behaviour.rospy_compat import ignore_feedback, write_at_once
from cssr_system.pepper.joint_table import PARTS
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline

_STATE_NAMES = {value: name for name, value in vars(GoalStatus).items() if name.isupper() and isinstance(value, int)}


def goal_state_name(status: int) -> str:
    """actionlib's name of a goal status (actionlib_msgs/GoalStatus), e.g. SUCCEEDED or PREEMPTED."""
    # Not GoalStatus.to_string: it names PENDING (0) "_has_header", the message class's False flag.
    return _STATE_NAMES.get(status, str(status))


def action_client(action: str) -> actionlib.ActionClient:
    """The client of a controller's FollowJointTrajectory action. The goal-handle client, not SimpleActionClient:
    its transitions carry their handle, so a result that arrives before send_goal returns is not lost."""
    client = actionlib.ActionClient(action, FollowJointTrajectoryAction)
    ignore_feedback(client)
    write_at_once(client.pub_goal)  # a goal or a cancel is on the wire when send_goal or cancel returns
    write_at_once(client.pub_cancel)
    return client


def goal_message(joints, timed: TimedTrajectory) -> FollowJointTrajectoryGoal:
    """The goal of a planned trajectory, to start as soon as it arrives. It carries positions, velocities and
    accelerations (the controller plays quintics through them), a hold after a last point at rest
    (`planners.settled`) and GOAL_TIME_TOLERANCE; no tolerances of its own, so the controller's apply."""
    timed = settled(timed)
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = list(joints)
    goal.trajectory.header.stamp = rospy.Time(0)  # start now
    goal.goal_time_tolerance = rospy.Duration.from_sec(GOAL_TIME_TOLERANCE)
    nanoseconds = numpy.rint(numpy.asarray(timed.times) * 1e9).astype(numpy.int64).tolist()
    goal.trajectory.points = [
        JointTrajectoryPoint(positions=list(point.positions), velocities=list(point.velocities),
                             accelerations=list(point.accelerations),
                             time_from_start=rospy.Duration(*divmod(nanosecond, 1000000000)))
        for point, nanosecond in zip(to_points(timed), nanoseconds)]
    return goal


def rehearse(part: str, plan: Planner) -> None:
    """Plans, builds and encodes one goal of `part` and its log line without sending them, so that the first
    `enabled` pays no first-use costs (on the robot laptop's Python they made it take ~80 ms)."""
    joints = PARTS[part].joints
    centre, zeros = numpy.array(PARTS[part].centre), numpy.zeros(len(joints))
    timed = plan(0.0, centre, zeros, zeros)
    FollowJointTrajectoryActionGoal(goal=goal_message(joints, timed)).serialize(io.BytesIO())
    format_log_line(format_timestamp(time.time()), contract.GOAL_SENT, dict(times=timed.times,
                                                                            positions=timed.positions))


class OutgoingGoal(NamedTuple):
    """A goal planned and built, not yet sent: a stop plans every part's goal before the first one leaves."""
    purpose: str  # PURPOSE_ANIMATE or PURPOSE_HOME
    planned_at: Optional[float]  # on the stream's clock, when the goal starts; None: that clock does not run yet
    start_state: tuple  # (positions, velocities, accelerations) it starts from
    timed: TimedTrajectory
    goal: FollowJointTrajectoryGoal


class RunningGoal:
    """A goal of ours: its number, purpose, actionlib handle, and the motion the controller makes of it.

    A goal sent while the clock did not run yet (simulated time before its first /clock message) starts when the
    clock starts: `start(now)` dates it then."""

    def __init__(self, number: int, purpose: str, handle, outgoing: OutgoingGoal) -> None:
        self.number = number
        self.purpose = purpose
        self.handle = handle  # actionlib ClientGoalHandle
        self.duration = outgoing.goal.trajectory.points[-1].time_from_start.to_sec()  # with its hold
        self.start_time: Optional[float] = None
        self.end_time = float("inf")
        self.last_positions = numpy.array(outgoing.timed.positions[-1], dtype=float)
        self._start_state = tuple(None if vector is None else numpy.array(vector, dtype=float)
                                  for vector in outgoing.start_state)  # a copy: the callers' arrays may change
        self._timed: Optional[TimedTrajectory] = outgoing.timed
        self._goal = outgoing.goal  # the message sent (actionlib keeps it with the handle)
        self._spline: Optional[JointTrajectorySpline] = None
        if outgoing.planned_at is not None:
            self.start(outgoing.planned_at)

    def start(self, now: float) -> None:
        self.start_time = now
        self.end_time = now + self.duration

    @property
    def dated(self) -> bool:
        return self.start_time is not None

    @property
    def spline(self) -> JointTrajectorySpline:
        """What the controller executes. Built when first needed (the next goal's start), not while goals are
        being sent: at an enable every millisecond before the last part's goal counts."""
        if self._spline is None:
            self._spline = JointTrajectorySpline(*self._start_state, to_points(self._timed),
                                                 start_time=self.start_time or 0.0)
        return self._spline

    def prepare(self) -> None:
        """Builds the spline and every segment's polynomial ahead, while nothing waits, so that the next goal or a
        stop that starts from this one only samples it."""
        if self._timed is not None and self.dated:
            self.spline.compute_segments()

    def release(self) -> None:
        """The goal no longer runs for us (replaced, cancelled, yielded): only its end is still awaited, for the log.
        Its motion and the message's points are let go (actionlib needs the message's goal id only), so that up
        to part_stream.MAX_UNFINISHED_GOALS of them cost little."""
        if self._goal is not None:
            self._goal.trajectory.points = []
        self._start_state = self._timed = self._spline = self._goal = None
