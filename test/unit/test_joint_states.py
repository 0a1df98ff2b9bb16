"""Unit tests of the measured joints (core/joint_states.py): bad /joint_states are ignored and reported once."""
import math

import genpy
import numpy
from sensor_msgs.msg import JointState

from cssr_system.core.joint_states import MAX_AGE, JointStateCache

ARM = ("RShoulderPitch", "RShoulderRoll")


class Rig:
    def __init__(self):
        self.now = 1000.0
        self.reports = []
        self.cache = JointStateCache(lambda: self.now, self.reports.append)

    def message(self, names=ARM, positions=(1.5, -0.1), stamp=None):
        message = JointState(name=list(names), position=list(positions))
        message.header.stamp = genpy.Time.from_sec(self.now if stamp is None else stamp)
        return message


def test_a_sound_message_gives_the_positions():
    rig = Rig()
    rig.cache.update(rig.message())
    numpy.testing.assert_array_equal(rig.cache.positions(ARM), [1.5, -0.1])
    assert rig.reports == []


def test_nan_and_infinite_positions_are_ignored_and_reported_once():
    rig = Rig()
    rig.cache.update(rig.message())
    for bad in (math.nan, math.inf, -math.inf):
        rig.cache.update(rig.message(positions=(bad, 0.0)))
    numpy.testing.assert_array_equal(rig.cache.positions(ARM), [1.5, -0.1])
    assert len(rig.reports) == 1 and "not a finite number" in rig.reports[0]


def test_names_and_positions_of_different_lengths_are_ignored():
    rig = Rig()
    rig.cache.update(rig.message(positions=(1.0,)))
    rig.cache.update(rig.message(positions=(1.0, 2.0, 3.0)))
    assert rig.cache.positions(ARM) is None
    assert len([text for text in rig.reports if "2 names but" in text]) == 1


def test_stamps_far_in_the_past_or_the_future_are_ignored():
    rig = Rig()
    rig.cache.update(rig.message(stamp=rig.now - 30.0))
    rig.cache.update(rig.message(stamp=rig.now + 30.0))
    assert rig.cache.positions(ARM) is None
    assert any("behind" in text for text in rig.reports)


def test_a_zero_stamp_means_now():
    rig = Rig()
    message = rig.message()
    message.header.stamp = genpy.Time()
    rig.cache.update(message)
    numpy.testing.assert_array_equal(rig.cache.positions(ARM), [1.5, -0.1])


def test_measurements_age_on_the_nodes_clock():
    rig = Rig()
    rig.cache.update(rig.message())
    rig.now += MAX_AGE + 0.01
    assert rig.cache.positions(ARM) is None


def test_a_message_without_some_joints_updates_the_others_only():
    rig = Rig()
    rig.cache.update(rig.message())
    rig.now += 0.5
    rig.cache.update(rig.message(names=("RShoulderPitch",), positions=(1.6,)))
    numpy.testing.assert_array_equal(rig.cache.positions(ARM), [1.6, -0.1])
    rig.now += 0.6  # RShoulderRoll's measurement is now 1.1 s old
    assert rig.cache.positions(ARM) is None
    assert rig.cache.positions(("RShoulderPitch",)) is not None


def test_a_joint_never_measured_is_reported_once():
    rig = Rig()
    rig.cache.update(rig.message())
    assert rig.cache.positions(ARM + ("RElbowRoll",)) is None
    assert rig.cache.positions(ARM + ("RElbowRoll",)) is None
    assert rig.reports == ["/joint_states: no measurement of RElbowRoll; planning from the plan instead"]


def test_something_that_is_not_a_joint_state_is_ignored():
    rig = Rig()
    rig.cache.update(object())
    assert len(rig.reports) == 1 and "unusable message" in rig.reports[0]


def test_held_measurements_stay_current_until_released():
    rig = Rig()
    rig.cache.update(rig.message())
    rig.cache.hold(ARM)
    rig.now += 60.0
    numpy.testing.assert_array_equal(rig.cache.positions(ARM), [1.5, -0.1])
    assert rig.cache.complete(ARM)
    rig.cache.release()
    assert rig.cache.positions(ARM) is None, "released, the old measurements are too old"
    assert not rig.cache.complete(ARM)
    rig.cache.update(rig.message(positions=(1.4, 0.0)))
    numpy.testing.assert_array_equal(rig.cache.positions(ARM), [1.4, 0.0])


def test_a_motion_of_ours_makes_the_older_measurements_of_its_joints_no_longer_count():
    rig = Rig()
    rig.cache.update(rig.message())
    rig.cache.hold(ARM)
    rig.now += 0.1
    rig.cache.moving(ARM[:1])
    assert rig.cache.positions(ARM) is None and rig.cache.complete(ARM[1:]), "the other joint stays held"
    rig.now += 0.1
    rig.cache.update(rig.message(positions=(1.2, -0.1)))
    numpy.testing.assert_array_equal(rig.cache.positions(ARM), [1.2, -0.1])  # measured since
    assert rig.reports == []


def test_a_measurement_stamped_before_the_motion_began_does_not_count():
    rig = Rig()
    rig.cache.moving(ARM)
    rig.cache.update(rig.message(stamp=rig.now - 0.01))
    assert rig.cache.positions(ARM) is None
    rig.cache.update(rig.message(stamp=rig.now))
    assert rig.cache.positions(ARM) is not None


def test_where_a_goal_of_ours_left_the_joints_is_current_and_held_while_nothing_is_listened_to():
    rig = Rig()
    rig.cache.update(rig.message())
    rig.cache.hold(ARM)
    rig.cache.moving(ARM)
    rig.now += 5.0
    rig.cache.settle(ARM, numpy.array([0.3, -0.2]))
    rig.now += 600.0
    numpy.testing.assert_array_equal(rig.cache.positions(ARM), [0.3, -0.2])
    rig.cache.release()
    rig.cache.moving(ARM)
    rig.cache.settle(ARM, [0.4, -0.2])
    rig.now += MAX_AGE + 0.01
    assert rig.cache.positions(ARM) is None, "listening: it ages as a measurement does"


def test_complete_needs_every_joint_current_and_reports_nothing():
    rig = Rig()
    assert rig.cache.complete(())
    rig.cache.update(rig.message(names=("RShoulderPitch",), positions=(1.5,)))
    assert not rig.cache.complete(ARM)
    assert rig.cache.complete(("RShoulderPitch",))
    rig.now += MAX_AGE + 0.01
    assert not rig.cache.complete(("RShoulderPitch",))
    assert rig.reports == []
