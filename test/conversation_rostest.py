#!/usr/bin/env python3
"""The modes following the conversation (rostest; README: "Modes"), on the simulator interface of the simulated
Pepper: a Bool topic puts the robot into listening and an action's active goal into speaking, each within a goal
period, spliced without a stop or a velocity jump; speaking wins over listening; a speaking topic whose node dies falls
back to idle after the time-out; a part another node moves still yields while speaking."""
import os
import signal
import subprocess
import sys
import threading
import time
import unittest

import actionlib
import numpy
import rospy
import rostest
from actionlib.msg import TestAction
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from cssr_system.animate_behaviour.contract import NODE_NAME, REPLY_SUCCESS, SERVICE_PATH
from cssr_system.msg import AnimateBehaviourStatus
from cssr_system.pepper.joint_table import PARTS
from cssr_system.srv import setActivation

NODE = "/" + NODE_NAME
PARTS_HERE = ("RArm", "LArm", "Leg")
SWITCH_TIME = 1.0  # s: a goal period of the shipped random style (gestureDuration 1 s)
TIMEOUT = 1.5  # s: conversationTimeout in conversation.test
# rad/s^2 between two samples: a velocity jump. The speaking beats accelerate up to about 20 rad/s^2 (the wrists,
# under their speed cap); the unit tests (test/unit/test_modes.py) check that each splice starts exactly where the
# controller is, at its velocity.
JUMP_ACCELERATION = 30.0


class ConversationTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.wait_for_service(SERVICE_PATH, timeout=30)
        cls.call = rospy.ServiceProxy(SERVICE_PATH, setActivation)
        cls.lock = threading.Lock()
        cls.samples, cls.statuses = [], []
        rospy.Subscriber("/joint_states", JointState, cls.on_joint_states, queue_size=100)
        rospy.Subscriber(NODE + "/status", AnimateBehaviourStatus, cls.on_status, queue_size=100)
        cls.listening = rospy.Publisher("/listening", Bool, queue_size=1, latch=True)
        cls.speaking_ends = threading.Event()
        cls.tts = actionlib.SimpleActionServer("/tts", TestAction, cls.speak, auto_start=False)
        cls.tts.start()
        cls.tts_client = actionlib.SimpleActionClient("/tts", TestAction)
        assert cls.tts_client.wait_for_server(rospy.Duration(10))

    @classmethod
    def speak(cls, goal):
        """The stand-in text to speech: speaks until told to stop."""
        cls.speaking_ends.wait(20.0)
        cls.speaking_ends.clear()
        cls.tts.set_succeeded()

    @classmethod
    def on_joint_states(cls, message):
        with cls.lock:
            cls.samples.append((time.monotonic(), message.header.stamp.to_sec(),
                                dict(zip(message.name, zip(message.position, message.velocity)))))

    @classmethod
    def on_status(cls, message):
        with cls.lock:
            cls.statuses.append((time.monotonic(), message))

    def wait_for_mode(self, mode, since, within):
        """When the status first said `mode` after `since` (fails unless within `within` s)."""
        deadline = since + within
        while time.monotonic() < deadline + 0.5:
            with self.lock:
                seen = [(at, status) for at, status in self.statuses if at >= since and status.mode == mode]
            if seen:
                self.assertLessEqual(seen[0][0] - since, within, "%s within %.1f s" % (mode, within))
                return seen[0][1]
            time.sleep(0.02)
        self.fail("the mode never became %s" % mode)

    def assert_smooth_and_animating(self, start):
        with self.lock:
            window = [(stamp, joints) for at, stamp, joints in self.samples if at >= start]
            states = {part.state for at, status in self.statuses if at >= start for part in status.parts
                      if part.part in PARTS_HERE and part.part != "RArm"}
        for name in [joint for part in PARTS_HERE for joint in PARTS[part].joints]:
            velocities = numpy.array([joints[name][1] for _, joints in window])
            steps = numpy.maximum(numpy.diff([stamp for stamp, _ in window]), 1e-3)
            self.assertLessEqual((numpy.abs(numpy.diff(velocities)) / steps).max(), JUMP_ACCELERATION, name)
        self.assertEqual(states, {"animating"}, "no part stopped")

    def test_the_conversation_sets_the_mode_by_itself(self):
        self.assertEqual(self.call("enabled").success, REPLY_SUCCESS)
        time.sleep(2.0)
        start = time.monotonic()
        self.listening.publish(Bool(data=True))
        status = self.wait_for_mode("listening", start, SWITCH_TIME)
        self.assertEqual(status.mode_by, "listeningTopic /listening")
        time.sleep(1.5)
        speaking = time.monotonic()
        self.tts_client.send_goal(actionlib.msg.TestGoal(goal=1))
        self.assertEqual(self.wait_for_mode("speaking", speaking, SWITCH_TIME).mode_by, "speakingAction /tts")
        self.listening.publish(Bool(data=True))  # listening too: speaking wins
        time.sleep(2.0)
        self.assertEqual(self.statuses[-1][1].mode, "speaking")
        ended = time.monotonic()
        self.speaking_ends.set()
        self.wait_for_mode("listening", ended, SWITCH_TIME)
        time.sleep(1.0)
        quiet = time.monotonic()
        self.listening.publish(Bool(data=False))
        self.wait_for_mode("idle", quiet, SWITCH_TIME)
        time.sleep(1.0)
        self.assert_smooth_and_animating(start)

    def test_a_speaking_topic_whose_node_dies_falls_back_to_idle_and_parts_still_yield(self):
        self.assertEqual(self.call("enabled").success, REPLY_SUCCESS)
        speaker = subprocess.Popen(["rostopic", "pub", "/speaking", "std_msgs/Bool", "data: true"],
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            start = time.monotonic()
            self.wait_for_mode("speaking", start, 10.0)  # rostopic takes a few seconds to start
            time.sleep(TIMEOUT + 1.0)
            self.assertEqual(self.statuses[-1][1].mode, "speaking", "a latched topic's publisher keeps it alive")
            gesture = rospy.Publisher("/pepper/RightArm_controller/command", JointTrajectory, queue_size=1)
            time.sleep(0.5)
            point = JointTrajectoryPoint(positions=list(PARTS["RArm"].centre), time_from_start=rospy.Duration(2.0))
            gesture.publish(JointTrajectory(joint_names=list(PARTS["RArm"].joints), points=[point]))
            time.sleep(0.5)
            arm = [part for part in self.statuses[-1][1].parts if part.part == "RArm"][0]
            self.assertEqual(arm.state, "yielding", "another node's motion wins while speaking")
        finally:
            os.kill(speaker.pid, signal.SIGKILL)
            speaker.wait()
        died = time.monotonic()
        status = self.wait_for_mode("idle", died, TIMEOUT + 1.0)
        self.assertEqual(status.mode_by, "speakingTopic /speaking silent")

    def tearDown(self):
        self.listening.publish(Bool(data=False))
        self.call("disabled")
        time.sleep(1.0)


if __name__ == "__main__":
    rospy.init_node("conversation_test")
    rostest.rosrun("cssr_system", "conversation", ConversationTest, sys.argv)
