#!/usr/bin/env python3
"""The benchmark's yardstick: a minimal rospy node with animateBehaviour's interface and nothing else. It serves
`setActivation`, holds one action client per controller of the platform's topic file, sends each a one-point goal
to its centre on `enabled`, cancels them on `disabled`, and exits on SIGINT or SIGTERM after cancelling. Measured
with the same code as the node (`benchmark.py`), its figures show what rospy itself costs on the machine at hand."""
import signal
import sys
import time

import actionlib
import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system.animate_behaviour.configuration import ALL_BEHAVIOURS, load_configuration
from cssr_system.animate_behaviour.configuration import shipped_configuration_path, topic_file_path
from cssr_system.animate_behaviour.contract import NODE_NAME, SERVICE_NAME
from cssr_system.animate_behaviour.topics import load_topic_map
from cssr_system.pepper.joint_table import PARTS
from cssr_system.srv import setActivation, setActivationResponse

SIGNALS = {signal.SIGINT, signal.SIGTERM}


def main() -> int:
    # Blocked here, before rospy starts its threads, so that every thread inherits the mask and the signal waits
    # for sigwait below, whichever thread the kernel would have handed it to.
    signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
    rospy.init_node(NODE_NAME, disable_signals=True)
    configuration = load_configuration(shipped_configuration_path(),
                                       {"platform": rospy.get_param("~platform", "robot"),
                                        "behaviour": ALL_BEHAVIOURS})
    topics = load_topic_map(topic_file_path(configuration)).topics
    clients = {key: actionlib.ActionClient(name, FollowJointTrajectoryAction) for key, name in topics.items()
               if key in PARTS}
    handles = []

    def handle(request):
        state = request.state.strip().lower()
        if state == "enabled":
            for key, client in clients.items():
                goal = FollowJointTrajectoryGoal()
                goal.trajectory.joint_names = list(PARTS[key].joints)
                goal.trajectory.points.append(JointTrajectoryPoint(positions=list(PARTS[key].centre),
                                                                   time_from_start=rospy.Duration(1.0)))
                handles.append(client.send_goal(goal))
        elif state == "disabled":
            for goal_handle in handles:
                goal_handle.cancel()
            del handles[:]
        else:
            return setActivationResponse("0")
        return setActivationResponse("1")

    rospy.Service(SERVICE_NAME, setActivation, handle)
    signal.sigwait(SIGNALS)
    for goal_handle in handles:
        goal_handle.cancel()
    time.sleep(0.05)  # the cancels leave through rospy's publisher queues
    rospy.signal_shutdown("signal")
    return 0


if __name__ == "__main__":
    sys.exit(main())
