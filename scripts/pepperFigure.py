#!/usr/bin/env python3
"""pepperFigure: Pepper's figure moving as recorded, an animated GIF, from a recording or a ROS 1 bag.

rosrun cssr_system pepperFigure.py RECORDING.json|BAG.bag [-o OUT.gif] [--clearance]   (README: "See Pepper move")
"""
import sys

from cssr_system.recording.figure_command import main


def read_bag(path, joint_states_topic, odometry_topic):
    from cssr_system.ros1.bag_recording import recording_from_bag  # only where ROS 1's rosbag is
    return recording_from_bag(path, joint_states_topic, odometry_topic)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], read_bag))
