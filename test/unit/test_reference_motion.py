"""Unit tests of the benchmark's reference motion (test/benchmark/reference_motion.py): the yardstick must do at a
disable what the node does with the shipped homeOnDisable, or the stop and reply figures compare unlike work."""
import os
import sys

import numpy
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "benchmark"))

from reference_motion import ReferenceMotion, configuration_of  # noqa: E402

from cssr_system.animate_behaviour.topics import WHEELS_KEY  # noqa: E402
from cssr_system.pepper.joint_table import PARTS  # noqa: E402


class Recorder:
    def __init__(self):
        self.goals, self.turns = [], []

    def send(self, key, joints, timed):
        self.goals.append((key, tuple(joints), timed))

    def turn(self, angular_z):
        self.turns.append(angular_z)


@pytest.fixture
def motion_of():
    made = []

    def make(platform):
        configuration, topics = configuration_of(platform, {})
        recorder = Recorder()
        motion = ReferenceMotion(configuration, topics, recorder.send, recorder.turn)
        made.append(motion)
        return motion, recorder, topics

    yield make
    for motion in made:
        motion.close()


@pytest.mark.parametrize("platform", ["robot", "simulator"])
def test_a_disable_sends_every_animated_part_one_goal_back_to_its_centre(motion_of, platform):
    motion, recorder, topics = motion_of(platform)
    motion.enable()
    first = [key for key, _, _ in recorder.goals]
    assert first and set(first) <= set(PARTS) and set(first) <= set(topics)
    motion.disable()
    returns = recorder.goals[len(first):]
    assert [key for key, _, _ in returns] == first, "one return goal per part, sent before disable() returns"
    for key, joints, timed in returns:
        assert joints == PARTS[key].joints
        assert len(timed.times) == 2, "one point and its hold, as the node's return goal"
        assert numpy.allclose(timed.positions[-1], PARTS[key].centre)
        assert not numpy.any(timed.velocities[-1])


def test_a_disable_while_disabled_sends_nothing(motion_of):
    motion, recorder, _ = motion_of("robot")
    motion.enable()
    motion.disable()
    sent = len(recorder.goals)
    motion.disable()
    assert len(recorder.goals) == sent


def test_the_base_turns_back_by_what_it_turned_at_enable(motion_of):
    motion, recorder, topics = motion_of("robot")  # cmd_moveto: one command a turn
    assert WHEELS_KEY in topics
    motion.enable()
    assert len(recorder.turns) == 1
    motion.disable()
    assert len(recorder.turns) == 2
    assert recorder.turns[1] == pytest.approx(-recorder.turns[0])
