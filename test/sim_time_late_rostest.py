#!/usr/bin/env python3
"""Simulated time that starts late, at a large time (rostest; README: "Faults"): goals sent while the clock is silent
(rospy's clock reads 0) count from when it starts, so none is declared lost and none is replaced before its end."""
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

RUN = 20.0  # s of wall time after the clock starts: several goals end on it


class SimTimeLateTest(unittest.TestCase):
    def test_goals_sent_before_the_clock_runs_are_not_lost(self):
        rospy.wait_for_service(SERVICE_PATH, timeout=30)
        call = rospy.ServiceProxy(SERVICE_PATH, setActivation)
        since = datetime.datetime.now()
        self.assertEqual(rospy.get_time(), 0.0, "the clock is still silent")
        self.assertEqual(call("enabled").success, REPLY_SUCCESS)
        deadline = time.monotonic() + 30.0
        while rospy.get_time() == 0.0 and time.monotonic() < deadline:
            time.sleep(0.01)
        self.assertGreater(rospy.get_time(), 1.0e5, "the clock started late, at a large time")
        time.sleep(RUN)
        self.assertEqual(call("disabled").success, REPLY_SUCCESS)
        time.sleep(2.0)
        log = read_log(rospy.get_param("/animateBehaviour/logFile"), since=since)
        errors = [entry.fields["message"] for entry in log if entry.event == contract.ERROR]
        self.assertEqual([message for message in errors if "lost" in message], [], "no goal declared lost")
        finished = [entry.fields for entry in log if entry.event == contract.GOAL_FINISHED]
        animation = [entry for entry in finished if entry["purpose"] == contract.PURPOSE_ANIMATE]
        self.assertTrue(animation, "animation goals ran to their end")
        replaced = [entry for entry in animation if entry["state"] != "SUCCEEDED"]
        # The disable replaces each part's running goal: at most one per part ends otherwise.
        self.assertLessEqual(len(replaced), 3, "no goal replaced before its end: %s" % replaced)


if __name__ == "__main__":
    rospy.init_node("sim_time_late_test")
    rostest.rosrun("cssr_system", "sim_time_late", SimTimeLateTest, sys.argv)
