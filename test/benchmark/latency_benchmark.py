#!/usr/bin/env python3
"""Latency benchmark of animateBehaviour against the simulated Pepper (`make benchmark`).

Prints, over many enable/disable cycles, the figures the README's "The service" section sets: service reply time, first
goal of every part after `enabled`, stop (home goal or cancel, zero twist) after `disabled`, and the
gap between a goal's success and the next goal. Times run from the caller sending the request to the
message arriving at a subscriber standing where the controller is. The targets must hold for 9
requests in 10 and never be exceeded twice over; the test asserts only generous bounds."""
import os
import statistics
import sys
import time
import unittest

import rospy
import rostest

from cssr_system.animate_behaviour.configuration import load_configuration, topic_file_path
from cssr_system.animate_behaviour.contract import NODE_NAME, SERVICE_PATH
from cssr_system.animate_behaviour.topics import WHEELS_KEY, load_topic_map
from cssr_system.srv import setActivation

# The wire recorder is test code shared with the rostests, one folder up.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from wire_recorder import WireRecorder, next_goal_gaps, wait_until  # noqa: E402

NODE = "/" + NODE_NAME
SERVICE = SERVICE_PATH
TARGETS = {  # seconds (README: "The service")
    "service reply": 0.100,
    "first goal of every part after enabled": 0.100,
    "stop of every part after disabled": 0.050,
    "next goal after a success": 0.200,
}


def first_per_part(store, since):
    firsts = {}
    for at, key, _ in store:
        if at >= since:
            firsts.setdefault(key, at)
    return firsts


class LatencyBenchmark(unittest.TestCase):
    def test_latencies(self):
        cycles = int(rospy.get_param("~cycles", 50))
        rospy.wait_for_service(SERVICE, timeout=30)
        call = rospy.ServiceProxy(SERVICE, setActivation, persistent=True)
        config = load_configuration(rospy.get_param(NODE + "/configFile"),
                                    {"platform": rospy.get_param(NODE + "/platform")})
        topics = dict(load_topic_map(topic_file_path(config)).topics)
        parts = {key for key in topics if key != WHEELS_KEY}
        wire = WireRecorder(topics)
        wait_until(wire.connected, 10)
        call("enabled")
        time.sleep(1.0)
        call("disabled")
        time.sleep(1.0)
        figures = {name: [] for name in TARGETS}
        for _ in range(cycles):
            wire.clear()
            sent = time.monotonic()
            call("enabled")
            figures["service reply"].append(time.monotonic() - sent)
            wait_until(lambda: set(first_per_part(wire.snapshot(wire.goals), sent)) >= parts, 2)
            firsts = first_per_part(wire.snapshot(wire.goals), sent)
            figures["first goal of every part after enabled"].append(max(firsts.values()) - sent)
            time.sleep(0.3)
            sent = time.monotonic()
            call("disabled")
            figures["service reply"].append(time.monotonic() - sent)

            def stopped():
                goals = first_per_part(wire.snapshot(wire.goals), sent)
                cancels = first_per_part(wire.snapshot(wire.cancels), sent)
                return set(goals) | set(cancels) >= parts
            wait_until(stopped, 2)
            stops = first_per_part(wire.snapshot(wire.goals), sent)
            for key, at in first_per_part(wire.snapshot(wire.cancels), sent).items():
                stops[key] = min(at, stops.get(key, at))
            figures["stop of every part after disabled"].append(max(stops.values()) - sent)
            time.sleep(0.3)

        # Short goals, so that many succeed: the next goal must follow at once.
        for key, value in (("numPoints", 2), ("legRepeatFactor", 1), ("numPointsLeg", 1),
                           ("gestureDuration", 0.3)):
            rospy.set_param(NODE + "/" + key, value)
        wire.clear()
        call("enabled")
        time.sleep(8.0)
        call("disabled")
        figures["next goal after a success"] = [
            gap for _, gap in next_goal_gaps(wire.snapshot(wire.goals), wire.snapshot(wire.results))]

        print("\nanimateBehaviour latency benchmark ({} enable/disable cycles, platform {})".format(
            cycles, config.platform))
        print("{:<42} {:>8} {:>8} {:>8} {:>8} {:>9}  {}".format(
            "figure", "target", "p50", "p90", "max", "samples", "meets"))
        for name, values in figures.items():
            target = TARGETS[name]
            ordered = sorted(values)
            p90 = ordered[int(0.9 * (len(ordered) - 1))]
            meets = p90 <= target and ordered[-1] <= 2 * target
            print("{:<42} {:>6.0f}ms {:>6.1f}ms {:>6.1f}ms {:>6.1f}ms {:>9}  {}".format(
                name, target * 1000, statistics.median(values) * 1000, p90 * 1000,
                ordered[-1] * 1000, len(values), "yes" if meets else "NO"))
            self.assertLess(ordered[-1], 10 * target, name)  # generous: a loaded machine


if __name__ == "__main__":
    rospy.init_node("latency_benchmark")
    rostest.rosrun("cssr_system", "latency_benchmark", LatencyBenchmark, sys.argv)
