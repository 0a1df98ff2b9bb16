#!/usr/bin/env python3
"""Faults never take the robot with them (rostest; README: "Faults").

The launch file runs the simulated Pepper (respawned when it dies, as a controller spawner does); this test starts
the animateBehaviour node itself, once per case, as a process whose output it reads, and injects one fault per
case: a log file on /dev/full, a log folder deleted while running, corrupt /joint_states, a controller that rejects
every goal, controllers that die and come back, a signal while a controller is missing. Every case asserts: no
traceback in the node's output, goals sent while enabled, everything stopped after `disabled`, the node alive
until told to stop, and exit status 0 within 1 s of SIGINT or SIGTERM.
"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import actionlib
import genpy
import rospkg
import rospy
import rostest
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryResult
from sensor_msgs.msg import JointState
from wire_recorder import WireRecorder, wait_until

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import REPLY_SUCCESS, SERVICE_PATH
from cssr_system.animate_behaviour.event_log import read_log
from cssr_system.animate_behaviour.topics import load_topic_map
from cssr_system.pepper.joint_table import PARTS
from cssr_system.srv import setActivation

PACKAGE_DIR = rospkg.RosPack().get_path("cssr_system")
ROBOT_TOPICS = os.path.join(PACKAGE_DIR, "data", "pepperTopics.dat")
FAULTY_ACTION = "/faulty/RightHand_controller/follow_joint_trajectory"
MISSING_ACTION = "/missing/LeftHand_controller/follow_joint_trajectory"
# Short goals, so that a new goal follows every second or so.
SHORT_GOALS = ["_numPoints:=2", "_gestureDuration:=0.5", "_legRepeatFactor:=1", "_numPointsLeg:=1"]
EXIT_BOUND = 1.0  # s from a signal to the node's exit
RESUME_BOUND = 3.0  # s from a controller's return to the part's next goal
NODE = "/animateBehaviour"
ANIMATED_KEYS = ("RArm", "LArm", "Leg")  # parts every case watches: their controllers are the standard ones


class Node:
    """An animateBehaviour process of this test, its output in a file."""

    def __init__(self, folder, *arguments):
        self.output_path = os.path.join(folder, "node_output.txt")
        self.output = open(self.output_path, "w")
        self.process = subprocess.Popen(["rosrun", "cssr_system", "animateBehaviour.py"] + list(arguments),
                                        stdout=self.output, stderr=subprocess.STDOUT)
        rospy.wait_for_service(SERVICE_PATH, timeout=30)
        self.call = rospy.ServiceProxy(SERVICE_PATH, setActivation)

    def text(self):
        with open(self.output_path, encoding="utf-8", errors="replace") as stream:
            return stream.read()

    def stop(self, signal_number=signal.SIGINT):
        """Signal, wait for the exit: (exit status, seconds)."""
        started = time.monotonic()
        self.process.send_signal(signal_number)
        try:
            status = self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            status = None
        seconds = time.monotonic() - started
        self.output.close()
        # rostest's master outlives the process: forget its service before the next node starts.
        wait_until(lambda: not service_listed(), 5)
        return status, seconds


def service_listed():
    try:
        rospy.wait_for_service(SERVICE_PATH, timeout=0.05)
        return True
    except rospy.ROSException:
        return False


class FaultsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="faults-")
        cls.topics = dict(load_topic_map(ROBOT_TOPICS).topics)
        cls.wire = WireRecorder(cls.topics)
        cls.faulty_goals = []
        cls.faulty = actionlib.ActionServer(FAULTY_ACTION, FollowJointTrajectoryAction, goal_cb=cls._reject,
                                            auto_start=False)
        cls.faulty.start()
        cls.bad_publisher = rospy.Publisher("/joint_states", JointState, queue_size=10)
        cls.joint_state_times = []
        rospy.Subscriber("/joint_states", JointState, cls._on_joint_state, queue_size=100)
        # A topic file where the right hand's controller rejects everything and the left hand's is missing.
        cls.faulty_topics = os.path.join(cls.folder, "faultyTopics.dat")
        with open(cls.faulty_topics, "w") as stream:
            for key, name in cls.topics.items():
                name = {"RHand": FAULTY_ACTION, "LHand": MISSING_ACTION}.get(key, name)
                stream.write("%s %s\n" % (key, name))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.folder, ignore_errors=True)

    @classmethod
    def _reject(cls, goal_handle):
        cls.faulty_goals.append(time.monotonic())
        goal_handle.set_rejected(FollowJointTrajectoryResult(error_code=-1, error_string="rejects everything"))

    @classmethod
    def _on_joint_state(cls, message):
        if message._connection_header.get("callerid") == "/simulatedPepper":
            cls.joint_state_times.append(time.monotonic())

    def setUp(self):
        self.wire.clear()
        self.case_folder = tempfile.mkdtemp(dir=self.folder)

    # -- helpers ----------------------------------------------------------------------------------
    def start(self, *arguments):
        if rospy.has_param(NODE):  # private parameters of an earlier case's node stay on the server
            rospy.delete_param(NODE)
        arguments = ("_behaviour:=body", "_logFile:=%s" % os.path.join(self.case_folder, "node.log")) + arguments
        node = Node(self.case_folder, *arguments)
        self.addCleanup(lambda: node.process.poll() is None and node.stop())
        # Its first goals leave at the enable: the recorder must hear them (the next come seconds later).
        self.assertTrue(wait_until(lambda: self.wire.connected_to(NODE, ANIMATED_KEYS), 10),
                        "the recorder hears the node's goals")
        return node

    def our_goals(self, keys, since):
        return [(at, key) for at, key, message in self.wire.snapshot(self.wire.goals)
                if key in keys and at >= since and message._connection_header.get("callerid") == NODE]

    def assert_animates(self, node, keys=ANIMATED_KEYS, seconds=2.0):
        since = time.monotonic()
        time.sleep(seconds)
        # A controller the node has not connected yet (it checks twice a second) gets its goal on connecting.
        wait_until(lambda: {key for _, key in self.our_goals(keys, since - 0.5)} >= set(keys), 5.0)
        moved = {key for _, key in self.our_goals(keys, since - 0.5)}
        self.assertEqual(moved, set(keys), "goals of every part while enabled")
        self.assertIsNone(node.process.poll(), "the node is alive")

    def assert_stops(self, node, keys=ANIMATED_KEYS):
        """`disabled`: one return-to-centre goal per part, then nothing more."""
        disabled = time.monotonic()
        self.assertEqual(node.call("disabled").success, REPLY_SUCCESS)
        time.sleep(0.5)
        stopping = {key for _, key in self.our_goals(keys, disabled)}
        self.assertEqual(stopping, set(keys), "every part stopped (its return goal)")
        settled = time.monotonic()
        time.sleep(1.0)
        self.assertEqual(self.our_goals(keys, settled), [], "nothing sent after the stop")

    def assert_clean_exit(self, node, signal_number=signal.SIGINT):
        status, seconds = node.stop(signal_number)
        self.assertEqual(status, 0)
        self.assertLessEqual(seconds, EXIT_BOUND)
        self.assertNotIn("Traceback", node.text())

    def assert_one_final_state_per_goal(self, log_file):
        """Every goal_sent has exactly one goal_finished; the returns home still running at the exit say so."""
        entries = read_log(log_file)
        sent = sorted((entry.fields["part"], entry.fields["goal"]) for entry in entries
                      if entry.event == contract.GOAL_SENT)
        finished = [entry.fields for entry in entries if entry.event == contract.GOAL_FINISHED]
        self.assertTrue(sent)
        self.assertEqual(sorted((fields["part"], fields["goal"]) for fields in finished), sent)
        self.assertIn("RUNNING_AT_EXIT", {fields["state"] for fields in finished if fields["purpose"] == "home"})

    # -- the log file ----------------------------------------------------------------------------------
    def test_a_log_file_on_a_full_disk(self):
        node = self.start("_logFile:=/dev/full")
        self.assertEqual(node.call("enabled").success, REPLY_SUCCESS)
        self.assert_animates(node)
        self.assert_stops(node)
        text = node.text()
        self.assertIn("/dev/full", text, "the problem with the log file is reported")
        self.assert_clean_exit(node)

    def test_the_log_folder_deleted_while_running(self):
        log_folder = os.path.join(self.case_folder, "logs")
        node = self.start("_logFile:=%s" % os.path.join(log_folder, "node.log"), *SHORT_GOALS)
        self.assertEqual(node.call("enabled").success, REPLY_SUCCESS)
        time.sleep(1.0)
        shutil.rmtree(log_folder)
        self.assert_animates(node)
        self.assert_stops(node)
        self.assertTrue(os.path.exists(os.path.join(log_folder, "node.log")), "the log is written again")
        self.assert_clean_exit(node, signal.SIGTERM)

    # -- sensors -------------------------------------------------------------------------------------
    def test_corrupt_joint_states(self):
        node = self.start(*SHORT_GOALS)
        self.assertEqual(node.call("enabled").success, REPLY_SUCCESS)
        names = list(PARTS["RArm"].joints)
        stop = threading.Event()

        def publish_corrupt():
            while not stop.is_set():
                for message in (JointState(name=names, position=[float("nan")] * len(names)),
                                JointState(name=names, position=[1.0]),
                                JointState(name=names, position=[float("inf")] * len(names)),
                                JointState(name=names, position=[0.0] * len(names))):
                    message.header.stamp = rospy.Time.now() - genpy.Duration(60.0) if message.position[0] == 0.0 \
                        else rospy.Time.now()
                    self.bad_publisher.publish(message)
                time.sleep(0.01)
        publisher = threading.Thread(target=publish_corrupt)
        publisher.start()
        try:
            self.assert_animates(node, seconds=3.0)
        finally:
            stop.set()
            publisher.join()
        self.assert_stops(node)
        text = node.text()
        self.assertEqual(text.count("not a finite number"), 1, "reported once")
        self.assertEqual(text.count("names but"), 1)
        self.assertEqual(text.count("behind"), 1)
        self.assert_clean_exit(node)

    # -- controllers ---------------------------------------------------------------------------------
    def test_a_controller_that_rejects_everything_is_retried_with_back_off(self):
        node = self.start("_robotTopics:=%s" % self.faulty_topics, "_behaviour:=hands", *SHORT_GOALS)
        del self.faulty_goals[:]
        self.assertEqual(node.call("enabled").success, REPLY_SUCCESS)
        time.sleep(7.5)
        self.assertGreaterEqual(len(self.faulty_goals), 3)
        gaps = [later - earlier for earlier, later in zip(self.faulty_goals, self.faulty_goals[1:])]
        self.assertAlmostEqual(gaps[0], 2.0, delta=0.5)
        self.assertAlmostEqual(gaps[1], 4.0, delta=0.5)
        self.assertEqual(node.text().count("rejects everything"), len(self.faulty_goals), "one line per back-off")
        self.assert_animates(node, keys=("RArm", "LArm"), seconds=0.5)
        self.assert_stops(node, keys=("RArm", "LArm"))
        self.assert_clean_exit(node)

    def test_controllers_that_die_and_come_back(self):
        node = self.start(*SHORT_GOALS)
        self.assertEqual(node.call("enabled").success, REPLY_SUCCESS)
        self.assert_animates(node)
        killed = time.monotonic()
        subprocess.run(["rosnode", "kill", "/simulatedPepper"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        gone = wait_until(lambda: self.joint_state_times[-1] < time.monotonic() - 0.5, 10)
        self.assertTrue(gone, "the controllers are gone")
        self.assertTrue(wait_until(lambda: self.joint_state_times[-1] > killed + 1.0, 30), "the controllers are back")
        back = time.monotonic()
        time.sleep(RESUME_BOUND + 0.5)
        for key in ("RArm", "LArm", "Leg", "RHand", "LHand"):
            resumed = [at for at, goal_key in self.our_goals((key,), back - 0.5)]
            self.assertTrue(resumed, "%s resumed; the node said:\n%s" % (key, node.text()[-3000:]))
            self.assertLessEqual(resumed[0] - back, RESUME_BOUND, "%s resumed late" % key)
        self.assert_stops(node, keys=("RArm", "LArm", "Leg", "RHand", "LHand"))
        self.assert_clean_exit(node)

    # -- signals -------------------------------------------------------------------------------------
    def test_a_signal_while_a_controller_is_missing(self):
        node = self.start("_robotTopics:=%s" % self.faulty_topics, *SHORT_GOALS)
        self.assertEqual(node.call("enabled").success, REPLY_SUCCESS)
        self.assert_animates(node, seconds=1.5)
        signalled = time.monotonic()
        self.assert_clean_exit(node)
        stopping = {key for _, key in self.our_goals(("RArm", "LArm", "Leg"), signalled)}
        self.assertEqual(stopping, {"RArm", "LArm", "Leg"}, "the robot was stopped before the exit")

    def test_a_signal_while_homing_and_while_enabling(self):
        node = self.start()
        self.assertEqual(node.call("enabled").success, REPLY_SUCCESS)
        time.sleep(1.0)
        self.assertEqual(node.call("disabled").success, REPLY_SUCCESS)
        self.assert_clean_exit(node, signal.SIGTERM)  # while the parts return to their centre
        self.assert_one_final_state_per_goal(os.path.join(self.case_folder, "node.log"))
        node = self.start()
        enabling = threading.Thread(target=lambda: node.call("enabled"))
        enabling.start()
        self.assert_clean_exit(node)
        enabling.join()


if __name__ == "__main__":
    rospy.init_node("faults_test")
    rostest.rosrun("cssr_system", "faults", FaultsTest, sys.argv)
