"""Unit tests of the model of the physical robot's driver in the simulated Pepper (pepper/simulated_pepper.py):
12 Hz writes, the 0.09 rad dead band, 20 % of each joint's maximum speed."""
import numpy
import pytest

from cssr_system.pepper.joint_table import (DRIVER_JOINT_PRECISION, DRIVER_RATE, DRIVER_SPEED_FRACTION, JOINTS,
                                            PARTS)
from cssr_system.pepper.simulated_pepper import NAOQI_DCM, GoalPoint, NaoqiDcmDriver, SimulatedPepper

NAMES = ("RShoulderPitch", "RElbowRoll")
START = (1.5, 0.3)


def speed(name):
    return JOINTS[name].max_velocity * DRIVER_SPEED_FRACTION


def test_a_change_within_the_dead_band_is_not_written():
    driver = NaoqiDcmDriver(NAMES, START, 0.0)
    for step in range(1, 61):
        positions, _ = driver.update((1.5 + 0.08, 0.3 + 0.05), step * 0.05)
    numpy.testing.assert_array_equal(positions, START)
    assert driver.writes == 0


def test_a_change_beyond_the_dead_band_writes_every_joint():
    driver = NaoqiDcmDriver(NAMES, START, 0.0)
    commanded = (1.5 + DRIVER_JOINT_PRECISION + 0.01, 0.3 + 0.02)  # only the shoulder is beyond the band
    positions = None
    for step in range(1, 41):
        positions, _ = driver.update(commanded, step * 0.05)
    assert driver.writes >= 1
    numpy.testing.assert_allclose(positions, commanded, atol=1e-9)  # the elbow's small change rode along


def test_writes_happen_at_12_hz_only():
    driver = NaoqiDcmDriver(NAMES, START, 0.0)
    driver.update((1.5, 0.3), 0.0)
    moments = []
    for step in range(1, 201):  # a command that keeps running away: a write at every chance
        now = step * 0.005
        before = driver.writes
        driver.update((1.5 + 0.2 + 10.0 * now, 0.3), now)  # faster than the driver moves it
        if driver.writes > before:
            moments.append(now)
    gaps = numpy.diff(moments)
    assert gaps == pytest.approx(1.0 / DRIVER_RATE, abs=0.006)


def test_joints_move_at_20_percent_of_their_maximum_speed():
    driver = NaoqiDcmDriver(NAMES, START, 0.0)
    far = (1.5 + 1.0, 0.3 + 0.5)
    previous = numpy.array(START)
    for step in range(1, 21):
        positions, velocities = driver.update(far, step * 0.02)
        moved = positions - previous
        assert numpy.all(numpy.abs(moved) <= numpy.array([speed(n) for n in NAMES]) * 0.02 + 1e-12)
        previous = positions
    assert abs(velocities[0]) == pytest.approx(speed("RShoulderPitch"))


def test_the_simulated_pepper_shows_what_the_driver_executes():
    pepper = SimulatedPepper("robot", driver=NAOQI_DCM)
    joints = PARTS["RArm"].joints
    target = [c + (0.3 if name == "RShoulderPitch" else 0.0) for name, c in zip(joints, PARTS["RArm"].centre)]
    pepper.controllers["RArm"].submit("goal", joints, [GoalPoint(0.5, target, None, None)], 0.0)
    index = pepper.joint_names.index("RShoulderPitch")
    commanded = pepper.commanded_state(0.5).positions[index]
    executed = [pepper.joint_state(t).positions[index] for t in numpy.arange(0.0, 0.51, 0.02)][-1]
    assert commanded == pytest.approx(target[0])
    assert executed < commanded - 0.05, "the driver lags behind the controller's command"
    later = [pepper.joint_state(t).positions[index] for t in numpy.arange(0.52, 2.0, 0.02)][-1]
    assert later == pytest.approx(target[0], abs=1e-9)
