#!/usr/bin/env python3
"""The benchmark's yardstick on ROS 2: a minimal rclpy node with animateBehaviour's interface and nothing else, the twin
of reference_node.py. It serves `setActivation` and `set_enabled`, holds one FollowJointTrajectory action client per
controller of the platform's topic file, and while enabled sends each part goals planned as the node plans them, back
to back, and turns the base as the node does (reference_motion.py); on `disabled`, and on SIGINT or SIGTERM before it
exits, it sends each part back to its centre as the node does. It serves an animate action that refuses every goal,
and subscribes to what a node that yields to other nodes must receive, as the node does (each controller's status and
trajectory topics, the base topic, the JointAngles topic; their messages are dropped), besides its action clients'
topics: no /joint_states. One executor thread serves it, as one serves the node.

  reference_node_ros2.py --ros-args -p platform:=robot [-p gestureDuration:=0.5 -p numPoints:=10 ...]
"""
import signal
import sys
import threading
import time

import rclpy
from control_msgs.action import FollowJointTrajectory
from cssr_system_interfaces.srv import SetActivation
from geometry_msgs.msg import Twist
from action_msgs.msg import GoalStatusArray
from cssr_system_interfaces.action import Animate
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
from rclpy.action import ActionClient, ActionServer, GoalResponse
from rclpy.qos import qos_profile_action_status_default
from trajectory_msgs.msg import JointTrajectory
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions
from std_srvs.srv import SetBool

from reference_motion import SETTINGS, ReferenceMotion, configuration_of

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.topics import WHEELS_KEY, joint_angles_topic
from cssr_system.pepper.joint_table import PARTS
from cssr_system.ros2.foreign_watch import trajectory_topic
from cssr_system.ros2.trajectory_client import goal_message

SIGNALS = {signal.SIGINT, signal.SIGTERM}


class ReferenceNode:
    def __init__(self, node: Node) -> None:
        given = {name: parameter.value for name, parameter in node.get_parameters_by_prefix("").items()}
        settings = {key: given[key] for key in SETTINGS if key in given}
        configuration, topics = configuration_of(given.get("platform", "robot"), settings)
        self.clients = {key: ActionClient(node, FollowJointTrajectory, node.resolve_topic_name(name))
                        for key, name in topics.items() if key in PARTS}
        self._wheels = (node.create_publisher(Twist, node.resolve_topic_name(topics[WHEELS_KEY]), 10)
                        if WHEELS_KEY in topics else None)
        self.motion = ReferenceMotion(configuration, topics, self._send, self._turn)
        node.create_service(SetActivation, "~/" + contract.SET_ACTIVATION, self._on_set_activation)
        node.create_service(SetBool, "~/" + contract.SET_ENABLED, self._on_set_enabled)
        self._animate = ActionServer(node, Animate, "~/" + contract.ANIMATE_ACTION, lambda handle: Animate.Result(),
                                     goal_callback=lambda goal: GoalResponse.REJECT)
        self._watch(node, topics)

    @staticmethod
    def _watch(node: Node, topics) -> None:
        """The subscriptions of a node that yields to other nodes' goals, trajectories, turns and setAngles calls."""
        for key, name in topics.items():
            action = node.resolve_topic_name(name)
            if key in PARTS:
                node.create_subscription(GoalStatusArray, action + "/_action/status", lambda message: None,
                                         qos_profile_action_status_default)
                node.create_subscription(JointTrajectory, trajectory_topic(action), lambda message: None, 10)
            elif key == WHEELS_KEY:
                node.create_subscription(Twist, action, lambda message: None, 10)
        node.create_subscription(JointAnglesWithSpeed, node.resolve_topic_name(joint_angles_topic(topics)),
                                 lambda message: None, 10)

    def _send(self, key, joints, timed) -> None:
        self.clients[key].send_goal_async(goal_message(joints, timed))

    def _turn(self, angular_z: float) -> None:
        twist = Twist()
        twist.angular.z = angular_z
        self._wheels.publish(twist)

    def _activate(self, enabled: bool) -> None:
        if enabled:
            self.motion.enable()
        else:
            self.motion.disable()

    def _on_set_activation(self, request, response):
        state = request.state.strip().lower()
        response.success = contract.REPLY_FAILURE
        if state in ("enabled", "disabled"):
            self._activate(state == "enabled")
            response.success = contract.REPLY_SUCCESS
        return response

    def _on_set_enabled(self, request, response):
        self._activate(request.data)
        response.success, response.message = True, "enabled" if request.data else "disabled"
        return response


def main() -> int:
    # Blocked before rclpy starts its threads, so that the signal waits for sigwait below in any thread.
    signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
    rclpy.init(args=sys.argv, signal_handler_options=SignalHandlerOptions.NO)
    node = Node(contract.NODE_NAME, automatically_declare_parameters_from_overrides=True)
    reference = ReferenceNode(node)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, name="executor", daemon=True)
    spinner.start()
    signal.sigwait(SIGNALS)
    reference.motion.disable()
    reference.motion.close()
    time.sleep(0.05)  # the return goals leave
    executor.shutdown()
    spinner.join(5.0)  # rclpy's threads end before the interpreter does
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
