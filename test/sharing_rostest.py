#!/usr/bin/env python3
"""Sharing the robot (rostest): a second node moves parts while animateBehaviour animates, as gestureExecution,
overtAttention or teleoperation do. This test is that second node: its own actionlib client, its own publishers.

Asserts what the README's "Sharing the robot" promises: the other node's gesture runs to its end (SUCCEEDED); no goal
of ours reaches that controller meanwhile; the other parts keep moving; the part resumes from where the gesture left
it within the quiet time + 0.5 s, under the speed cap, without a velocity jump; a chain of goals counts as one
gesture; a trajectory on the controller's command topic is respected the same way; a Twist on the Wheels topic
pauses our turns and suppresses our return; the status topic shows `yielding` with the other node's caller id;
`set_enabled` works. Private parameter: `platform`.
"""
import os
import sys
import threading
import time
import unittest

import actionlib
import numpy
import rospkg
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from geometry_msgs.msg import Twist, Vector3
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
from wire_recorder import WireRecorder, wait_until

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import load_configuration, topic_file_path
from cssr_system.animate_behaviour.contract import (NODE_NAME, REPLY_SUCCESS, SERVICE_PATH, SET_ENABLED_SERVICE_NAME,
                                                    STATUS_TOPIC)
from cssr_system.animate_behaviour.event_log import read_log
from cssr_system.animate_behaviour.topics import WHEELS_KEY, load_topic_map
from cssr_system.msg import AnimateBehaviourStatus
from cssr_system.pepper.joint_table import PARTS, RELATIVE, command_topic, speed_limit, wheels_command_kind
from cssr_system.srv import setActivation

QUIET_TIME = 1.0  # the shipped yieldQuietTime
RESUME_MARGIN = 0.5  # s: the part resumes within the quiet time + this
OURS = "/" + NODE_NAME
GESTURE_PART = "RArm"
# A velocity jump shows as an acceleration far beyond the planned ones (about 3 rad/s^2 at most here): a step of
# 0.2 rad/s between two 50 Hz samples is 10 rad/s^2.
JUMP_ACCELERATION = 8.0  # rad/s^2
GESTURE_OFFSETS = (-0.25, -0.2, 0.3, 0.2, 0.2)  # rad from the rest centre (RArm joint order), within the limits


def caller(message) -> str:
    return message._connection_header.get("callerid", "")


class SharingTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.platform = rospy.get_param("~platform", "robot")
        rospy.wait_for_service(SERVICE_PATH, timeout=30)
        cls.set_activation = rospy.ServiceProxy(SERVICE_PATH, setActivation, persistent=True)
        cls.set_enabled = rospy.ServiceProxy("/" + SET_ENABLED_SERVICE_NAME, SetBool)
        data_dir = os.path.join(rospkg.RosPack().get_path("cssr_system"), "data")
        config = load_configuration(rospy.get_param("/animateBehaviour/configFile"), {"platform": cls.platform},
                                    data_dir=data_dir)
        cls.topics = dict(load_topic_map(topic_file_path(config, data_dir)).topics)
        cls.wire = WireRecorder(cls.topics)
        wait_until(cls.wire.connected, 10)
        cls.lock = threading.Lock()
        cls.joint_samples = []  # (monotonic time, {name: (position, velocity)})
        cls.statuses = []  # (monotonic time, AnimateBehaviourStatus)
        rospy.Subscriber("/joint_states", JointState, cls._on_joint_state, queue_size=50)
        rospy.Subscriber("/" + STATUS_TOPIC, AnimateBehaviourStatus, cls._on_status, queue_size=50)
        cls.gesture_client = actionlib.SimpleActionClient(cls.topics[GESTURE_PART], FollowJointTrajectoryAction)
        assert cls.gesture_client.wait_for_server(rospy.Duration(10))
        cls.command_publisher = rospy.Publisher(command_topic(cls.topics[GESTURE_PART]), JointTrajectory,
                                                queue_size=1)
        cls.twist_publisher = rospy.Publisher(cls.topics[WHEELS_KEY], Twist, queue_size=10)
        wait_until(lambda: cls.command_publisher.get_num_connections() >= 2
                   and cls.twist_publisher.get_num_connections() >= 2, 10)
        time.sleep(0.5)  # the node's subscribers connect to this node's goal publisher as well

    @classmethod
    def _on_joint_state(cls, message):
        with cls.lock:
            cls.joint_samples.append((time.monotonic(), dict(zip(message.name, zip(message.position,
                                                                                   message.velocity))),
                                      message.header.stamp.to_sec()))

    @classmethod
    def _on_status(cls, message):
        with cls.lock:
            cls.statuses.append((time.monotonic(), message))

    def setUp(self):
        rospy.set_param("/animateBehaviour/behaviour", "body")
        self.assertEqual(self.set_activation("disabled").success, REPLY_SUCCESS)
        time.sleep(2.5)  # the return home ends
        self.wire.clear()

    def tearDown(self):
        self.set_activation("disabled")

    # -- helpers ----------------------------------------------------------------------------------
    def enable(self, behaviour="body", settle=2.0):
        rospy.set_param("/animateBehaviour/behaviour", behaviour)
        self.assertEqual(self.set_activation("enabled").success, REPLY_SUCCESS)
        time.sleep(settle)

    def measured(self, joints):
        with self.lock:
            latest = self.joint_samples[-1][1]
        return [latest[name][0] for name in joints]

    def gesture_trajectory(self, duration, steps):
        """A gesture from where the arm is, out to a pose and back toward it, ending at rest."""
        joints = PARTS[GESTURE_PART].joints
        start = numpy.array(self.measured(joints))
        pose = numpy.array(PARTS[GESTURE_PART].centre) + numpy.array(GESTURE_OFFSETS)
        trajectory = JointTrajectory(joint_names=list(joints))
        for index in range(1, steps + 1):
            fraction = index / steps
            target = pose if fraction <= 0.75 else start + (pose - start) * 0.5
            trajectory.points.append(JointTrajectoryPoint(positions=list(target), velocities=[0.0] * len(joints),
                                                          time_from_start=rospy.Duration(duration * fraction)))
        return trajectory

    def our_goals(self, key, start, end):
        return [at for at, goal_key, message in self.wire.snapshot(self.wire.goals)
                if goal_key == key and caller(message) == OURS and start <= at <= end]

    def first_goal_of_ours_after(self, key, moment, timeout):
        found = []
        wait_until(lambda: found.extend(self.our_goals(key, moment, float("inf"))) or found, timeout)
        return found[0] if found else None

    def statuses_between(self, start, end):
        with self.lock:
            return [status for at, status in self.statuses if start <= at <= end]

    def part_states(self, part, start, end):
        return [(p.state, p.yielding_to) for status in self.statuses_between(start, end)
                for p in status.parts if p.part == part]

    def joint_range(self, key, start, end):
        with self.lock:
            samples = [s for at, s, _ in self.joint_samples if start <= at <= end]
        return max(max(s[name][0] for s in samples) - min(s[name][0] for s in samples) for name in PARTS[key].joints)

    def assert_smooth_resume(self, key, resumed_at):
        """Under the speed cap and without a velocity jump in the 2 s after our first goal."""
        time.sleep(2.0)
        with self.lock:
            samples = [(s, stamp) for at, s, stamp in self.joint_samples if resumed_at - 0.2 <= at <= resumed_at + 2.0]
        self.assertGreater(len(samples), 20)
        stamps = numpy.array([stamp for _, stamp in samples])
        for name in PARTS[key].joints:
            velocities = numpy.array([s[name][1] for s, _ in samples])
            self.assertLessEqual(numpy.max(numpy.abs(velocities)), speed_limit(name) * 1.05,
                                 "%s beyond the speed cap after resuming" % name)
            accelerations = numpy.diff(velocities) / numpy.maximum(numpy.diff(stamps), 1e-3)
            self.assertLessEqual(numpy.max(numpy.abs(accelerations)), JUMP_ACCELERATION,
                                 "%s velocity jumps after resuming" % name)

    def log_events(self, event, since_wall, part=None, wait=0.0):
        """The log's `event` entries since `since_wall` (of `part`, if given); `wait`: seconds to wait for one, as the
        node's log is written by a thread of its own, after the goals that the test has seen already."""
        deadline = time.monotonic() + wait
        while True:
            entries = [e for e in read_log(rospy.get_param("/animateBehaviour/logFile"))
                       if e.event == event and e.timestamp.timestamp() >= since_wall
                       and (part is None or e.fields.get("part") == part)]
            if entries or time.monotonic() >= deadline:
                return entries
            time.sleep(0.05)

    # -- joints -----------------------------------------------------------------------------------
    def test_gesture_goal_runs_to_its_end_and_the_part_resumes(self):
        self.enable()
        since_wall = time.time()
        goal = FollowJointTrajectoryGoal(trajectory=self.gesture_trajectory(4.0, 8))
        sent = time.monotonic()
        self.gesture_client.send_goal(goal)
        self.assertTrue(self.gesture_client.wait_for_result(rospy.Duration(10)))
        ended = time.monotonic()
        self.assertEqual(self.gesture_client.get_state(), GoalStatus.SUCCEEDED,
                         "the other node's gesture ran to its end")
        self.assertEqual(self.our_goals(GESTURE_PART, sent + 0.05, ended), [], "no goal of ours during the gesture")
        other = "LArm"
        self.assertGreater(self.joint_range(other, sent + 0.5, ended), 0.005, "the other arm kept moving")
        self.assertGreater(len(self.our_goals(other, 0, ended)) + len(self.our_goals("Leg", 0, ended)), 0)
        states = self.part_states(GESTURE_PART, sent, ended)
        self.assertIn(("yielding", rospy.get_caller_id()), states, "the status shows whom the arm yields to")
        resumed = self.first_goal_of_ours_after(GESTURE_PART, ended, QUIET_TIME + RESUME_MARGIN + 1.0)
        self.assertIsNotNone(resumed, "the arm resumes")
        self.assertLessEqual(resumed - ended, QUIET_TIME + RESUME_MARGIN)
        self.assertGreaterEqual(resumed - ended, QUIET_TIME - 0.2, "a quiet time before resuming")
        self.assert_smooth_resume(GESTURE_PART, resumed)
        yielded = [e.fields for e in self.log_events(contract.PART_YIELDED, since_wall, GESTURE_PART, wait=5.0)]
        resumed_entries = [e.fields for e in self.log_events(contract.PART_RESUMED, since_wall, GESTURE_PART,
                                                             wait=5.0)]
        self.assertTrue(yielded and resumed_entries, "the yield and the resume are in the log")
        self.assertEqual(yielded[0]["caller"], rospy.get_caller_id())
        self.assertGreater(resumed_entries[0]["seconds"], 4.0)

    def test_a_chain_of_goals_is_one_gesture(self):
        self.enable()
        first_sent = time.monotonic()
        for _ in range(3):
            self.gesture_client.send_goal(FollowJointTrajectoryGoal(trajectory=self.gesture_trajectory(1.0, 2)))
            self.assertTrue(self.gesture_client.wait_for_result(rospy.Duration(5)))
            self.assertEqual(self.gesture_client.get_state(), GoalStatus.SUCCEEDED)
        ended = time.monotonic()
        self.assertEqual(self.our_goals(GESTURE_PART, first_sent + 0.05, ended + QUIET_TIME - 0.2), [])
        resumed = self.first_goal_of_ours_after(GESTURE_PART, ended, QUIET_TIME + RESUME_MARGIN + 1.0)
        self.assertIsNotNone(resumed)
        self.assertLessEqual(resumed - ended, QUIET_TIME + RESUME_MARGIN)

    def test_a_trajectory_on_the_command_topic_is_respected(self):
        self.enable()
        trajectory = self.gesture_trajectory(3.0, 6)
        sent = time.monotonic()
        self.command_publisher.publish(trajectory)
        last_point = sent + 3.0
        time.sleep(1.5)
        pose = numpy.array(PARTS[GESTURE_PART].centre) + numpy.array(GESTURE_OFFSETS)
        numpy.testing.assert_allclose(self.measured(PARTS[GESTURE_PART].joints), pose, atol=0.05,
                                      err_msg="the controller follows the command trajectory")
        self.assertIn(("yielding", rospy.get_caller_id()), self.part_states(GESTURE_PART, sent, time.monotonic()))
        resumed = self.first_goal_of_ours_after(GESTURE_PART, sent + 0.05, 3.0 + QUIET_TIME + RESUME_MARGIN + 1.0)
        self.assertIsNotNone(resumed)
        self.assertGreaterEqual(resumed, last_point + QUIET_TIME - 0.2, "nothing of ours before the last point")
        self.assertLessEqual(resumed - last_point, QUIET_TIME + RESUME_MARGIN)
        self.assert_smooth_resume(GESTURE_PART, resumed)

    def test_disable_while_yielding_sends_nothing_to_that_part(self):
        self.enable()
        self.gesture_client.send_goal(FollowJointTrajectoryGoal(trajectory=self.gesture_trajectory(3.0, 6)))
        time.sleep(0.5)
        disabled = time.monotonic()
        self.assertEqual(self.set_activation("disabled").success, REPLY_SUCCESS)
        self.assertTrue(self.gesture_client.wait_for_result(rospy.Duration(6)))
        self.assertEqual(self.gesture_client.get_state(), GoalStatus.SUCCEEDED)
        time.sleep(QUIET_TIME + RESUME_MARGIN)
        self.assertEqual(self.our_goals(GESTURE_PART, disabled - 0.4, time.monotonic()), [])
        self.assertEqual([c for c in self.wire.snapshot(self.wire.cancels) if c[1] == GESTURE_PART
                          and c[0] >= disabled - 0.4], [], "no cancel either")
        self.assertGreater(len(self.our_goals("LArm", disabled, time.monotonic())), 0, "the other arm went home")

    # -- base -------------------------------------------------------------------------------------
    def foreign_turn(self):
        """A small turn by another node: one relative command, or a velocity streamed for 1 s."""
        if wheels_command_kind(self.topics[WHEELS_KEY]) == RELATIVE:
            self.twist_publisher.publish(Twist(angular=Vector3(z=0.1)))
            return 0.1 + 1.0  # the driver's turn time and settle time
        for _ in range(10):
            self.twist_publisher.publish(Twist(angular=Vector3(z=0.1)))
            time.sleep(0.1)
        return 0.5  # the velocity time-out

    def our_twists(self, start, end):
        return [at for at, _, message in self.wire.snapshot(self.wire.twists)
                if caller(message) == OURS and start <= at <= end]

    def test_a_foreign_twist_pauses_our_turns_and_suppresses_our_return(self):
        self.enable("rotation", settle=1.0)
        since_wall = time.time()
        started = time.monotonic()
        busy = self.foreign_turn()
        foreign_end = time.monotonic() + busy
        states = self.part_states(WHEELS_KEY, started, time.monotonic() + 0.2)
        time.sleep(0.3)
        states = self.part_states(WHEELS_KEY, started, time.monotonic())
        self.assertIn(("yielding", rospy.get_caller_id()), states)
        first_ours = min(self.our_twists(started + 0.1, float("inf")) or [float("inf")])
        # On a velocity topic the interrupted turn is not ended with a zero of ours: the other node commands.
        self.assertTrue(first_ours == float("inf") or first_ours >= foreign_end + QUIET_TIME - 0.2,
                        "a turn of ours while the other node commands the base")
        disabled = time.monotonic()
        self.assertEqual(self.set_activation("disabled").success, REPLY_SUCCESS)
        time.sleep(1.5)
        if disabled < foreign_end + QUIET_TIME:  # disabled while yielding: no return at all
            self.assertEqual(self.our_twists(disabled, time.monotonic()), [])
        returns = [e for e in self.log_events(contract.BASE_COMMAND, since_wall)
                   if e.fields["purpose"] == contract.PURPOSE_HOME]
        self.assertEqual(returns, [], "the return is suppressed")

    # -- services and status ------------------------------------------------------------------------
    def test_set_enabled_and_the_status_topic(self):
        response = self.set_enabled(True)
        self.assertTrue(response.success, response.message)
        time.sleep(1.0)
        with self.lock:
            latest = self.statuses[-1][1]
        self.assertTrue(latest.enabled)
        self.assertIn("animating", [p.state for p in latest.parts])
        self.assertGreater(len(self.wire.snapshot(self.wire.goals)), 0)
        response = self.set_enabled(False)
        self.assertTrue(response.success, response.message)
        time.sleep(0.3)
        with self.lock:
            latest = self.statuses[-1][1]
        self.assertFalse(latest.enabled)
        self.assertTrue(all(p.state in ("idle", "homing") for p in latest.parts))
        # Latched: a late subscriber gets the current status at once.
        late = rospy.wait_for_message("/" + STATUS_TOPIC, AnimateBehaviourStatus, timeout=2)
        self.assertFalse(late.enabled)


if __name__ == "__main__":
    rospy.init_node("sharing_test")
    rostest.rosrun("cssr_system", "sharing_" + rospy.get_param("~platform", "robot"), SharingTest, sys.argv)
