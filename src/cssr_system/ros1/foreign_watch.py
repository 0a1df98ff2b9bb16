"""Subscriptions that notice other nodes' commands on our controllers and on the base topic, and post them
to the supervisor as events (README: "Sharing the robot").

Goals: every client's goals travel on ``<action>/goal``, and the node takes each of them there as the controller
does, before the controller has accepted it (core/foreign_goals.py: `goal_sent`), so that its last look before a
goal of ours leaves sees another client's goal as early as the controller does (doc/performance.md: "Another node's
goal and our next one"). It costs a thread per publisher of the topic and the reading of every goal, our own
included. Every action server also publishes ``<action>/status``, the list of every client's goals with their
states, at each change and a few times a second, which tells when each goal ends. actionlib starts each goal id with
its client's node name, which tells whose goal it is. Trajectories on a
controller's ``command`` topic, Twists on the base topic and setAngles calls on naoqi_driver's JointAngles topic
are watched directly; this node's own Twists and calls are recognised by their caller id."""
from typing import Callable, Optional, Sequence

import numpy
import rospy
from actionlib_msgs.msg import GoalStatus, GoalStatusArray
from control_msgs.msg import FollowJointTrajectoryActionGoal
from geometry_msgs.msg import Twist
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
from trajectory_msgs.msg import JointTrajectory

from cssr_system.core.events import ForeignCommand, ForeignJointAngles, ForeignTwist
from cssr_system.core.foreign_goals import ForeignGoals
from cssr_system.core.foreign_motion import set_angles_on_our_joints
from cssr_system.pepper.joint_table import command_topic
from cssr_system.ros1.rospy_compat import caller_of, caller_of_goal

RUNNING_STATES = (GoalStatus.PENDING, GoalStatus.ACTIVE, GoalStatus.PREEMPTING, GoalStatus.RECALLING)


def trajectory_end(trajectory: JointTrajectory, received_at: float) -> float:
    """When the last point of `trajectory` passes (a zero stamp means "start when received")."""
    start = received_at if trajectory.header.stamp.is_zero() else trajectory.header.stamp.to_sec()
    return start + (trajectory.points[-1].time_from_start.to_sec() if trajectory.points else 0.0)


class ForeignCommandWatch:
    def __init__(self, own_caller_id: str, post: Callable[[object], None], clock: Callable[[], float],
                 report_error: Callable[[str, Exception], None] = None,
                 status_seen: Callable[[str], None] = None) -> None:
        self._report_error = report_error
        self._status_seen = status_seen  # told of every status message, by action (the controller watcher)
        self._own_prefix = own_caller_id + "-"
        self._own = own_caller_id
        self._post = post
        self._clock = clock
        self.goals = ForeignGoals(post)  # also the last look of the trajectory clients
        self._subscribers = []  # kept for the node's life
        # The measured positions of joints (None when unknown), for how long another node's setAngles call runs.
        self._positions: Callable[[Sequence[str]], Optional[numpy.ndarray]] = lambda joints: None

    def watch_controller(self, action: str) -> None:
        self._subscribers += [
            rospy.Subscriber(action + "/goal", FollowJointTrajectoryActionGoal, self._guarded(self._on_goal),
                             callback_args=action, queue_size=10),
            rospy.Subscriber(action + "/status", GoalStatusArray, self._guarded(self._on_status), callback_args=action),
            rospy.Subscriber(command_topic(action), JointTrajectory, self._guarded(self._on_command),
                             callback_args=action, queue_size=10)]

    def watch_base(self, topic: str) -> None:
        self._subscribers.append(rospy.Subscriber(topic, Twist, self._guarded(self._on_twist), callback_args=topic,
                                                  queue_size=10))

    def watch_joint_angles(self, topic: str, positions: Callable[[Sequence[str]], Optional[numpy.ndarray]]) -> None:
        """naoqi_driver's JointAngles topic; `positions` gives the measured joints (JointStateCache.positions)."""
        self._positions = positions
        self._subscribers.append(rospy.Subscriber(topic, JointAnglesWithSpeed, self._guarded(self._on_joint_angles),
                                                  callback_args=topic, queue_size=10))

    def _guarded(self, callback):
        """`callback`, reporting an unexpected error in one line instead of rospy's traceback."""
        def guarded(message, argument):
            try:
                callback(message, argument)
            except Exception as error:
                if self._report_error is None:
                    raise
                self._report_error("watching %s" % argument, error)
        return guarded

    def _on_status(self, message: GoalStatusArray, action: str) -> None:
        if self._status_seen is not None:
            self._status_seen(action)
        self.goals.status_list(action, ((status.goal_id.id, status.status in RUNNING_STATES)
                                        for status in message.status_list
                                        if not status.goal_id.id.startswith(self._own_prefix)), caller_of_goal)

    def _on_goal(self, message: FollowJointTrajectoryActionGoal, action: str) -> None:
        if not message.goal_id.id.startswith(self._own_prefix):
            self.goals.goal_sent(action, message.goal_id.id, caller_of_goal)

    def _on_command(self, message: JointTrajectory, action: str) -> None:
        caller = caller_of(message)
        if caller != self._own:  # never ours: the node does not publish there
            self._post(ForeignCommand(action, caller or "unknown", trajectory_end(message, self._clock())))

    def _on_twist(self, message: Twist, topic: str) -> None:
        caller = caller_of(message)
        if caller and caller != self._own:
            self._post(ForeignTwist(topic, caller, message))

    def _on_joint_angles(self, message: JointAnglesWithSpeed, topic: str) -> None:
        """Posts a ForeignJointAngles for another node's call naming joints of our parts, with when it ends (from
        the measured joints; from their centres when unmeasured)."""
        caller = caller_of(message)
        if caller == self._own:
            return
        call = set_angles_on_our_joints(message.joint_names, message.joint_angles, message.speed, message.relative,
                                        self._positions)
        if call is not None:
            self._post(ForeignJointAngles(topic, caller or "unknown", call[0], self._clock() + call[1]))
