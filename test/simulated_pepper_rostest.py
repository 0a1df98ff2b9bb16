#!/usr/bin/env python3
"""rostest of scripts/simulatedPepper.py over real ROS: action servers, /joint_states, base, odometry.

The platform under test is this test node's private parameter ~platform ("robot" or "simulator");
the .test file starts simulatedPepper with the same value.
"""
import math
import threading
import time
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryGoal,
                              FollowJointTrajectoryResult)
from geometry_msgs.msg import Twist, Vector3
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from std_msgs.msg import UInt32
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system.pepper.joint_table import (BASE_MAX_ANGULAR_ACCELERATION, BASE_MOVETO_ANGULAR_VELOCITY,
                                            BASE_VELOCITY_COMMAND_TIMEOUT, JOINTS, PARTS, WHEEL_JOINTS)

PACKAGE = "cssr_system"
SERVER_TIMEOUT = 10.0  # s; the node starts in well under 2 s, but the test machine may be busy
ARM = PARTS["RArm"]
ARM_TARGET = (1.0, -0.4, 0.6, 1.2, 0.3)  # ARM.joints order, inside the limits

EXPECTED_SERVERS = {
    "robot": ["/pepper_dcm/RightArm_controller/follow_joint_trajectory",
              "/pepper_dcm/LeftArm_controller/follow_joint_trajectory",
              "/pepper_dcm/RightHand_controller/follow_joint_trajectory",
              "/pepper_dcm/LeftHand_controller/follow_joint_trajectory",
              "/pepper_dcm/Pelvis_controller/follow_joint_trajectory",
              "/pepper_dcm/Head_controller/follow_joint_trajectory"],
    "simulator": ["/pepper/RightArm_controller/follow_joint_trajectory",
                  "/pepper/LeftArm_controller/follow_joint_trajectory",
                  "/pepper/Pelvis_controller/follow_joint_trajectory",
                  "/pepper/Head_controller/follow_joint_trajectory"],
}
NAMESPACES = {"robot": "/pepper_dcm", "simulator": "/pepper"}


def trajectory_goal(joints, points):
    """A goal starting now; points: (time_from_start, positions[, velocities])."""
    goal = FollowJointTrajectoryGoal()
    goal.trajectory.joint_names = list(joints)
    for entry in points:
        goal.trajectory.points.append(JointTrajectoryPoint(
            positions=list(entry[1]), velocities=list(entry[2]) if len(entry) > 2 else [],
            time_from_start=rospy.Duration.from_sec(entry[0])))
    return goal


def yaw(odometry: Odometry) -> float:
    orientation = odometry.pose.pose.orientation
    return 2.0 * math.atan2(orientation.z, orientation.w)


def angle_difference(a: float, b: float) -> float:
    return math.remainder(a - b, 2.0 * math.pi)


class Latest:
    """The latest message of a topic, with the arrival times of all messages."""

    def __init__(self, topic, message_type):
        self._lock = threading.Lock()
        self.message = None
        self.arrivals = []
        self._subscriber = rospy.Subscriber(topic, message_type, self._store, queue_size=50)

    def _store(self, message):
        with self._lock:
            self.message = message
            self.arrivals.append(time.monotonic())

    def wait(self, timeout=5.0, after=None):
        """The first message received after time.monotonic() `after` (default: now)."""
        after = time.monotonic() if after is None else after
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self._lock:
                if self.arrivals and self.arrivals[-1] > after:
                    return self.message
            time.sleep(0.005)
        raise AssertionError("no message within {} s".format(timeout))

    def count_between(self, start, end):
        with self._lock:
            return sum(1 for arrival in self.arrivals if start <= arrival < end)


class SimulatedPepperTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.platform = rospy.get_param("~platform", "robot")
        cls.namespace = NAMESPACES[cls.platform]
        cls.joint_states = Latest("/joint_states", JointState)
        cls.odometry = Latest(cls.namespace + "/odom", Odometry)
        cls.violations = Latest("/simulatedPepper/limit_violations", UInt32)
        cls.arm_server = cls.namespace + "/RightArm_controller/follow_joint_trajectory"

    def client(self, namespace=None):
        client = actionlib.SimpleActionClient(namespace or self.arm_server, FollowJointTrajectoryAction)
        self.assertTrue(client.wait_for_server(rospy.Duration(SERVER_TIMEOUT)), namespace or self.arm_server)
        return client

    def joint_positions(self, message):
        return dict(zip(message.name, message.position))

    def test_action_servers_are_named_as_on_the_platform(self):
        for namespace in EXPECTED_SERVERS[self.platform]:
            self.client(namespace)
        topics = [name for name, _ in rospy.get_published_topics()]
        served = sorted(set(name.rsplit("/", 1)[0]
                        for name in topics if name.endswith("/follow_joint_trajectory/status")))
        self.assertEqual(served, sorted(EXPECTED_SERVERS[self.platform]))
        if self.platform == "simulator":
            self.assertFalse([name for name in topics if "Hand_controller" in name])

    def test_a_valid_goal_succeeds_and_joint_states_show_it(self):
        client = self.client()
        client.send_goal(trajectory_goal(ARM.joints, [(1.0, ARM_TARGET)]))
        self.assertTrue(client.wait_for_result(rospy.Duration(5.0)))
        self.assertEqual(client.get_state(), GoalStatus.SUCCEEDED)
        self.assertEqual(client.get_result().error_code, FollowJointTrajectoryResult.SUCCESSFUL)
        positions = self.joint_positions(self.joint_states.wait())
        for joint, target in zip(ARM.joints, ARM_TARGET):
            self.assertAlmostEqual(positions[joint], target, places=6, msg=joint)

    def test_a_goal_with_wrong_joints_is_rejected(self):
        # A plain ActionClient: SimpleActionClient can miss transitions that arrive before its send_goal
        # returns (ros/actionlib#206), and a rejection arrives that fast.
        client = actionlib.ActionClient(self.arm_server, FollowJointTrajectoryAction)
        self.assertTrue(client.wait_for_server(rospy.Duration(SERVER_TIMEOUT)))
        handle = client.send_goal(trajectory_goal(ARM.joints[:-1] + ("LHand",), [(1.0, ARM_TARGET)]))
        deadline = time.monotonic() + 5.0
        while handle.get_comm_state() != actionlib.CommState.DONE and time.monotonic() < deadline:
            time.sleep(0.01)
        self.assertEqual(handle.get_goal_status(), GoalStatus.REJECTED)
        result = handle.get_result()
        self.assertEqual(result.error_code, FollowJointTrajectoryResult.INVALID_JOINTS)
        self.assertIn(ARM.joints[-1], result.error_string)
        self.assertIn("LHand", result.error_string)

    def test_a_second_goal_preempts_the_first(self):
        first, second = self.client(), self.client()
        first.send_goal(trajectory_goal(ARM.joints, [(3.0, ARM.centre)]))
        rospy.sleep(0.5)
        second.send_goal(trajectory_goal(ARM.joints, [(1.0, ARM_TARGET)]))
        self.assertTrue(first.wait_for_result(rospy.Duration(5.0)))
        self.assertEqual(first.get_state(), GoalStatus.PREEMPTED)
        self.assertTrue(second.wait_for_result(rospy.Duration(5.0)))
        self.assertEqual(second.get_state(), GoalStatus.SUCCEEDED)

    def test_cancel_holds_the_position(self):
        client = self.client()
        start = self.joint_positions(self.joint_states.wait())[ARM.joints[0]]
        target = -1.0 if start > 0.0 else 1.0
        goal_positions = (target,) + tuple(ARM.centre[1:])
        client.send_goal(trajectory_goal(ARM.joints, [(3.0, goal_positions)]))
        rospy.sleep(1.0)
        client.cancel_goal()
        self.assertTrue(client.wait_for_result(rospy.Duration(5.0)))
        self.assertEqual(client.get_state(), GoalStatus.PREEMPTED)
        held = self.joint_states.wait()
        rospy.sleep(0.5)
        later = self.joint_states.wait()
        index = later.name.index(ARM.joints[0])
        self.assertAlmostEqual(later.position[index], held.position[index], places=9)
        self.assertEqual(later.velocity[index], 0.0)
        self.assertGreater(abs(later.position[index] - target), 0.3)  # stopped on the way
        self.assertGreater(abs(later.position[index] - start), 0.05)  # but it had moved

    def test_a_goal_beyond_the_limits_is_executed_clamped_and_counted(self):
        before = self.violations.wait(timeout=5.0, after=0.0).data
        roll = ARM.joints.index("RShoulderRoll")
        beyond = list(ARM.centre)
        beyond[roll] = JOINTS["RShoulderRoll"].upper + 0.3
        client = self.client()
        client.send_goal(trajectory_goal(ARM.joints, [(0.5, beyond)]))
        self.assertTrue(client.wait_for_result(rospy.Duration(5.0)))
        self.assertEqual(client.get_state(), GoalStatus.SUCCEEDED)
        deadline = time.monotonic() + 3.0
        while self.violations.message.data == before and time.monotonic() < deadline:
            time.sleep(0.01)
        self.assertEqual(self.violations.message.data, before + 1)
        positions = self.joint_positions(self.joint_states.wait())
        self.assertAlmostEqual(positions["RShoulderRoll"], JOINTS["RShoulderRoll"].upper, places=9)

    def test_joint_states_hold_every_joint_at_about_50_hz(self):
        message = self.joint_states.wait()
        self.assertEqual(list(message.name), list(JOINTS) + list(WHEEL_JOINTS))
        self.assertEqual(len(message.velocity), len(message.name))
        self.assertGreater(message.header.stamp.to_sec(), 0.0)
        start = time.monotonic()
        rospy.sleep(2.0)
        rate = self.joint_states.count_between(start, start + 2.0) / 2.0
        self.assertTrue(30.0 <= rate <= 70.0, rate)
        positions = self.joint_positions(message)
        if self.platform == "simulator":  # no hand controllers: the hands stay at their centre
            self.assertAlmostEqual(positions["RHand"], PARTS["RHand"].centre[0])
            self.assertAlmostEqual(positions["LHand"], PARTS["LHand"].centre[0])

    def test_the_base_turns_as_the_platform_does(self):
        odometry = self.odometry.wait()
        self.assertEqual((odometry.header.frame_id, odometry.child_frame_id), ("odom", "base_footprint"))
        publisher = rospy.Publisher(self.namespace + ("/cmd_moveto" if self.platform == "robot" else "/cmd_vel"),
                                    Twist, queue_size=10)
        deadline = time.monotonic() + 5.0
        while publisher.get_num_connections() == 0 and time.monotonic() < deadline:
            time.sleep(0.01)
        if self.platform == "robot":
            self.check_moveto(publisher)
        else:
            self.check_cmd_vel(publisher)

    def check_moveto(self, publisher):
        start = yaw(self.odometry.wait())
        angle = 0.5
        publisher.publish(Twist(angular=Vector3(z=angle)))
        rospy.sleep(0.1)
        moving = self.odometry.wait()
        self.assertAlmostEqual(moving.twist.twist.angular.z, BASE_MOVETO_ANGULAR_VELOCITY, places=6)
        publisher.publish(Twist(angular=Vector3(z=-1.0)))  # busy: dropped
        rospy.sleep(angle / BASE_MOVETO_ANGULAR_VELOCITY + 0.2)
        end = self.odometry.wait()
        self.assertAlmostEqual(angle_difference(yaw(end), start), angle, delta=0.01)
        self.assertEqual(end.twist.twist.angular.z, 0.0)
        rospy.sleep(0.5)
        self.assertAlmostEqual(angle_difference(yaw(self.odometry.wait()), start), angle, delta=0.01)

    def check_cmd_vel(self, publisher):
        speed = 0.5
        command = Twist()
        command.angular.z = speed
        for _ in range(10):  # 1 s at 10 Hz
            publisher.publish(command)
            rospy.sleep(0.1)
        last = time.monotonic()
        self.assertAlmostEqual(self.odometry.wait().twist.twist.angular.z, speed, places=6)
        # Still turning just before the time-out, stopped after it and the deceleration.
        rospy.sleep(BASE_VELOCITY_COMMAND_TIMEOUT - 0.15)
        self.assertGreater(self.odometry.wait().twist.twist.angular.z, 0.4)
        stop = last + BASE_VELOCITY_COMMAND_TIMEOUT + speed / BASE_MAX_ANGULAR_ACCELERATION
        rospy.sleep(max(0.0, stop + 0.2 - time.monotonic()))
        stopped = self.odometry.wait()
        self.assertEqual(stopped.twist.twist.angular.z, 0.0)
        rospy.sleep(0.3)
        self.assertAlmostEqual(angle_difference(yaw(self.odometry.wait()), yaw(stopped)), 0.0, places=9)


if __name__ == "__main__":
    rospy.init_node("simulated_pepper_test")
    # One result file per platform: the name carries it.
    rostest.rosrun(PACKAGE, "simulated_pepper_" + rospy.get_param("~platform", "robot"), SimulatedPepperTest)
