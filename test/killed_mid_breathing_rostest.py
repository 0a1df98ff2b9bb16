#!/usr/bin/env python3
"""A node killed mid-breathing leaves the robot coming to rest smoothly (rostest; README: "Controllers: what each
goal carries").

The test starts animateBehaviour itself (breathing, simulator platform), enables it, kills it with SIGKILL while the
arms and leg breathe, and records /joint_states of the simulated Pepper: its last goals play to their ends, which
are at rest, so every joint slows to |v| < 1e-3 rad/s with no velocity jump over 0.01 rad/s between 50 Hz samples.
Every goal seen on the wire ends with velocities and accelerations of exactly 0."""
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import rospkg
import rospy
import rostest
from sensor_msgs.msg import JointState
from wire_recorder import WireRecorder, wait_until

from cssr_system.animate_behaviour.contract import REPLY_SUCCESS, SERVICE_PATH
from cssr_system.animate_behaviour.topics import load_topic_map
from cssr_system.pepper.joint_table import PARTS
from cssr_system.srv import setActivation

SIMULATOR_TOPICS = os.path.join(rospkg.RosPack().get_path("cssr_system"), "data", "simulatorTopics.dat")
PARTS_MOVED = ("RArm", "LArm", "Leg")  # behaviour body on the simulator platform
AT_REST = 1e-3  # rad/s: a joint slower than this has come to rest
JUMP = 0.01  # rad/s: the largest change of velocity between two 50 Hz samples that is no jump
SAMPLE_PERIOD = 0.02  # s between /joint_states messages
REST_BOUND = 30.0  # s after the kill: the running goal (12 s of breaths at 15 a minute) and its ending play out


class KilledMidBreathingTest(unittest.TestCase):
    def test_every_joint_comes_to_rest_smoothly(self):
        topics = dict(load_topic_map(SIMULATOR_TOPICS).topics)
        wire = WireRecorder(topics)
        lock, samples = threading.Lock(), []

        def on_joint_states(message):
            with lock:
                samples.append(message)
        rospy.Subscriber("/joint_states", JointState, on_joint_states, queue_size=100)
        folder = tempfile.mkdtemp(prefix="killed-")
        node = subprocess.Popen(["rosrun", "cssr_system", "animateBehaviour.py", "_platform:=simulator",
                                 "_behaviour:=body", "_motionStyle:=breathing", "_breathsPerMinute:=15",
                                 "_logFile:=" + os.path.join(folder, "animateBehaviour.log")])
        try:
            rospy.wait_for_service(SERVICE_PATH, timeout=30)
            self.assertTrue(wait_until(wire.connected, 10))
            self.assertEqual(rospy.ServiceProxy(SERVICE_PATH, setActivation)("enabled").success, REPLY_SUCCESS)
            time.sleep(4.0)
        finally:
            node.send_signal(signal.SIGKILL)
            node.wait(10)
        with lock:
            killed = len(samples)
        joints = [joint for part in PARTS_MOVED for joint in PARTS[part].joints]

        def at_rest():
            with lock:
                last = samples[-1]
            speeds = dict(zip(last.name, last.velocity))
            return all(abs(speeds[joint]) < AT_REST for joint in joints)
        self.assertFalse(at_rest(), "killed while moving")
        self.assertTrue(wait_until(at_rest, REST_BOUND), "every joint comes to rest")
        time.sleep(0.5)
        with lock:
            after = samples[killed:]
        for joint in joints:
            index = after[0].name.index(joint)
            for before, later in zip(after, after[1:]):
                gap = (later.header.stamp - before.header.stamp).to_sec()
                change = abs(later.velocity[index] - before.velocity[index])
                self.assertLessEqual(change, JUMP * max(1.0, gap / SAMPLE_PERIOD), (joint, change, gap))
        with wire.lock:
            goals = list(wire.goals)
        self.assertGreaterEqual(len(goals), len(PARTS_MOVED))
        for _, key, message in goals:
            last = message.goal.trajectory.points[-1]
            self.assertEqual(list(last.velocities), [0.0] * len(last.velocities), key)
            self.assertEqual(list(last.accelerations), [0.0] * len(last.accelerations), key)


if __name__ == "__main__":
    rospy.init_node("killed_mid_breathing_test")
    rostest.rosrun("cssr_system", "killed_mid_breathing", KilledMidBreathingTest, sys.argv)
