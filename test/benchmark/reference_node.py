#!/usr/bin/env python3
"""The benchmark's yardstick on ROS 1: a minimal rospy node with animateBehaviour's interface and nothing else. It
serves `setActivation` and `set_enabled`, holds one action client per controller of the platform's topic file, and
while enabled sends each part goals planned as the node plans them, back to back, and turns the base as the node does
(reference_motion.py); it cancels them on `disabled`, and exits on SIGINT or SIGTERM after cancelling. It subscribes
to nothing but what its action clients need (their status and result topics; not their feedback, as the node).
Measured with the same code as the node (`benchmark.py`), its figures show what rospy itself costs on the machine at
hand.

  reference_node.py _platform:=robot [_gestureDuration:=0.5 _numPoints:=10]
"""
import signal
import sys
import time

import actionlib
import rospy
from control_msgs.msg import FollowJointTrajectoryAction
from geometry_msgs.msg import Twist
from std_srvs.srv import SetBool, SetBoolResponse

from reference_motion import SETTINGS, ReferenceMotion, configuration_of

from cssr_system.animate_behaviour.contract import NODE_NAME, SERVICE_NAME, SET_ENABLED_SERVICE_NAME
from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.pepper.joint_table import PARTS
from cssr_system.ros1.trajectory_client import goal_message
from cssr_system.srv import setActivation, setActivationResponse

SIGNALS = {signal.SIGINT, signal.SIGTERM}


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
    handles = {}

    def send(key, joints, timed):
        handles[key] = clients[key].send_goal(goal_message(joints, timed))

    def cancel():
        for goal_handle in handles.values():
            goal_handle.cancel()
        handles.clear()
    wheels = rospy.Publisher(topics[WHEELS_KEY], Twist, queue_size=10) if WHEELS_KEY in topics else None

    def turn(angular_z):
        twist = Twist()
        twist.angular.z = angular_z
        wheels.publish(twist)
    motion = ReferenceMotion(configuration, topics, send, cancel, turn)

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
    signal.sigwait(SIGNALS)
    motion.disable()
    motion.close()
    time.sleep(0.05)  # the cancels leave through rospy's publisher queues
    rospy.signal_shutdown("signal")
    return 0


if __name__ == "__main__":
    sys.exit(main())
