"""One controller's goal stream: its action client, its state (idle, animating, homing, waiting) and the
goals it sent. Only the supervisor thread calls it.
"""
import enum
import time
from collections import OrderedDict
from typing import NamedTuple, Optional

import actionlib
from actionlib.action_client import CommState
import numpy
import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import PURPOSE_HOME, NODE_NAME
from cssr_system.animate_behaviour.event_log import EventLog
from cssr_system.animate_behaviour.motion.trajectory_timing import TimedTrajectory, time_trajectory, to_points
from cssr_system.animate_behaviour.motion.waypoints import PartMotion
from cssr_system.animate_behaviour.node.events import GoalDone
from cssr_system.animate_behaviour.node.joint_states import JointStateCache
from cssr_system.pepper.joint_table import PARTS
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline


MAX_UNFINISHED_GOALS = 16  # handles kept for goals whose end has not been reported yet


LOST_RESULT_GRACE = 5.0  # s after a goal's end before a missing result counts as lost


class PartState(enum.Enum):
    IDLE = "idle"  # no goal of ours is running
    ANIMATING = "animating"  # random goals, one after the other
    HOMING = "homing"  # the return-to-centre goal after a disable
    WAITING = "waiting"  # animating, but waiting before the next goal (retry after a failure)


class SentGoal(NamedTuple):
    number: int
    purpose: str  # PURPOSE_ANIMATE or PURPOSE_HOME
    spline: JointTrajectorySpline  # what the controller executes, on the monotonic clock
    handle: object  # actionlib ClientGoalHandle


class PartStream:
    """One controller's goal stream. Only the supervisor thread calls its methods."""

    def __init__(self, part: str, action: str, post) -> None:
        self.part = part
        self.action = action
        # The goal-handle client, not SimpleActionClient: its transitions carry their handle, so
        # a result that arrives before send_goal returns is not lost.
        self.client = actionlib.ActionClient(action, FollowJointTrajectoryAction)
        self.connected = False
        self.state = PartState.IDLE
        self.motion: Optional[PartMotion] = None
        self.retry_at: Optional[float] = None
        self._post = post
        self._goal_number = 0
        self._sent: Optional[SentGoal] = None
        # Goals that have not reported their end, replaced and cancelled ones too: holding their
        # handles keeps their transitions coming, so every goal's final state reaches the log.
        self._unfinished: "OrderedDict[int, SentGoal]" = OrderedDict()

    # -- state estimates --------------------------------------------------------------------
    def current_state(self, joint_states: JointStateCache, now: float):
        """Positions and velocities to start the next goal from: what the controller is executing
        for us (it splices new goals onto that), else the measured joints, else the centre."""
        joints = PARTS[self.part].joints
        if self._sent is not None and now <= self._sent.spline.end_time:
            positions, velocities, accelerations = self._sent.spline.sample(now)
            return numpy.asarray(positions), numpy.asarray(velocities), numpy.asarray(accelerations)
        measured = joint_states.positions(joints)
        if measured is None and self._sent is not None:
            measured = numpy.asarray(self._sent.spline.sample(now)[0])
        if measured is None:
            measured = numpy.array(PARTS[self.part].centre, dtype=float)
        zeros = numpy.zeros(len(joints))
        return measured, zeros, zeros

    # -- commands -----------------------------------------------------------------------------
    def send(self, waypoints: numpy.ndarray, gesture_duration: float, purpose: str,
             joint_states: JointStateCache, log: EventLog) -> TimedTrajectory:
        now = time.monotonic()
        joints = PARTS[self.part].joints
        positions, velocities, accelerations = self.current_state(joint_states, now)
        bands = self.motion.bounds if self.motion is not None else ()
        lower, upper = [b.lower for b in bands], [b.upper for b in bands]
        # A return home from a moving joint brakes inside the band it was animated in.
        home_bounds = (lower, upper) if purpose == PURPOSE_HOME and bands else None
        timed = time_trajectory(waypoints, joints, positions, velocities, gesture_duration,
                                start_accelerations=accelerations, position_bounds=home_bounds)
        points = to_points(timed)
        goal = FollowJointTrajectoryGoal()
        goal.trajectory.joint_names = list(joints)
        goal.trajectory.header.stamp = rospy.Time(0)  # start now
        for point in points:
            goal.trajectory.points.append(JointTrajectoryPoint(
                positions=list(point.positions), velocities=list(point.velocities),
                accelerations=list(point.accelerations),
                time_from_start=rospy.Duration.from_sec(point.time)))
        self._goal_number += 1
        number = self._goal_number

        def transition(handle, part=self.part):
            if handle.get_comm_state() != CommState.DONE:
                return
            result = handle.get_result()
            self._post(GoalDone(part, self.action, number, handle.get_goal_status(),
                                None if result is None else result.error_code,
                                "" if result is None else result.error_string))

        handle = self.client.send_goal(goal, transition)
        self._sent = SentGoal(number, purpose,
                              JointTrajectorySpline(positions, velocities, accelerations, points,
                                                    start_time=now), handle)
        self._unfinished[number] = self._sent
        while len(self._unfinished) > MAX_UNFINISHED_GOALS:  # a controller that never answers
            self._unfinished.popitem(last=False)
        rospy.logdebug("%s: %s goal %d (%s) sent to %s: %d points over %.1f s.", NODE_NAME,
                       self.part, number, purpose, self.action, len(points), timed.times[-1])
        log.write(contract.GOAL_SENT, part=self.part, label=PARTS[self.part].label,
                  action=self.action, purpose=purpose, goal=number, joints=joints,
                  centre=PARTS[self.part].centre,
                  lower=lower, upper=upper,
                  moving=self.motion.moving if self.motion is not None else (),
                  times=timed.times, positions=timed.positions)
        return timed

    def cancel(self) -> None:
        if self._sent is not None and self.connected:
            self._sent.handle.cancel()
        self._sent = None

    def overdue(self, now: float) -> bool:
        """True when our goal should long have ended but no result came (a lost result)."""
        return self._sent is not None and now > self._sent.spline.end_time + LOST_RESULT_GRACE

    def is_current(self, goal_number: int) -> bool:
        return self._sent is not None and self._sent.number == goal_number

    def finished(self, goal_number: int) -> Optional[SentGoal]:
        """The goal that reported its end, once; None for one already reported."""
        return self._unfinished.pop(goal_number, None)

    def forget_goal(self) -> None:
        self._sent = None

    @property
    def sent_purpose(self) -> Optional[str]:
        return None if self._sent is None else self._sent.purpose
