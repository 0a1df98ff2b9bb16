#!/usr/bin/env python3
"""Live settings and the animate action (rostest; README: "Live settings", "The animate action"), on the simulator
interface of the simulated Pepper, breathing style: dynamic_reconfigure sets each setting and refuses an invalid one;
an intensity change mid-run brings every part into its new bands without a stop or a velocity jump; the base
switched off sends no Twist afterwards; an action goal with a duration ends SUCCEEDED on time with every part at its
centre; a second goal preempts the first without stopping the robot, with feedback once a second; cancelling stops
the motion."""
import datetime
import os
import sys
import threading
import time
import unittest

import actionlib
import dynamic_reconfigure.client
import numpy
import rospkg
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import Twist
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import load_configuration, shipped_configuration_path
from cssr_system.animate_behaviour.contract import NODE_NAME, REPLY_SUCCESS, SERVICE_PATH
from cssr_system.animate_behaviour.event_log import read_log
from cssr_system.motion.waypoints import animated_parts
from cssr_system.msg import AnimateAction, AnimateBehaviourStatus, AnimateGoal
from cssr_system.pepper.joint_table import PARTS, centre_of
from cssr_system.srv import setActivation

NODE = "/" + NODE_NAME
PARTS_HERE = ("RArm", "LArm", "Leg")  # the simulator has no hand controllers
SETTLE = 4.0  # s after a change for the new goal to ease into the new bands
BAND_TOLERANCE = 2e-3
JUMP_ACCELERATION = 8.0  # rad/s^2 between 50 Hz samples: far beyond the planned motion, a velocity jump
DURATION_TOLERANCE = 0.3  # s
CENTRE_TOLERANCE = 0.01  # rad


class InteractionTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.wait_for_service(SERVICE_PATH, timeout=30)
        cls.call = rospy.ServiceProxy(SERVICE_PATH, setActivation)
        cls.settings = dynamic_reconfigure.client.Client(NODE, timeout=30)
        cls.action = actionlib.SimpleActionClient(NODE + "/animate", AnimateAction)
        assert cls.action.wait_for_server(rospy.Duration(30))
        cls.lock = threading.Lock()
        cls.samples, cls.twists, cls.statuses = [], [], []
        rospy.Subscriber("/joint_states", JointState, cls.on_joint_states, queue_size=100)
        rospy.Subscriber("/pepper/cmd_vel", Twist, cls.on_twist, queue_size=100)
        rospy.Subscriber(NODE + "/status", AnimateBehaviourStatus, cls.on_status, queue_size=100)
        cls.data = os.path.join(rospkg.RosPack().get_path("cssr_system"), "data")

    @classmethod
    def on_joint_states(cls, message):
        with cls.lock:
            cls.samples.append((time.monotonic(), dict(zip(message.name, zip(message.position, message.velocity)))))

    @classmethod
    def on_twist(cls, message):
        with cls.lock:
            cls.twists.append((time.monotonic(), message._connection_header.get("callerid", "")))

    @classmethod
    def on_status(cls, message):
        with cls.lock:
            cls.statuses.append((time.monotonic(), message))

    def setUp(self):
        self.settings.update_configuration({"intensity": 1.0, "base": True, "arms": True, "hands": True,
                                            "leg": True, "style": "breathing"})

    def tearDown(self):
        self.action.cancel_all_goals()
        self.call("disabled")
        time.sleep(1.5)

    def window(self, start, end):
        with self.lock:
            return [joints for at, joints in self.samples if start <= at <= end]

    def bands(self, **overrides):
        settings = dict(platform="simulator", behaviour="all", motionStyle="breathing", **overrides)
        config = load_configuration(rospy.get_param(NODE + "/configFile", shipped_configuration_path()), settings,
                                    data_dir=self.data)
        return [bounds for motion in animated_parts(config, PARTS_HERE) for bounds in motion.bounds]

    def assert_smooth(self, joints_list, what):
        for name in [joint for part in PARTS_HERE for joint in PARTS[part].joints]:
            velocities = numpy.array([joints[name][1] for joints in joints_list])
            self.assertLessEqual(numpy.abs(numpy.diff(velocities)).max() / 0.02, JUMP_ACCELERATION, what + name)

    def assert_at_centre(self):
        latest = self.window(time.monotonic() - 0.2, time.monotonic())[-1]
        for part in PARTS_HERE:
            for name in PARTS[part].joints:
                self.assertAlmostEqual(latest[name][0], centre_of(name), delta=CENTRE_TOLERANCE, msg=name)

    def test_dynamic_reconfigure_sets_each_setting_and_refuses_an_invalid_one(self):
        since = datetime.datetime.now()
        changes = {"intensity": 0.4, "tempo": 8.0, "style": "random", "arms": False, "hands": False, "leg": False,
                   "base": False}
        for name, value in changes.items():
            self.assertEqual(self.settings.update_configuration({name: value})[name], value, name)
        self.assertEqual(self.settings.update_configuration({"style": "dance"})["style"], "random",
                         "an unknown style is refused and nothing changes")
        time.sleep(0.5)
        with self.lock:
            status = self.statuses[-1][1]
        self.assertEqual((round(status.intensity, 3), status.tempo, status.motion_style, list(status.moving_parts)),
                         (0.4, 8.0, "random", []))
        self.assertEqual(status.settings_by, "dynamic_reconfigure")
        logged = [entry.fields for entry in read_log(rospy.get_param(NODE + "/logFile"), since=since)
                  if entry.event == contract.SETTING_CHANGED]
        self.assertEqual(len(logged), len(changes), logged)
        self.assertEqual({entry["by"] for entry in logged}, {"dynamic_reconfigure"})
        self.assertEqual(self.settings.update_configuration({"tempo": 12.0, "style": "breathing"})["tempo"], 12.0)

    def test_an_intensity_change_mid_run_narrows_every_band_without_a_stop(self):
        self.assertEqual(self.call("enabled").success, REPLY_SUCCESS)
        time.sleep(SETTLE)
        changed = time.monotonic()
        self.settings.update_configuration({"intensity": 0.3})
        time.sleep(SETTLE + 4.0)
        after = self.window(changed + SETTLE, time.monotonic())
        self.assertGreater(len(after), 100)
        for bounds in self.bands(intensity=0.3):
            positions = [joints[bounds.name][0] for joints in after]
            self.assertGreaterEqual(min(positions), bounds.lower - BAND_TOLERANCE, bounds.name)
            self.assertLessEqual(max(positions), bounds.upper + BAND_TOLERANCE, bounds.name)
        self.assert_smooth(self.window(changed - 1.0, time.monotonic()), "no velocity jump at the change: ")
        with self.lock:
            states = {part.state for at, status in self.statuses if at > changed for part in status.parts
                      if part.part != "Wheels"}
        self.assertEqual(states, {"animating"}, "no part stopped or went home")

    def test_the_base_switched_off_sends_no_twist_afterwards(self):
        self.assertEqual(self.call("enabled").success, REPLY_SUCCESS)
        deadline = time.monotonic() + 15.0
        while time.monotonic() < deadline and not any(caller == NODE for _, caller in self.twists):
            time.sleep(0.1)  # the breathing style turns rarely: wait for a turn
        self.settings.update_configuration({"base": False})
        switched = time.monotonic()
        time.sleep(6.0)
        with self.lock:
            ours = [at for at, caller in self.twists if caller == NODE and at > switched + 0.2]
        self.assertEqual(ours, [], "no Twist of ours once the base is switched off")

    def test_a_goal_with_a_duration_succeeds_on_time_with_every_part_home(self):
        """At intensity 1 the parts are far from their centres and moving when the duration ends, each style, and the
        timed goal replaced another a moment before: each part starts back when its own return needs."""
        for style in ("random", "breathing"):
            replaced = actionlib.SimpleActionClient(NODE + "/animate", AnimateAction)
            self.assertTrue(replaced.wait_for_server(rospy.Duration(10)))
            replaced.send_goal(AnimateGoal(intensity=1.0, style=style))
            time.sleep(1.0)
            started = time.monotonic()
            self.action.send_goal(AnimateGoal(intensity=1.0, style=style, duration=4.0))
            self.assertTrue(self.action.wait_for_result(rospy.Duration(15)))
            ended = time.monotonic() - started
            self.assertEqual(self.action.get_state(), GoalStatus.SUCCEEDED, style)
            self.assertEqual(self.action.get_result().reason, "duration elapsed")
            self.assertAlmostEqual(ended, 4.0, delta=DURATION_TOLERANCE, msg=style)
            self.assertAlmostEqual(self.action.get_result().animated, 4.0, delta=DURATION_TOLERANCE, msg=style)
            self.assert_at_centre()
            with self.lock:
                states = {part.part: part.state for part in self.statuses[-1][1].parts}
            self.assertEqual(set(states.values()), {"idle"}, "every part and the base back: %s" % states)
            self.assertEqual(replaced.get_state(), GoalStatus.PREEMPTED)

    def test_a_second_goal_preempts_the_first_without_a_stop(self):
        first = actionlib.SimpleActionClient(NODE + "/animate", AnimateAction)
        self.assertTrue(first.wait_for_server(rospy.Duration(10)))
        first.send_goal(AnimateGoal(intensity=1.0))
        time.sleep(SETTLE)
        switched = time.monotonic()
        feedback = []
        self.action.send_goal(AnimateGoal(intensity=0.5, parts=["arms", "hands", "leg"], style="random"),
                              feedback_cb=feedback.append)
        self.assertTrue(first.wait_for_result(rospy.Duration(5)))
        self.assertEqual(first.get_state(), GoalStatus.PREEMPTED)
        self.assertEqual(first.get_result().reason, "replaced")
        time.sleep(3.0)
        with self.lock:
            states = {part.state for at, status in self.statuses if at > switched for part in status.parts
                      if part.part != "Wheels"}
        self.assertEqual(states, {"animating"}, "the motion goes on")
        self.assert_smooth(self.window(switched - 1.0, time.monotonic()), "no velocity jump at the switch: ")
        self.assertEqual(self.action.get_state(), GoalStatus.ACTIVE)
        self.assertGreaterEqual(len(feedback), 2, "feedback about once a second")
        self.assertEqual({part.part for part in feedback[-1].parts}, set(PARTS_HERE) | {"Wheels"})
        self.assertGreater(feedback[-1].elapsed, 1.0)

    def test_a_goal_that_names_no_part_moves_every_part_the_base_too(self):
        since = datetime.datetime.now()
        self.action.send_goal(AnimateGoal(intensity=0.7))
        time.sleep(1.0)
        with self.lock:
            status = self.statuses[-1][1]
        self.assertTrue(status.enabled)
        self.assertIn("base", status.moving_parts, "a goal that names no part moves the base too")
        self.assertEqual([entry for entry in read_log(rospy.get_param(NODE + "/logFile"), since=since)
                          if entry.event == contract.SETTING_CHANGED and entry.fields["key"] == "turnBase"], [])
        self.action.cancel_goal()
        self.assertTrue(self.action.wait_for_result(rospy.Duration(5)))

    def test_a_goal_naming_an_unknown_part_is_rejected_with_the_reason(self):
        self.action.send_goal(AnimateGoal(intensity=0.5, parts=["head"]))
        self.assertTrue(self.action.wait_for_result(rospy.Duration(5)))
        self.assertEqual(self.action.get_state(), GoalStatus.REJECTED)
        self.assertIn("unknown part 'head'", self.action.get_result().reason)

    def test_no_deprecated_actionlib_parameter(self):
        self.assertFalse(rospy.has_param(NODE + "/animate/status_frequency"), "actionlib warns about it")
        self.assertEqual(rospy.get_param(NODE + "/actionlib_status_frequency"), 1.0)

    def test_cancelling_stops_the_motion(self):
        self.action.send_goal(AnimateGoal(intensity=1.0))
        time.sleep(2.0)
        self.action.cancel_goal()
        self.assertTrue(self.action.wait_for_result(rospy.Duration(5)))
        self.assertEqual(self.action.get_state(), GoalStatus.PREEMPTED)
        self.assertEqual(self.action.get_result().reason, "cancelled")
        time.sleep(1.5)
        with self.lock:
            status = self.statuses[-1][1]
        self.assertFalse(status.enabled)
        self.assertEqual({part.state for part in status.parts}, {"idle"})
        self.assert_at_centre()


if __name__ == "__main__":
    rospy.init_node("interaction_test")
    rostest.rosrun("cssr_system", "interaction", InteractionTest, sys.argv)
