#!/usr/bin/env python3
"""The controller's verdicts (rostest; README: "Controllers: what each goal carries"). The simulated Pepper judges
goals as joint_trajectory_controller does with Pepper's default constraints (goal_time 0, stopped velocity 0.01) and
reports velocity as a difference of positions over its control period (as a simulator does), at the control rate the
.test file sets. Each style animates for `~run_for` s, then a disable sends every part home: every goal of ours ends
SUCCEEDED, or PREEMPTED by our own next goal; none is ABORTED."""
import datetime
import sys
import time
import unittest

import rospy
import rostest

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import REPLY_SUCCESS, SERVICE_PATH
from cssr_system.animate_behaviour.event_log import read_log
from cssr_system.srv import setActivation

SETTLE = 2.5  # s after a disable for every return home (at most 2 s, and its hold) to end


class ControllerVerdictsTest(unittest.TestCase):
    def run_style(self, style):
        rospy.set_param("/animateBehaviour/motionStyle", style)
        since = datetime.datetime.now()
        self.assertEqual(self.call("enabled").success, REPLY_SUCCESS)
        time.sleep(rospy.get_param("~run_for", 60.0))
        self.assertEqual(self.call("disabled").success, REPLY_SUCCESS)
        time.sleep(SETTLE)
        log = read_log(rospy.get_param("/animateBehaviour/logFile"), since=since)
        finished = [entry.fields for entry in log if entry.event == contract.GOAL_FINISHED]
        sent = [entry.fields for entry in log if entry.event == contract.GOAL_SENT]
        return sent, finished

    def check(self, style):
        sent, finished = self.run_style(style)
        states = {}
        for entry in finished:
            states.setdefault(entry["state"], []).append("%s goal %s (%s): %s" % (
                entry["part"], entry["goal"], entry["purpose"], entry["error_string"]))
        self.assertNotIn("ABORTED", states, "%s: no goal aborted: %s" % (style, states.get("ABORTED")))
        self.assertLessEqual(set(states), {"SUCCEEDED", "PREEMPTED"}, style)
        homes = [entry for entry in finished if entry["purpose"] == contract.PURPOSE_HOME]
        self.assertEqual({entry["part"] for entry in homes}, {"RArm", "LArm", "RHand", "LHand", "Leg"},
                         "%s: every part went home" % style)
        self.assertTrue(all(entry["state"] == "SUCCEEDED" for entry in homes), "%s: %s" % (style, homes))
        self.assertGreaterEqual(len(finished), len(sent) - 1, "%s: every goal's end was reported" % style)

    def test_every_goal_ends_as_the_controller_should_judge_it(self):
        rospy.wait_for_service(SERVICE_PATH, timeout=30)
        self.call = rospy.ServiceProxy(SERVICE_PATH, setActivation)
        for style in ("random", "breathing"):
            self.check(style)


if __name__ == "__main__":
    rospy.init_node("controller_verdicts_test")
    rostest.rosrun("cssr_system", "controller_verdicts", ControllerVerdictsTest, sys.argv)
