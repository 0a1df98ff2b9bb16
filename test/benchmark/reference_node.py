#!/usr/bin/env python3
"""The benchmark's yardstick: a minimal rospy node with animateBehaviour's interface and nothing else. It serves
`setActivation`, holds one action client per controller of the platform's topic file, sends each a one-point goal
to its centre on `enabled`, cancels them on `disabled`, and exits on SIGINT or SIGTERM. Measured with the same
code as the node (`benchmark.py`), its figures show what rospy itself costs on the machine at hand."""
import signal
import sys
import threading

import actionlib
import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system.animate_behaviour.contract import NODE_NAME, SERVICE_NAME
from cssr_system.animate_behaviour.topics import load_topic_map
from cssr_system.package_files import data_dir
from cssr_system.pepper.joint_table import PARTS
from cssr_system.srv import setActivation, setActivationResponse


def main() -> int:
    rospy.init_node(NODE_NAME, disable_signals=True)
    topic_file = "pepperTopics.dat" if rospy.get_param("~platform", "robot") == "robot" else "simulatorTopics.dat"
    topics = load_topic_map("%s/%s" % (data_dir(), topic_file)).topics
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
    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda number, frame: stop.set())
    signal.signal(signal.SIGTERM, lambda number, frame: stop.set())
    while not stop.wait(1.0) and not rospy.is_shutdown():
        pass
    for goal_handle in handles:
        goal_handle.cancel()
    rospy.signal_shutdown("signal")
    return 0


if __name__ == "__main__":
    sys.exit(main())
