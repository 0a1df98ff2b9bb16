"""pepperFigure: the GIF of a recording and of a ROS 1 bag; the clearance margin of the motion styles."""
import math
import os
import subprocess
import sys

import numpy
import pytest

from cssr_system.animate_behaviour.configuration import load_configuration, shipped_configuration_path
from cssr_system.figure.clearance import (HAND_MARGIN, close_hand_warnings, largest_quiet_selected_range,
                                          recorded_clearances)
from cssr_system.recording.figure_command import main
from cssr_system.figure.render import FRAME_RATE
from cssr_system.motion.report import commanded_run
from cssr_system.recording.recording import Recording, write_recording

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def waving_recording(seconds=3.0):
    times = numpy.arange(0.0, seconds, 0.02)
    pitch = 1.5 - 1.2 * numpy.sin(times)  # the left arm rises to the front
    positions = numpy.column_stack([pitch, numpy.full(len(times), -0.2)])
    return Recording(0.0, ("LShoulderPitch", "HipPitch"), times, positions, times, 0.5 * times,
                     activations=((0.5, "enabled"), (2.0, "disabled")), info={"platform": "simulator"})


def frames_of(path):
    from PIL import Image
    image = Image.open(path)
    return image, image.n_frames


def test_a_recording_renders_at_ten_frames_a_second_with_the_state_changing(tmp_path):
    path = write_recording(str(tmp_path / "animation.json"), waving_recording())
    assert main([path]) == 0
    image, count = frames_of(str(tmp_path / "animation.gif"))
    assert count == int(3.0 * FRAME_RATE)
    assert image.info["duration"] == 100
    first = numpy.asarray(image.convert("RGB"))
    image.seek(15)  # 1.5 s: enabled, the arm raised: the picture differs
    assert numpy.abs(numpy.asarray(image.convert("RGB")).astype(int) - first).sum() > 0


def test_an_unreadable_recording_is_one_error_line(tmp_path, capsys):
    (tmp_path / "broken.json").write_text("{")
    assert main([str(tmp_path / "broken.json")]) == 1
    assert capsys.readouterr().err.startswith("pepperFigure: error: ")


def test_a_ros1_bag_of_joint_states_and_odometry_renders(tmp_path):
    rosbag = pytest.importorskip("rosbag")
    rospy = pytest.importorskip("rospy")
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import JointState
    path = str(tmp_path / "robot.bag")
    with rosbag.Bag(path, "w") as bag:
        for step in range(20):
            stamp = rospy.Time.from_sec(100.0 + 0.1 * step)
            state = JointState(name=["RShoulderPitch", "RElbowRoll"], position=[1.5 - 0.05 * step, 0.4])
            state.header.stamp = stamp
            bag.write("/joint_states", state, stamp)
            odometry = Odometry()
            odometry.header.stamp = stamp
            odometry.pose.pose.orientation.z, odometry.pose.pose.orientation.w = math.sin(0.05), math.cos(0.05)
            bag.write("/pepper_dcm/odom", odometry, stamp)
    from cssr_system.ros1.bag_recording import recording_from_bag
    recording = recording_from_bag(path)
    assert recording.joint_names == ("RShoulderPitch", "RElbowRoll")
    assert recording.times[-1] == pytest.approx(1.9)
    assert recording.headings[0] == pytest.approx(0.1)
    script = os.path.join(REPO, "scripts", "pepperFigure.py")
    done = subprocess.run([sys.executable, script, path], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          universal_newlines=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert frames_of(str(tmp_path / "robot.gif"))[1] == 20


@pytest.fixture(scope="module")
def largest_quiet():
    config = load_configuration(shipped_configuration_path(), {"behaviour": "body", "platform": "robot"})
    return config._replace(selected_range=largest_quiet_selected_range(config), intensity=1.0)


def test_the_check_is_quiet_at_the_shipped_ranges_and_names_the_key_past_the_largest_quiet_ones(largest_quiet):
    shipped = load_configuration(shipped_configuration_path(), {"behaviour": "body"})
    assert close_hand_warnings(shipped) == []
    assert close_hand_warnings(largest_quiet) == []
    [line] = close_hand_warnings(largest_quiet._replace(selected_range=largest_quiet.selected_range + 0.05))
    assert line.split(" ", 1)[0] in ("armMaximumRange", "speakingArmRange", "legMaximumRange") and "hand within" in line


def test_the_check_names_speakings_own_bands_when_they_bring_a_hand_too_close():
    shipped = load_configuration(shipped_configuration_path(), {"behaviour": "body"})
    [line] = close_hand_warnings(shipped._replace(speaking_arm_range=(1.0,) * 5))
    assert line.startswith("speakingArmRange ") and "hand within" in line


@pytest.mark.parametrize("style", ["random", "breathing"])
def test_each_style_at_the_largest_quiet_ranges_keeps_the_hands_the_margin_from_the_body(style, largest_quiet):
    times, names, commanded = commanded_run(largest_quiet._replace(motion_style=style), 30.0, 1)
    from cssr_system.figure.body_model import arm_clearances, closest
    from cssr_system.figure.clearance import filled
    from cssr_system.figure.kinematics import link_frames
    frames = link_frames({name: filled(commanded[:, column]) for column, name in enumerate(names)})
    hands = closest(arm_clearances(frames, ("hand",), with_other_arm=False))
    assert hands.distance >= HAND_MARGIN - 0.002, hands  # 2 mm: the bands are sampled, the motion is continuous
    assert all(value.distance > 0 for value in recorded_clearances(names, commanded).values())
