"""Subscriptions that notice other nodes' commands on our controllers and on the base topic, and post them to the
supervisor as events (README: "Sharing the robot"), on ROS 2.

Goals: an action server publishes its goals' states on the action's status topic (``<action>/_action/status``, the
name ROS 2's action design gives it); a running goal whose id is not one of ours (`own_goals`: those we sent lately)
is another client's.
Trajectories on a controller's ``joint_trajectory`` topic are always another node's (this node sends goals).
Twists on the base topic and setAngles calls on naoqi_driver2's JointAngles topic are another node's unless they
are ours coming back (ros2/rclpy_compat.py). ROS 2 gives no message its publisher, so the other node is named by
the topic's publishers other than this node."""
from typing import Callable, Optional, Sequence, Set

import numpy
from action_msgs.msg import GoalStatus, GoalStatusArray
from geometry_msgs.msg import Twist
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
from rclpy.qos import qos_profile_action_status_default
from trajectory_msgs.msg import JointTrajectory

from cssr_system.core.events import ForeignCommand, ForeignJointAngles, ForeignTwist
from cssr_system.core.foreign_goals import ForeignGoals
from cssr_system.core.foreign_motion import set_angles_on_our_joints
from cssr_system.ros2.joint_angles_topic import joint_angles_key
from cssr_system.ros2.rclpy_compat import ACTION_STATUS, OwnMessages, endpoint_names, other_action_client
from cssr_system.ros2.time_conversion import seconds_of

RUNNING_STATES = (GoalStatus.STATUS_ACCEPTED, GoalStatus.STATUS_EXECUTING, GoalStatus.STATUS_CANCELING)
QUEUE_DEPTH = 10
UNKNOWN_NODE = "another node"


def trajectory_topic(action: str) -> str:
    """ros2_control's joint_trajectory_controller's topic beside its action (ROS 1's is ``command``)."""
    return action.rsplit("/", 1)[0] + "/joint_trajectory"


def twist_key(twist: Twist) -> tuple:
    return (twist.linear.x, twist.linear.y, twist.linear.z, twist.angular.x, twist.angular.y, twist.angular.z)


def trajectory_end(trajectory: JointTrajectory, received_at: float) -> float:
    """When the last point of `trajectory` passes (a zero stamp means "start when received")."""
    stamp = seconds_of(trajectory.header.stamp)
    start = received_at if stamp == 0.0 else stamp
    return start + (seconds_of(trajectory.points[-1].time_from_start) if trajectory.points else 0.0)


class ForeignCommandWatch:
    def __init__(self, node, own_goals: Set[bytes], post: Callable[[object], None], clock: Callable[[], float],
                 report_error: Callable[[str, Exception], None], status_seen: Callable[[str], None]) -> None:
        self._node = node
        self._own_goals = own_goals
        self._post = post
        self._clock = clock
        self._report_error = report_error
        self._status_seen = status_seen
        self.own_twists = OwnMessages()  # the base stream's turns, as they come back
        self.own_calls = OwnMessages()  # the joint-angle streams' calls (ros2/joint_angles_topic.py)
        self.goals = ForeignGoals(post)  # also the last look of the trajectory clients
        self._subscriptions = []  # kept for the node's life
        self._positions: Callable[[Sequence[str]], Optional[numpy.ndarray]] = lambda joints: None

    def watch_controller(self, action: str) -> None:
        self._subscribe(GoalStatusArray, action + ACTION_STATUS, self._on_status, action,
                        qos_profile_action_status_default)
        self._subscribe(JointTrajectory, trajectory_topic(action), self._on_trajectory, action)

    def watch_base(self, topic: str) -> None:
        self._subscribe(Twist, topic, self._on_twist, topic)

    def watch_joint_angles(self, topic: str, positions: Callable[[Sequence[str]], Optional[numpy.ndarray]]) -> None:
        """naoqi_driver2's JointAngles topic; `positions` gives the measured joints (JointStateCache.positions)."""
        self._positions = positions
        self._subscribe(JointAnglesWithSpeed, topic, self._on_joint_angles, topic)

    def _subscribe(self, message_type, topic: str, callback, argument: str, qos=QUEUE_DEPTH) -> None:
        def guarded(message) -> None:  # an unexpected error in one line, not rclpy's traceback
            try:
                callback(message, argument)
            except Exception as error:
                self._report_error("watching %s" % argument, error)
        self._subscriptions.append(self._node.create_subscription(message_type, topic, guarded, qos))

    def _publisher_of(self, topic: str) -> str:
        """The topic's publishers other than this node (ROS 2 does not say which one sent a message)."""
        names = sorted(endpoint_names(self._node.get_publishers_info_by_topic(topic))
                       - {self._node.get_fully_qualified_name()})
        return ",".join(names) or UNKNOWN_NODE

    def _on_status(self, message: GoalStatusArray, action: str) -> None:
        self._status_seen(action)
        uuids = (bytes(status.goal_info.goal_id.uuid) for status in message.status_list)
        self.goals.status_list(action, ((uuid.hex(), status.status in RUNNING_STATES)
                                        for uuid, status in zip(uuids, message.status_list)
                                        if uuid not in self._own_goals),
                               lambda goal_id: other_action_client(self._node, action))

    def _on_trajectory(self, message: JointTrajectory, action: str) -> None:
        topic = trajectory_topic(action)
        self._post(ForeignCommand(action, self._publisher_of(topic), trajectory_end(message, self._clock())))

    def _on_twist(self, message: Twist, topic: str) -> None:
        if not self.own_twists.is_own(twist_key(message)):
            self._post(ForeignTwist(topic, self._publisher_of(topic), message))

    def _on_joint_angles(self, message: JointAnglesWithSpeed, topic: str) -> None:
        """Posts a ForeignJointAngles for another node's call naming joints of our parts, with when it ends (from
        the measured joints; from their centres when unmeasured)."""
        if self.own_calls.is_own(joint_angles_key(message.joint_names, message.joint_angles, message.speed)):
            return
        call = set_angles_on_our_joints(message.joint_names, message.joint_angles, message.speed, message.relative,
                                        self._positions)
        if call is not None:
            self._post(ForeignJointAngles(topic, self._publisher_of(topic), call[0], self._clock() + call[1]))
