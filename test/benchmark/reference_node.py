#!/usr/bin/env python3
"""The benchmark's yardstick on ROS 1: a minimal rospy node with animateBehaviour's interface and nothing else. It
serves `setActivation` and `set_enabled`, holds one action client per controller of the platform's topic file, and
while enabled sends each part goals planned as the node plans them, back to back, and turns the base as the node does
(reference_motion.py); on `disabled`, and on SIGINT or SIGTERM before it exits, it sends each part back to its centre
as the node does. It serves an animate action that refuses every goal (its status as often as the node's), and
subscribes to what a node that yields to other nodes must receive, as the node does (each controller's status and
command topics, the base topic, the JointAngles topic; their messages are dropped), besides its action clients' topics
(not their feedback, as the node): no /joint_states.
Measured with the same code as the node (`benchmark.py`), its figures show what rospy itself costs on the machine at
hand.

  reference_node.py _platform:=robot [_gestureDuration:=0.5 _numPoints:=10]
"""
import signal
import sys
import time

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatusArray
from control_msgs.msg import FollowJointTrajectoryAction
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
from trajectory_msgs.msg import JointTrajectory
from geometry_msgs.msg import Twist
from std_srvs.srv import SetBool, SetBoolResponse

from reference_motion import SETTINGS, ReferenceMotion, configuration_of

from cssr_system.animate_behaviour.contract import (ANIMATE_ACTION, NODE_NAME, SERVICE_NAME, SET_ENABLED_SERVICE_NAME,
                                                    STATUS_FREQUENCY_PARAMETER)
from cssr_system.animate_behaviour.topics import WHEELS_KEY, joint_angles_topic
from cssr_system.msg import AnimateAction
from cssr_system.pepper.joint_table import PARTS, command_topic
from cssr_system.ros1.animate_action import STATUS_FREQUENCY
from cssr_system.ros1.trajectory_client import goal_message
from cssr_system.srv import setActivation, setActivationResponse

SIGNALS = {signal.SIGINT, signal.SIGTERM}


def watch(topics) -> list:
    """The subscriptions of a node that yields to other nodes' goals, trajectories, turns and setAngles calls."""
    subscribers = [rospy.Subscriber(joint_angles_topic(topics), JointAnglesWithSpeed, lambda message: None)]
    for key, name in topics.items():
        if key in PARTS:
            subscribers += [rospy.Subscriber(name + "/status", GoalStatusArray, lambda message: None),
                            rospy.Subscriber(command_topic(name), JointTrajectory, lambda message: None)]
        elif key == WHEELS_KEY:
            subscribers.append(rospy.Subscriber(name, Twist, lambda message: None))
    return subscribers


def animate_action() -> actionlib.ActionServer:
    """An animate action that refuses every goal."""
    rospy.set_param("~" + STATUS_FREQUENCY_PARAMETER, STATUS_FREQUENCY)
    server = actionlib.ActionServer(rospy.resolve_name("~" + ANIMATE_ACTION), AnimateAction,
                                    goal_cb=lambda handle: handle.set_rejected(), auto_start=False)
    server.start()
    return server


def main() -> int:
    # Blocked here, before rospy starts its threads, so that every thread inherits the mask and the signal waits
    # for sigwait below, whichever thread the kernel would have handed it to.
    signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
    rospy.init_node(NODE_NAME, disable_signals=True)
    settings = {key: rospy.get_param("~" + key) for key in SETTINGS if rospy.has_param("~" + key)}
    configuration, topics = configuration_of(rospy.get_param("~platform", "robot"), settings)
    clients = {key: actionlib.ActionClient(name, FollowJointTrajectoryAction) for key, name in topics.items()
               if key in PARTS}
    for client in clients.values():  # as the node: it has no use for the controllers' feedback
        client.feedback_sub.unregister()
    handles = {}  # part -> its last goal's handle, kept as the node keeps its goals': actionlib follows a goal's
    # status only while its handle lives

    def send(key, joints, timed):
        handles[key] = clients[key].send_goal(goal_message(joints, timed))
    wheels = rospy.Publisher(topics[WHEELS_KEY], Twist, queue_size=10) if WHEELS_KEY in topics else None

    def turn(angular_z):
        twist = Twist()
        twist.angular.z = angular_z
        wheels.publish(twist)
    motion = ReferenceMotion(configuration, topics, send, turn)

    def activate(enabled: bool) -> None:
        if enabled:
            motion.enable()
        else:
            motion.disable()

    def on_set_activation(request):
        state = request.state.strip().lower()
        if state not in ("enabled", "disabled"):
            return setActivationResponse("0")
        activate(state == "enabled")
        return setActivationResponse("1")

    def on_set_enabled(request):
        activate(request.data)
        return SetBoolResponse(True, "enabled" if request.data else "disabled")

    rospy.Service(SERVICE_NAME, setActivation, on_set_activation)
    rospy.Service(SET_ENABLED_SERVICE_NAME, SetBool, on_set_enabled)
    kept = [watch(topics), animate_action()]  # for the node's life
    signal.sigwait(SIGNALS)
    del kept
    motion.disable()
    motion.close()
    time.sleep(0.05)  # the return goals leave through rospy's publisher queues
    rospy.signal_shutdown("signal")
    return 0


if __name__ == "__main__":
    sys.exit(main())
