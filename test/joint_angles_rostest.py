#!/usr/bin/env python3
"""The joint_angles actuation on the simulated Pepper run as naoqi_driver (rostest; README: "Actuation on the
robot"). From /joint_states: no joint steps further between two samples than the speed cap allows, every joint
stays in its band, and after the disable every joint rests at its centre; another node's /joint_angles stream on
the right arm makes the right arm (only) yield, our calls stop naming its joints, and it resumes after the quiet
time. Private parameter: `style` (random or breathing)."""
import os
import sys
import threading
import time
import unittest

import numpy
import rospkg
import rospy
import rostest
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour.configuration import load_configuration
from cssr_system.animate_behaviour.contract import NODE_NAME, REPLY_SUCCESS, SERVICE_PATH, STATUS_TOPIC
from cssr_system.motion.waypoints import animated_parts
from cssr_system.msg import AnimateBehaviourStatus
from cssr_system.pepper.joint_table import PARTS, speed_limit
from cssr_system.ros1.rospy_compat import caller_of
from cssr_system.srv import setActivation

TOPIC = "/joint_angles"
RUN = 20.0  # s animating
EASE_IN = {"random": 1.5, "breathing": 3.0}  # s after enable (or a resume) before the joints must be in their bands
OTHER_AT, OTHER_FOR = 6.0, 2.0  # s after enable when the other node streams to the right arm, and for how long
QUIET_TIME = 1.0  # s: yieldQuietTime
STEP_TOLERANCE = 1e-3  # rad a 50 Hz step may pass the speed cap by (stamps and float32 rounding)
BAND_TOLERANCE = 1e-3
CENTRE_TOLERANCE = 0.01  # rad
SETTLE = 3.0  # s after the disable for every joint to be back at its centre


class Recorder:
    """/joint_states, the node's status and the node's own calls, with their arrival times (ROS time)."""

    def __init__(self):
        self.lock = threading.Lock()
        self.samples, self.statuses, self.calls = [], [], []
        rospy.Subscriber("/joint_states", JointState, self.on_joint_states, queue_size=200)
        rospy.Subscriber("/" + STATUS_TOPIC, AnimateBehaviourStatus, self.on_status, queue_size=50)
        rospy.Subscriber(TOPIC, JointAnglesWithSpeed, self.on_call, queue_size=200)

    def on_joint_states(self, message):
        with self.lock:
            self.samples.append((message.header.stamp.to_sec(), dict(zip(message.name, message.position))))

    def on_status(self, message):
        with self.lock:
            self.statuses.append((rospy.get_time(), {part.part: (part.state, part.yielding_to)
                                                     for part in message.parts}))

    def on_call(self, message):
        if caller_of(message) == "/" + NODE_NAME:
            with self.lock:
                self.calls.append((rospy.get_time(), tuple(message.joint_names)))

    def state_of(self, part):
        with self.lock:
            return self.statuses[-1][1].get(part) if self.statuses else None


def wait_for(condition, timeout):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and not condition():
        time.sleep(0.02)
    return condition()


class JointAnglesTest(unittest.TestCase):
    def test_joint_angles_on_the_simulated_naoqi_driver(self):
        style = rospy.get_param("~style", "random")
        rospy.wait_for_service(SERVICE_PATH, timeout=30)
        call = rospy.ServiceProxy(SERVICE_PATH, setActivation)
        recorder = Recorder()
        other = rospy.Publisher(TOPIC, JointAnglesWithSpeed, queue_size=10)
        # The simulated Pepper and the node (it watches other nodes' calls) listen before we publish.
        self.assertTrue(wait_for(lambda: other.get_num_connections() >= 3, 20.0), "connections to %s" % TOPIC)
        self.assertTrue(wait_for(lambda: recorder.state_of("RArm") is not None, 20.0), "status")
        self.assertEqual(call("enabled").success, REPLY_SUCCESS)
        enabled = rospy.get_time()
        time.sleep(OTHER_AT)
        yield_window = self.other_node_streams(recorder, other)
        time.sleep(max(0.0, enabled + RUN - rospy.get_time()))
        self.assertEqual(call("disabled").success, REPLY_SUCCESS)
        disabled = rospy.get_time()
        time.sleep(SETTLE)
        config = load_configuration(rospy.get_param("/%s/configFile" % NODE_NAME),
                                    {"platform": "robot", "motionStyle": style, "behaviour": "body"},
                                    data_dir=os.path.join(rospkg.RosPack().get_path("cssr_system"), "data"))
        with recorder.lock:
            samples = list(recorder.samples)
        self.check_steps(samples)
        self.check_bands(samples, config, enabled + EASE_IN[style], disabled, yield_window, EASE_IN[style])
        self.check_centres(samples, disabled)

    def other_node_streams(self, recorder, other):
        """Another node streams the right shoulder for OTHER_FOR s: the right arm yields (only it), our calls stop
        naming its joints, and it animates again after the quiet time. The window (start, resume) it yielded."""
        with recorder.lock:
            now_position = recorder.samples[-1][1]["RShoulderPitch"]
        started = rospy.get_time()
        while rospy.get_time() < started + OTHER_FOR:
            other.publish(JointAnglesWithSpeed(joint_names=["RShoulderPitch"], joint_angles=[now_position - 0.15],
                                               speed=0.05))
            time.sleep(0.1)
        stopped = rospy.get_time()
        self.assertEqual(recorder.state_of("RArm"), ("yielding", rospy.get_caller_id()))
        self.assertEqual(recorder.state_of("LArm")[0], "animating")
        with recorder.lock:
            named = [joints for at, joints in recorder.calls if started + 0.3 <= at <= stopped]
        self.assertTrue(named, "the other parts are still streamed")
        self.assertFalse([joints for joints in named if set(joints) & set(PARTS["RArm"].joints)],
                         "no call of ours names a joint of the yielding right arm")
        self.assertTrue(wait_for(lambda: recorder.state_of("RArm")[0] == "animating", QUIET_TIME + 3.0),
                        "the right arm resumes after the quiet time")
        resumed = rospy.get_time()
        self.assertGreater(resumed - stopped, QUIET_TIME - 0.2)
        return started, resumed

    def check_steps(self, samples):
        """No joint moves further between two samples than the 20 % speed cap allows."""
        stamps = numpy.array([stamp for stamp, _ in samples])
        self.assertGreater(len(samples), 1000)
        for part in PARTS.values():
            for name in part.joints:
                steps = numpy.abs(numpy.diff([joints[name] for _, joints in samples]))
                allowed = speed_limit(name) * numpy.diff(stamps) + STEP_TOLERANCE
                worst = int(numpy.argmax(steps - allowed))
                self.assertLessEqual(steps[worst], allowed[worst], "%s steps %.4f rad at %.2f s" % (
                    name, steps[worst], stamps[worst + 1] - stamps[0]))

    def check_bands(self, samples, config, start, end, yield_window, ease_in):
        """Every joint in its band while animated (the right arm not while yielding, nor during its ease-in)."""
        window = [(stamp, joints) for stamp, joints in samples if start <= stamp <= end]
        self.assertGreater(len(window), 500)
        for motion in animated_parts(config, tuple(PARTS)):
            kept = [(stamp, joints) for stamp, joints in window if motion.part != "RArm" or not
                    yield_window[0] <= stamp <= yield_window[1] + ease_in]
            for bounds, moving in zip(motion.bounds, motion.moving):
                positions = numpy.array([joints[bounds.name] for _, joints in kept])
                self.assertGreaterEqual(positions.min(), bounds.lower - BAND_TOLERANCE, bounds.name)
                self.assertLessEqual(positions.max(), bounds.upper + BAND_TOLERANCE, bounds.name)
                if moving and bounds.upper - bounds.lower > 0.05:
                    self.assertGreater(numpy.ptp(positions), 0.01, "%s moves" % bounds.name)

    def check_centres(self, samples, disabled):
        last = samples[-1]
        self.assertGreater(last[0], disabled + SETTLE - 1.0)
        for part in PARTS.values():
            for name, centre in zip(part.joints, part.centre):
                self.assertAlmostEqual(last[1][name], centre, delta=CENTRE_TOLERANCE, msg=name)


if __name__ == "__main__":
    rospy.init_node("joint_angles_test")
    rostest.rosrun("cssr_system", "joint_angles_" + rospy.get_param("~style", "random"), JointAnglesTest, sys.argv)
