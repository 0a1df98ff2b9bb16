"""The ROS 1 client of a controller's FollowJointTrajectory action, as the part streams use it (core/goals.py says
what they ask of it): the goal message of a planned trajectory, its sending through actionlib, and the goal's end
reported by name (README: "Controllers: what each goal carries")."""
import io
import time
from typing import Callable, Optional

import actionlib
import numpy
import rospy
from actionlib.action_client import CommState
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryActionGoal, FollowJointTrajectoryGoal
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.event_log import format_log_line, format_timestamp
from cssr_system.core.goals import WITHHELD
from cssr_system.motion.planners import GOAL_TIME_TOLERANCE, Planner, settled
from cssr_system.motion.trajectory_timing import TimedTrajectory
from cssr_system.pepper.joint_table import PARTS
from cssr_system.ros1.rospy_compat import ignore_feedback, server_ready, write_at_once

_STATE_NAMES = {value: name for name, value in vars(GoalStatus).items() if name.isupper() and isinstance(value, int)}


def goal_state_name(status: int) -> str:
    """actionlib's name of a goal status (actionlib_msgs/GoalStatus), e.g. SUCCEEDED or PREEMPTED."""
    # Not GoalStatus.to_string: it names PENDING (0) "_has_header", the message class's False flag.
    return _STATE_NAMES.get(status, str(status))


def goal_message(joints, timed: TimedTrajectory) -> FollowJointTrajectoryGoal:
    """The goal of a planned trajectory (with its hold, `planners.settled`), to start as soon as it arrives. It
    carries positions, velocities and accelerations (the controller plays quintics through them) and
    GOAL_TIME_TOLERANCE; no tolerances of its own, so the controller's apply."""
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = list(joints)
    goal.trajectory.header.stamp = rospy.Time(0)  # start now
    goal.goal_time_tolerance = rospy.Duration.from_sec(GOAL_TIME_TOLERANCE)
    nanoseconds = numpy.rint(numpy.asarray(timed.times) * 1e9).astype(numpy.int64).tolist()
    # Rows as lists of floats in one C loop each; the points' fields in the message's order (positions, velocities,
    # accelerations, effort, time_from_start): keyword arguments take genpy a third longer for 100 points.
    rows = zip(*(numpy.asarray(values, dtype=float).tolist()
                 for values in (timed.positions, timed.velocities, timed.accelerations)), nanoseconds)
    goal.trajectory.points = [
        JointTrajectoryPoint(positions, velocities, accelerations, [], rospy.Duration(*divmod(nanosecond, 1000000000)))
        for positions, velocities, accelerations, nanosecond in rows]
    return goal


def rehearse(part: str, plan: Planner) -> None:
    """Plans, builds and encodes one goal of `part` and its log line without sending them, so that the first
    `enabled` pays no first-use costs (on the robot laptop's Python they made it take ~80 ms)."""
    joints = PARTS[part].joints
    centre, zeros = numpy.array(PARTS[part].centre), numpy.zeros(len(joints))
    timed = plan(0.0, centre, zeros, zeros)
    FollowJointTrajectoryActionGoal(goal=goal_message(joints, settled(timed))).serialize(io.BytesIO())
    format_log_line(format_timestamp(time.time()), contract.GOAL_SENT, dict(times=timed.times,
                                                                            positions=timed.positions))


class SentGoal:
    """The handle of a goal sent: cancel it, or let its points go once it no longer runs for us (actionlib keeps
    the message with its handle; only the goal id is needed for its end)."""

    def __init__(self, handle, goal: FollowJointTrajectoryGoal) -> None:
        self.handle = handle  # actionlib ClientGoalHandle
        self.goal = goal

    def cancel(self) -> None:
        self.handle.cancel()

    def release(self) -> None:
        self.goal.trajectory.points = []


class WithheldGoal:
    """The handle of a goal that the last look withheld: it never left, so there is nothing to cancel."""

    def cancel(self) -> None:
        pass

    def release(self) -> None:
        pass


class TrajectoryClient:
    """One controller's FollowJointTrajectory client. The goal-handle client, not SimpleActionClient: its
    transitions carry their handle, so a result that arrives before send_goal returns is not lost.

    `last_look`: the watch's view of other clients' goals (core/foreign_goals.py). Each goal is sent under its
    lock, which the status callback (a rospy thread) also takes, unless the latest status shows another client's
    goal running on the controller: then the goal is withheld (README: "Sharing the robot")."""

    def __init__(self, action: str, client: Optional[actionlib.ActionClient] = None, last_look=None) -> None:
        self.action = action
        self._last_look = last_look
        self.client = client or actionlib.ActionClient(action, FollowJointTrajectoryAction)
        if client is None:
            ignore_feedback(self.client)
            write_at_once(self.client.pub_goal)  # a goal or a cancel is on the wire when send or cancel returns
            write_at_once(self.client.pub_cancel)

    def ready(self) -> bool:
        """The action server answers (rospy_compat.server_ready: actionlib's own test, without waiting)."""
        return server_ready(self.client)

    @staticmethod
    def goal(joints, timed: TimedTrajectory) -> FollowJointTrajectoryGoal:
        return goal_message(joints, timed)

    def send(self, goal: FollowJointTrajectoryGoal, done: Callable[[str, Optional[int], str], None]):
        def transition(handle) -> None:
            if handle.get_comm_state() != CommState.DONE:
                return
            result = handle.get_result()
            done(goal_state_name(handle.get_goal_status()), None if result is None else result.error_code,
                 "" if result is None else result.error_string)

        if self._last_look is None:
            return SentGoal(self.client.send_goal(goal, transition), goal)
        handles = []
        foreign = self._last_look.send_unless_foreign(
            self.action, lambda: handles.append(self.client.send_goal(goal, transition)))
        if foreign is not None:
            done(WITHHELD, None, "not sent: another client's goal %s is on the controller" % foreign)
            return WithheldGoal()
        return SentGoal(handles[0], goal)
