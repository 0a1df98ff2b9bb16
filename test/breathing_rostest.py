#!/usr/bin/env python3
"""The breathing style on the simulated Pepper (rostest; README: "Motion styles"): from /joint_states, every joint
stays in its band, under the speed cap, without velocity jumps (also where one goal replaces the next), and the two
shoulders move together. Private parameter: `platform`."""
import os
import sys
import threading
import time
import unittest

import numpy
import rospkg
import rospy
import rostest
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour.configuration import load_configuration
from cssr_system.animate_behaviour.contract import REPLY_SUCCESS, SERVICE_PATH
from cssr_system.motion.waypoints import animated_parts
from cssr_system.pepper.joint_table import PARTS, speed_limit
from cssr_system.srv import setActivation

RUN = 16.0  # s animating: more than one goal (3 breaths of 5 s each), so the test sees a splice
BLEND = 3.0  # s after enable before the joints must be in their bands (the first goal eases in from rest)
JUMP_ACCELERATION = 8.0  # rad/s^2: a velocity jump between 50 Hz samples shows far beyond the planned accelerations
BAND_TOLERANCE = 1e-3


class BreathingTest(unittest.TestCase):
    def test_breathing_from_joint_states(self):
        platform = rospy.get_param("~platform", "robot")
        rospy.wait_for_service(SERVICE_PATH, timeout=30)
        call = rospy.ServiceProxy(SERVICE_PATH, setActivation)
        lock, samples = threading.Lock(), []

        def on_joint_states(message):
            with lock:
                samples.append((message.header.stamp.to_sec(), dict(zip(message.name, zip(message.position,
                                                                                          message.velocity)))))
        rospy.Subscriber("/joint_states", JointState, on_joint_states, queue_size=100)
        self.assertEqual(call("enabled").success, REPLY_SUCCESS)
        enabled = rospy.get_time()
        time.sleep(RUN)
        self.assertEqual(call("disabled").success, REPLY_SUCCESS)
        config = load_configuration(rospy.get_param("/animateBehaviour/configFile"),
                                    {"platform": platform, "motionStyle": "breathing", "behaviour": "body"},
                                    data_dir=os.path.join(rospkg.RosPack().get_path("cssr_system"), "data"))
        parts = [key for key in PARTS if not (platform == "simulator" and key.endswith("Hand"))]
        with lock:
            window = [(stamp, joints) for stamp, joints in samples if enabled + BLEND <= stamp <= enabled + RUN]
        self.assertGreater(len(window), 200)
        stamps = numpy.array([stamp for stamp, _ in window])
        for motion in animated_parts(config, parts):
            for bounds, moving in zip(motion.bounds, motion.moving):
                positions = numpy.array([joints[bounds.name][0] for _, joints in window])
                velocities = numpy.array([joints[bounds.name][1] for _, joints in window])
                self.assertGreaterEqual(positions.min(), bounds.lower - BAND_TOLERANCE, bounds.name)
                self.assertLessEqual(positions.max(), bounds.upper + BAND_TOLERANCE, bounds.name)
                if moving and bounds.upper - bounds.lower > 0.05:
                    self.assertGreater(numpy.ptp(positions), 0.01, "%s breathes" % bounds.name)
                self.assertLessEqual(numpy.abs(velocities).max(), speed_limit(bounds.name) * 1.05, bounds.name)
                accelerations = numpy.diff(velocities) / numpy.maximum(numpy.diff(stamps), 1e-3)
                self.assertLessEqual(numpy.abs(accelerations).max(), JUMP_ACCELERATION, bounds.name)
        right = [joints["RShoulderPitch"][0] for _, joints in window]
        left = [joints["LShoulderPitch"][0] for _, joints in window]
        self.assertGreater(numpy.corrcoef(right, left)[0, 1], 0.8, "the two shoulders move together")


if __name__ == "__main__":
    rospy.init_node("breathing_test")
    rostest.rosrun("cssr_system", "breathing_" + rospy.get_param("~platform", "robot"), BreathingTest, sys.argv)
