#!/usr/bin/env python3
"""Several robots on one graph (rostest, README: "Several robots"): two simulated Peppers and two animateBehaviour
nodes in /robot1 and /robot2 (several_robots.test). Asserts that enabling one robot moves only that robot, that with
both enabled neither yields to the other, that disabling one leaves the other animating, that the two nodes' log
lines never mix, that a renamed node's service is under its new name, and that a remapped arm still yields to
another node's goal, which SUCCEEDS.
"""
import os
import sys
import time
import unittest

import actionlib
import rosgraph
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectoryPoint
from wire_recorder import wait_until

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.event_log import read_log
from cssr_system.msg import AnimateBehaviourStatus
from cssr_system.pepper.joint_table import PARTS, centre_of
from cssr_system.recording.robot_watch import RobotWatch
from cssr_system.srv import setActivation

NODES = {"robot1": "/robot1/animateBehaviour", "robot2": "/robot2/animateRobot2"}
REMAPPED_ARM = "/robot1/right_arm/follow_joint_trajectory"  # robot1's RArm controller, remapped in the launch
MOVED = 0.005  # rad: a joint that travelled more than this moved
WATCH = 3.0  # s of motion looked at per step


class Robot(RobotWatch):
    """What one robot's joints did, and what its node says, as seen from outside."""

    def __init__(self, name: str) -> None:
        super().__init__()
        self.node = NODES[name]
        rospy.Subscriber("/%s/joint_states" % name, JointState,
                         lambda message: self.joint_states(message.name, message.position), queue_size=50)
        rospy.Subscriber(contract.interface_of(self.node, contract.STATUS), AnimateBehaviourStatus, self.status,
                         queue_size=50)
        service = contract.interface_of(self.node, contract.SET_ACTIVATION)
        rospy.wait_for_service(service, timeout=30)
        self.set_activation = rospy.ServiceProxy(service, setActivation)


class SeveralRobotsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.robots = {name: Robot(name) for name in NODES}
        assert wait_until(lambda: all(robot.samples for robot in cls.robots.values()), 20)

    def test_each_robot_animates_stops_and_yields_on_its_own(self):
        robot1, robot2 = self.robots["robot1"], self.robots["robot2"]
        self.assertEqual(robot1.set_activation("enabled").success, contract.REPLY_SUCCESS)
        start = time.monotonic()
        time.sleep(WATCH)
        self.assertGreater(robot1.travel(start), MOVED, "robot1 moves once enabled")
        self.assertLess(robot2.travel(start), MOVED, "robot2 stays still: only robot1 was enabled")

        statuses = len(robot1.statuses), len(robot2.statuses)
        self.assertEqual(robot2.set_activation("enabled").success, contract.REPLY_SUCCESS)
        start = time.monotonic()
        time.sleep(WATCH)
        self.assertGreater(robot2.travel(start), MOVED, "robot2 moves once enabled")
        self.assertEqual(robot1.yielding_since(statuses[0]) + robot2.yielding_since(statuses[1]), [],
                         "neither robot yields to the other")

        self.assertEqual(robot1.set_activation("disabled").success, contract.REPLY_SUCCESS)
        time.sleep(2.5)  # the return home (at most 2 s) ends
        start = time.monotonic()
        time.sleep(WATCH)
        self.assertLess(robot1.travel(start), MOVED, "robot1 rests once disabled")
        self.assertGreater(robot2.travel(start), MOVED, "robot2 still animates")
        self.assertEqual(robot2.set_activation("disabled").success, contract.REPLY_SUCCESS)

    def test_a_renamed_node_offers_its_service_under_its_new_name(self):
        names = [name for name, _ in rospy.get_published_topics()]
        services = rosservice_names()
        self.assertIn("/robot2/animateRobot2/setActivation", services)
        self.assertIn("/robot2/animateRobot2/set_enabled", services)
        self.assertNotIn("/robot2/animateBehaviour/setActivation", services)
        self.assertIn("/robot2/animateRobot2/status", names)

    def test_the_two_nodes_never_write_into_one_log_file(self):
        asked = rospy.get_param("~log_file")  # a new name at every launch
        (first,) = started_in(asked)  # one node holds the file asked for; the other writes beside it
        (second,) = set(NODES.values()) - {first}
        beside = os.path.join(os.path.dirname(asked), second.strip("/").replace("/", "_") + "LogFile.log")
        self.assertEqual(started_in(beside), {second})

    def test_a_remapped_arm_yields_to_another_nodes_goal_which_succeeds(self):
        robot1 = self.robots["robot1"]
        self.assertEqual(robot1.set_activation("enabled").success, contract.REPLY_SUCCESS)
        try:
            client = actionlib.SimpleActionClient(REMAPPED_ARM, FollowJointTrajectoryAction)
            self.assertTrue(client.wait_for_server(rospy.Duration(10)))
            time.sleep(1.0)  # our goals are running on the arm
            count = len(robot1.statuses)
            client.send_goal(gesture_goal())
            self.assertTrue(client.wait_for_result(rospy.Duration(15)))
            self.assertEqual(client.get_state(), GoalStatus.SUCCEEDED, client.get_goal_status_text())
            yielded = robot1.yielding_since(count)
            self.assertIn("RArm", [part for part, _ in yielded])
            self.assertTrue(all(caller == rospy.get_name() for part, caller in yielded if part == "RArm"), yielded)
        finally:
            robot1.set_activation("disabled")


def started_in(path: str) -> set:
    """The nodes that wrote node_started into the log file at `path`."""
    return {entry.fields["node"] for entry in read_log(path) if entry.event == contract.NODE_STARTED}


def gesture_goal() -> FollowJointTrajectoryGoal:
    """A 3 s gesture of the right arm to its centre and back, as another node would send it."""
    joints = PARTS["RArm"].joints
    centre = [centre_of(joint) for joint in joints]
    raised = [value + (0.2 if index == 0 else 0.0) for index, value in enumerate(centre)]
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = list(joints)
    goal.trajectory.points = [JointTrajectoryPoint(positions=raised, time_from_start=rospy.Duration(1.5)),
                              JointTrajectoryPoint(positions=centre, time_from_start=rospy.Duration(3.0))]
    return goal


def rosservice_names():
    _, _, services = rosgraph.Master(rospy.get_name()).getSystemState()
    return {name for name, _ in services}


if __name__ == "__main__":
    rospy.init_node("several_robots_test")
    rostest.rosrun("cssr_system", "several_robots", SeveralRobotsTest, sys.argv)
