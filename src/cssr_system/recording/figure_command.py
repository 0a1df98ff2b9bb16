"""pepperFigure: the animated GIF of Pepper's figure from a recording, or from a ROS 1 bag (README: "See Pepper
move", doc/figure.md)."""
import argparse
import os
import sys
import time
from typing import Callable, Optional, Sequence

from cssr_system.figure.clearance import per_arm_lines, recorded_clearances
from cssr_system.figure.render import FRAME_RATE, render_recording
from cssr_system.recording.recording import read_recording

GIF_FILE_NAME = "animation.gif"  # beside the recorder's animation.png


def main(argv: Sequence[str], read_bag: Optional[Callable] = None) -> int:
    """`read_bag(path, joint_states_topic, odometry_topic)`: a recording from a bag (the ROS 1 front-end's)."""
    parser = argparse.ArgumentParser(prog="pepperFigure", description="Renders Pepper's figure (a model from its "
                                     "kinematics and simple solids) moving as recorded: an animated GIF, front and "
                                     "side views, %g frames a second." % FRAME_RATE)
    parser.add_argument("recording", help="a recording (animation.json) or a ROS 1 bag (.bag) of joint states and "
                                          "odometry")
    parser.add_argument("-o", "--output", help="the GIF (default: the recording's name with .gif)")
    parser.add_argument("--joint-states", default=None, help="a bag's JointState topic (default: the one it has)")
    parser.add_argument("--odometry", default=None, help="a bag's Odometry topic (default: the one it has)")
    parser.add_argument("--clearance", action="store_true", help="also print each arm's smallest clearance")
    arguments = parser.parse_args(argv)
    try:
        if arguments.recording.endswith(".bag"):
            if read_bag is None:
                raise ValueError("%s: reading a ROS 1 bag needs the rosbag module (ROS 1)" % arguments.recording)
            recording = read_bag(arguments.recording, arguments.joint_states, arguments.odometry)
        else:
            recording = read_recording(arguments.recording)
        output = arguments.output or os.path.splitext(arguments.recording)[0] + ".gif"
        started = time.monotonic()
        print(render_recording(recording, output))
        print("pepperFigure: %.1f s of recording rendered in %.1f s" % (
            recording.times[-1] - recording.times[0], time.monotonic() - started), file=sys.stderr)
        if arguments.clearance:
            print("\n".join(per_arm_lines(recorded_clearances(recording.joint_names, recording.positions),
                                          recording.times)))
    except (OSError, ValueError) as error:
        print("pepperFigure: error: %s" % error, file=sys.stderr)
        return 1
    return 0
