"""Subscriptions that notice other nodes' commands on our controllers and on the base topic, and post them
to the supervisor as events (README: "Sharing the robot").

Every client's goals travel on ``<action>/goal``, each message with its sender's caller id; every goal's end
on ``<action>/result``; a controller also obeys trajectories on its ``command`` topic. Messages from this
node itself are not foreign: they are recognised by the caller id (goals, Twists) or by the goal id, which
actionlib starts with the client's caller id (results)."""
from typing import Callable

import rospy
from control_msgs.msg import FollowJointTrajectoryActionGoal, FollowJointTrajectoryActionResult
from geometry_msgs.msg import Twist
from trajectory_msgs.msg import JointTrajectory

from cssr_system.animate_behaviour.node.events import ForeignCommand, ForeignGoal, ForeignResult, ForeignTwist
from cssr_system.pepper.joint_table import command_topic


def caller_of(message) -> str:
    """The caller id of the node that published `message` (rospy keeps its connection header)."""
    return getattr(message, "_connection_header", {}).get("callerid", "")


def trajectory_end(trajectory: JointTrajectory, received_at: float) -> float:
    """When the last point of `trajectory` passes (a zero stamp means "start when received")."""
    start = received_at if trajectory.header.stamp.is_zero() else trajectory.header.stamp.to_sec()
    return start + (trajectory.points[-1].time_from_start.to_sec() if trajectory.points else 0.0)


class ForeignCommandWatch:
    def __init__(self, own_caller_id: str, post: Callable[[object], None], clock: Callable[[], float]) -> None:
        self._own = own_caller_id
        self._post = post
        self._clock = clock
        self._subscribers = []  # kept for the node's life

    def watch_controller(self, action: str) -> None:
        self._subscribers += [
            rospy.Subscriber(action + "/goal", FollowJointTrajectoryActionGoal, self._on_goal, callback_args=action,
                             queue_size=10),
            rospy.Subscriber(action + "/result", FollowJointTrajectoryActionResult, self._on_result,
                             callback_args=action, queue_size=10),
            rospy.Subscriber(command_topic(action), JointTrajectory, self._on_command, callback_args=action,
                             queue_size=10)]

    def watch_base(self, topic: str) -> None:
        self._subscribers.append(rospy.Subscriber(topic, Twist, self._on_twist, callback_args=topic, queue_size=10))

    def _foreign(self, message) -> str:
        caller = caller_of(message)
        return caller if caller and caller != self._own else ""

    def _on_goal(self, message: FollowJointTrajectoryActionGoal, action: str) -> None:
        caller = self._foreign(message)
        if caller:
            self._post(ForeignGoal(action, message.goal_id.id, caller,
                                   trajectory_end(message.goal.trajectory, self._clock())))

    def _on_result(self, message: FollowJointTrajectoryActionResult, action: str) -> None:
        goal_id = message.status.goal_id.id
        if not goal_id.startswith(self._own + "-"):
            self._post(ForeignResult(action, goal_id))

    def _on_command(self, message: JointTrajectory, action: str) -> None:
        caller = self._foreign(message) or "unknown"  # we never publish there
        self._post(ForeignCommand(action, caller, trajectory_end(message, self._clock())))

    def _on_twist(self, message: Twist, topic: str) -> None:
        caller = self._foreign(message)
        if caller:
            self._post(ForeignTwist(topic, caller, message))
