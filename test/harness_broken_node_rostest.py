#!/usr/bin/env python3
"""The harness catches a broken node (rostest, with test/harness_broken_node.test).

The node under test ignores the configuration's selectedRange (a private parameter overrides it with
1.0), so its random positions span twice the bounds the harness computes from selectedRange 0.5. The
harness (scripts/animateBehaviourTest.py, run here as a plain process, as a user would) must exit
with status 1 and say what went wrong, on its console and in its report: which joint, where it was
observed, and the bound it passed.
"""
import os
import re
import subprocess
import sys
import unittest

import rospkg
import rospy
import rostest

PACKAGE_DIR = rospkg.RosPack().get_path("cssr_system")
HARNESS = os.path.join(PACKAGE_DIR, "scripts", "animateBehaviourTest.py")
TEST_CONFIGURATION = os.path.join(PACKAGE_DIR, "test", "harnessTestConfiguration.ini")
NUMBER = r"-?\d+(?:\.\d+)?(?:e-?\d+)?"
# e.g. "RShoulderPitch = 1.87 at +2.35 s after enabled, outside [1.33243, 1.74957] by 0.12"
OBSERVED_OUTSIDE = re.compile(
    r"(\w+) = ({0}) at \+{0} s after enabled, outside \[({0}), ({0})\] by ({0})".format(NUMBER))


class HarnessCatchesBrokenNode(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("harness_broken_node")
        platform = rospy.get_param("~platform", "simulator")
        folder = os.path.join(rospkg.get_ros_home(), "harness_broken_node")
        os.makedirs(folder, exist_ok=True)
        cls.report_file = os.path.join(folder, "animateBehaviourTestOutput.dat")
        if os.path.exists(cls.report_file):
            os.remove(cls.report_file)  # the harness appends: judge this run only
        command = [sys.executable, HARNESS, "__name:=animateBehaviourTestOfBrokenNode",
                   "_configFile:=" + TEST_CONFIGURATION, "_platform:=" + platform, "_tests:=body",
                   "_iterations:=1", "_reportFile:=" + cls.report_file,
                   "_nodeConfigFile:=" + os.path.join(folder, "animateBehaviourHarnessNode.ini")]
        cls.harness_run = subprocess.run(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                         stderr=subprocess.STDOUT, universal_newlines=True, timeout=90)
        with open(cls.report_file, encoding="utf-8") as stream:
            cls.report = stream.read()
        print(cls.harness_run.stdout)

    def test_harness_fails(self):
        self.assertEqual(self.harness_run.returncode, 1,
                         "the harness should report a failed test:\n" + self.harness_run.stdout)
        self.assertIn("Test Run Completed with Result: FAILED", self.report)

    def test_message_names_joint_position_and_bound(self):
        for text, where in ((self.harness_run.stdout, "console"), (self.report, "report")):
            self.assertIn("Observed positions within bounds: FAILED", text, where)
            found = OBSERVED_OUTSIDE.search(text)
            self.assertIsNotNone(found, "no 'joint = position ... outside [LB, UB] by excess' in the " + where)
            joint, value, lower, upper, excess = found.group(1), *map(float, found.group(2, 3, 4, 5))
            self.assertIn(joint, text)
            self.assertTrue(value < lower or value > upper, found.group(0))
            self.assertAlmostEqual(max(lower - value, value - upper), excess, delta=1e-4)

    def test_sent_positions_and_configuration_are_named(self):
        self.assertIn("Random positions sent within bounds: FAILED", self.report)
        self.assertIn("selectedRange: node used 1.0, the harness wrote 0.5", self.report)
        self.assertIn("~selectedRange=1.0", self.report)


if __name__ == "__main__":
    rostest.rosrun("cssr_system", "harness_broken_node", HarnessCatchesBrokenNode)
