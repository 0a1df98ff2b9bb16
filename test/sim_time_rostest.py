#!/usr/bin/env python3
"""Simulated time (rostest; README: "Faults"). With /use_sim_time and a clock that starts paused and then runs slower
(test/sim_time.test, 30 % of real time) or faster (test/sim_time_fast.test, twice real time) than real time: the
service answers while the clock stands still, and the enable takes effect once it runs; no goal is declared lost or
replaced while it is still running (everything that refers to what a controller executes is measured in ROS time);
the base stays within headingBound; disable still stops everything."""
import datetime
import sys
import time
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import REPLY_SUCCESS, SERVICE_PATH
from cssr_system.animate_behaviour.event_log import read_log
from cssr_system.recording.recording import unwrap_heading, yaw_from_quaternion
from cssr_system.srv import setActivation

HEADING_BOUND = 0.3  # the shipped headingBound
HEADING_TOLERANCE = 0.02


class SimTimeTest(unittest.TestCase):
    headings = []

    @classmethod
    def on_odometry(cls, message):
        orientation = message.pose.pose.orientation
        yaw = yaw_from_quaternion(orientation.x, orientation.y, orientation.z, orientation.w)
        cls.headings.append(unwrap_heading(cls.headings[-1] if cls.headings else None, yaw))

    def test_goals_live_on_ros_time(self):
        rospy.wait_for_service(SERVICE_PATH, timeout=30)
        call = rospy.ServiceProxy(SERVICE_PATH, setActivation)
        rospy.Subscriber("/pepper/odom", Odometry, self.on_odometry, queue_size=100)
        while rospy.get_time() == 0.0:  # rospy's clock reads 0 until the first /clock message
            time.sleep(0.01)
        paused_at = rospy.get_time()
        since = datetime.datetime.now()  # the log file may hold earlier runs' lines
        started = time.monotonic()
        self.assertEqual(call("enabled").success, REPLY_SUCCESS)
        self.assertLess(time.monotonic() - started, 1.0, "the service answers while the clock stands still")
        self.assertAlmostEqual(rospy.get_time(), paused_at, delta=0.01, msg="the clock was still paused")
        time.sleep(rospy.get_param("~run_for", 22.0))  # wall time: the first 3 s goals end, the next ones run
        log = read_log(rospy.get_param("/animateBehaviour/logFile"), since=since)
        finished = [entry.fields for entry in log if entry.event == contract.GOAL_FINISHED]
        errors = [entry.fields for entry in log if entry.event == contract.ERROR]
        self.assertTrue(finished, "goals ran to their end on the simulated clock")
        self.assertEqual({entry["state"] for entry in finished}, {"SUCCEEDED"}, "no goal was replaced while running")
        self.assertEqual([entry for entry in errors if "lost" in entry["message"]], [], "no goal declared lost")
        self.assertTrue(self.headings)
        start = self.headings[0]
        self.assertLessEqual(max(abs(heading - start) for heading in self.headings), HEADING_BOUND + HEADING_TOLERANCE)
        self.assertEqual(call("disabled").success, REPLY_SUCCESS)
        time.sleep(1.0)
        log = read_log(rospy.get_param("/animateBehaviour/logFile"), since=since)
        homes = {entry.fields["part"] for entry in log if entry.event == contract.GOAL_SENT
                 and entry.fields["purpose"] == contract.PURPOSE_HOME}
        self.assertEqual(homes, {"RArm", "LArm", "Leg"}, "disable stops every part")


if __name__ == "__main__":
    rospy.init_node("sim_time_test")
    rostest.rosrun("cssr_system", "sim_time", SimTimeTest, sys.argv)
