#!/usr/bin/env python3
"""A simulation clock for tests (README: "Faults"): publishes /clock at real-time factor ~factor (e.g. 0.3: the
simulation runs at 30 % of real time, as Pepper's Gazebo world does on a laptop), after ~paused_for seconds of
wall time with the clock standing still at ~start (as a simulation that starts paused). With ~silent_for it first
publishes nothing for that long (rospy's clock then reads 0), as a simulation resumed or a bag played with --clock
that starts later at a large time."""
import time

import rospy
from rosgraph_msgs.msg import Clock

PERIOD = 0.005  # s of wall time between /clock messages


def main() -> None:
    rospy.init_node("sim_clock")
    factor = float(rospy.get_param("~factor", 0.5))
    paused_for = float(rospy.get_param("~paused_for", 0.0))
    simulated = float(rospy.get_param("~start", 100.0))
    publisher = rospy.Publisher("/clock", Clock, queue_size=10)
    time.sleep(float(rospy.get_param("~silent_for", 0.0)))
    started = time.monotonic()
    last = started
    while not rospy.is_shutdown():
        now = time.monotonic()
        if now - started >= paused_for:
            simulated += (now - last) * factor
        last = now
        publisher.publish(Clock(clock=rospy.Time.from_sec(simulated)))
        time.sleep(PERIOD)


if __name__ == "__main__":
    main()
