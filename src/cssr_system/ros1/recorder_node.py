"""animateBehaviourRecorder: records a run of animateBehaviour and, when stopped, writes it and its plot.

rosrun cssr_system animateBehaviourRecorder.py [_output_dir:=DIR] [_node:=/animateBehaviour]

From its start until it is stopped (Ctrl-C, or roslaunch ending the launch) it records /joint_states,
the base heading (odometry of the simulated Pepper's platform, ``<namespace>/odom``), the goals,
cancels and results on every part's FollowJointTrajectory action (the namespaces of the node's topic
file), the setAngles calls on its JointAngles topic and the node's mode (its status topic). When
stopped, it reads the node's log file for the enable and disable instants and the joints' bands, and
writes into ``~output_dir``:

  animation.json   the recording (format: `cssr_system.recording.recording`), with
                   ``commanded`` (what the node commanded: its goals replayed as the controller
                   executes them, or its setAngles calls as naoqi_driver executes them, `commanded`)
                   and ``marks`` (every other node's goal on a part, from its receipt to its result,
                   and its bursts of setAngles calls) and ``modes`` (the node's mode over time)
  animation.png    its plot (`plot`)

and prints both paths. Nothing recorded (no /joint_states): nothing written. What it keeps and writes is
`run_recorder`'s, which the ROS 2 recorder (``cssr_system.ros2.recorder_node``) shares.

Parameters: ``~output_dir`` (default ``$ROS_HOME/animateBehaviourDemo``); ``~node`` (the node
recorded, default ``/animateBehaviour``: its parameters give its configuration file, platform,
topics and log file, as the node itself resolves them).
"""
import os
from typing import Any, Dict, Optional

import rospy
from actionlib_msgs.msg import GoalID
from control_msgs.msg import FollowJointTrajectoryActionGoal, FollowJointTrajectoryActionResult
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.topics import joint_angles_topic
from cssr_system.msg import AnimateBehaviourStatus
from cssr_system.pepper.joint_table import PARTS
from cssr_system.pepper.simulated_pepper import PLATFORMS, odometry_topic
from cssr_system.pepper.trajectory_interpolation import TrajectoryPoint
from cssr_system.recording.commanded import CancelRequest, GoalResult, SentCall, SentGoal
from cssr_system.recording.recording import RunSetting, run_setting
from cssr_system.recording.run_recorder import (NODE_NAME, RunRecorder, default_output_dir,
                                                say)
from cssr_system.ros1.rospy_compat import caller_of
from cssr_system.ros1.trajectory_client import goal_state_name


def goal_id_caller(goal_id: str) -> str:
    """The node that sent a goal, from its id alone: actionlib's ids are "<node>-<count>-<stamp>"."""
    return goal_id.rsplit("-", 2)[0]


class MessageRecorder(RunRecorder):
    """The ROS 1 messages, handed to the recorder (`run_recorder`) as plain values; the callbacks run in rospy's
    threads."""

    def on_joint_states(self, message: JointState) -> None:
        self.add_joint_states(message.header.stamp.to_sec(), message.name, message.position)

    def on_odometry(self, message: Odometry) -> None:
        orientation = message.pose.pose.orientation
        self.add_orientation(message.header.stamp.to_sec(), orientation.x, orientation.y, orientation.z,
                             orientation.w)

    def on_goal(self, message: FollowJointTrajectoryActionGoal, part: str) -> None:
        trajectory = message.goal.trajectory
        points = tuple(TrajectoryPoint(point.time_from_start.to_sec(), tuple(point.positions),
                                       tuple(point.velocities), tuple(point.accelerations))
                       for point in trajectory.points)
        # Its publisher, else (a message whose connection header names none) its goal id's prefix.
        sender = caller_of(message) or goal_id_caller(message.goal_id.id)
        self.add_goal(SentGoal(self.now(), part, sender, message.goal_id.id, tuple(trajectory.joint_names), points))

    def on_cancel(self, message: GoalID, part: str) -> None:
        stamp = message.stamp.to_sec()
        self.add_cancel(CancelRequest(self.now(), part, message.id, stamp - self.start_epoch if stamp > 0.0 else 0.0))

    def on_result(self, message: FollowJointTrajectoryActionResult, part: str) -> None:
        status = message.status
        self.add_result(GoalResult(self.now(), part, status.goal_id.id, goal_state_name(status.status)))

    def on_status(self, message: AnimateBehaviourStatus) -> None:
        self.add_mode(message.mode)

    def on_joint_angles(self, message: JointAnglesWithSpeed) -> None:
        self.add_call(SentCall(self.now(), caller_of(message), tuple(message.joint_names),
                               tuple(message.joint_angles), message.speed, message.relative))


def node_parameters(node: str) -> Dict[str, Any]:
    """The private parameters of `node` (names without its namespace); none when it has none."""
    try:
        values = rospy.get_param(node)
    except KeyError:
        return {}
    return values if isinstance(values, dict) else {}


def main() -> int:
    rospy.init_node(NODE_NAME)
    output_dir = os.path.abspath(rospy.get_param("~output_dir", default_output_dir(rospy.get_namespace())))
    node = rospy.resolve_name(str(rospy.get_param("~node", contract.NODE_NAME)))  # relative: in our namespace
    parameters = node_parameters(node)
    try:
        setting = run_setting(parameters, os.environ.get("ROS_HOME"), node)  # type: Optional[RunSetting]
        platform = setting.platform
        topics = setting.topics
    except ValueError as error:
        say("the configuration of %s cannot be read (%s): recording without its goals and log" % (node, error))
        setting, platform, topics = None, str(parameters.get("platform", "robot")), {}
    heading_topic = odometry_topic(PLATFORMS[platform if platform in PLATFORMS else "robot"])
    recorder = MessageRecorder(node, setting, heading_topic)
    rospy.Subscriber(contract.JOINT_STATES_TOPIC, JointState, recorder.on_joint_states, queue_size=100)
    rospy.Subscriber(heading_topic, Odometry, recorder.on_odometry, queue_size=100)
    rospy.Subscriber(contract.interface_of(node, contract.STATUS), AnimateBehaviourStatus, recorder.on_status,
                     queue_size=10)
    actions = [(key, topics[key]) for key in PARTS if key in topics]
    for key, action in actions:
        rospy.Subscriber(action + "/goal", FollowJointTrajectoryActionGoal, recorder.on_goal, key, queue_size=20)
        rospy.Subscriber(action + "/cancel", GoalID, recorder.on_cancel, key, queue_size=20)
        rospy.Subscriber(action + "/result", FollowJointTrajectoryActionResult, recorder.on_result, key,
                         queue_size=20)
    # With actuation joint_angles the node's commands are setAngles calls; other nodes' calls are marked either way.
    rospy.Subscriber(joint_angles_topic(topics), JointAnglesWithSpeed, recorder.on_joint_angles, queue_size=100)
    rospy.loginfo("%s: recording joint_states, %s, the goals on %d actions and the calls on %s; output in %s",
                  NODE_NAME, heading_topic, len(actions), joint_angles_topic(topics), output_dir)
    rospy.spin()  # until Ctrl-C or the end of the launch
    return recorder.save(output_dir)
