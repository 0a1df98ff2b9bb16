"""Unit tests of the model of naoqi_driver in the simulated Pepper (pepper/simulated_pepper.py, `NaoqiDriver`): each
/joint_angles message is one ALMotion setAngles call, executed at once; no ROS."""
import math

import numpy
import pytest

from cssr_system.pepper.joint_table import JOINTS, PARTS
from cssr_system.pepper.simulated_pepper import (LENGTHS_DIFFER, NAOQI_DCM, NAOQI_DRIVER, NOT_FINITE,
                                                 SPEED_OUT_OF_RANGE, UNKNOWN_JOINT, GoalPoint, NaoqiDriver,
                                                 SimulatedPepper, joint_angles_problem)

NAMES = ("RShoulderPitch", "RElbowRoll", "HipPitch")
START = (1.5, 0.3, -0.1)


def vmax(name):
    return JOINTS[name].max_velocity


def test_a_joint_moves_at_constant_speed_to_its_target_then_stands_still():
    driver = NaoqiDriver(NAMES, START, 0.0)
    driver.set_angles(["RShoulderPitch"], [1.0], 0.1, 1.0)
    speed = 0.1 * vmax("RShoulderPitch")
    arrival = 1.0 + 0.5 / speed
    for now in numpy.linspace(1.0, arrival, 7)[:-1]:
        positions, velocities = driver.state(now)
        assert positions[0] == pytest.approx(1.5 - speed * (now - 1.0), abs=1e-12)
        assert velocities[0] == pytest.approx(-speed)
    for now in (arrival, arrival + 0.01, arrival + 10.0):
        positions, velocities = driver.state(now)
        assert positions[0] == 1.0 and velocities[0] == 0.0  # exactly the target, not a rounding error away
    assert tuple(positions[1:]) == START[1:] and not velocities[1:].any()  # joints not named stay


def test_state_depends_only_on_the_time_asked():
    driver = NaoqiDriver(NAMES, START, 0.0)
    driver.set_angles(NAMES, [1.2, 0.6, 0.2], 0.05, 0.0)
    late = driver.state(3.0)
    early = driver.state(0.4)
    numpy.testing.assert_array_equal(driver.state(3.0)[0], late[0])
    numpy.testing.assert_array_equal(driver.state(0.4)[0], early[0])


def test_targets_beyond_the_limits_are_clamped():
    driver = NaoqiDriver(NAMES, START, 0.0)
    driver.set_angles(["HipPitch", "RElbowRoll"], [5.0, -5.0], 0.2, 0.0)
    positions, velocities = driver.state(10.0)
    assert positions[2] == JOINTS["HipPitch"].upper and positions[1] == JOINTS["RElbowRoll"].lower
    assert not velocities.any()


def test_a_newer_call_takes_over_only_the_joints_it_names():
    driver = NaoqiDriver(NAMES, START, 0.0)
    driver.set_angles(["RShoulderPitch", "RElbowRoll"], [1.0, 0.8], 0.1, 0.0)
    before, _ = driver.state(0.2)
    driver.set_angles(["RShoulderPitch"], [2.0], 0.05, 0.2)  # turns back, slower
    positions, velocities = driver.state(0.3)
    assert positions[0] == pytest.approx(before[0] + 0.05 * vmax("RShoulderPitch") * 0.1)
    assert velocities[0] == pytest.approx(0.05 * vmax("RShoulderPitch"))
    # The elbow keeps its own target and speed from the first call.
    assert positions[1] == pytest.approx(min(0.8, 0.3 + 0.1 * vmax("RElbowRoll") * 0.3))
    assert driver.state(100.0)[0].tolist() == [2.0, 0.8, -0.1]
    assert driver.calls == 2


def test_relative_angles_add_to_where_the_joint_is():
    driver = NaoqiDriver(NAMES, START, 0.0)
    driver.set_angles(["HipPitch"], [0.5], 0.1, 0.0)
    here = driver.state(0.5)[0][2]
    driver.set_angles(["HipPitch"], [-0.05], 0.1, 0.5, relative=True)
    assert driver.state(5.0)[0][2] == pytest.approx(here - 0.05)


def test_no_joint_ever_moves_faster_than_its_speed_asks_nor_leaves_its_limits():
    rng = numpy.random.default_rng(4)
    lower = numpy.array([joint.lower for joint in JOINTS.values()])
    upper = numpy.array([joint.upper for joint in JOINTS.values()])
    driver = NaoqiDriver(tuple(JOINTS), (lower + upper) / 2, 0.0)
    caps = numpy.zeros(len(JOINTS))  # speed each joint was last given
    for now in numpy.arange(0.05, 5.0, 0.05):
        names = [name for name in JOINTS if rng.random() < 0.5]
        speed = float(rng.uniform(0.01, 1.0))
        driver.set_angles(names, [rng.uniform(JOINTS[name].lower - 0.2, JOINTS[name].upper + 0.2) for name in names],
                          speed, now)
        caps[[name in names for name in JOINTS]] = speed * numpy.array([vmax(name) for name in names])
        positions, velocities = driver.state(now + 0.025)
        moved = numpy.abs(positions - driver.state(now)[0]) / 0.025
        assert (moved <= caps * (1 + 1e-9) + 1e-12).all() and (numpy.abs(velocities) <= caps).all()
        assert ((positions >= lower) & (positions <= upper)).all()


@pytest.mark.parametrize("names, angles, speed, problem", [
    (["RShoulderPitch", "RElbowRoll"], [1.0], 0.1, LENGTHS_DIFFER),
    (["Body"], [0.0], 0.1, UNKNOWN_JOINT),
    (["RShoulderPitch"], [math.nan], 0.1, NOT_FINITE),
    (["RShoulderPitch"], [1.0], math.inf, NOT_FINITE),
    (["RShoulderPitch"], [1.0], 0.0, SPEED_OUT_OF_RANGE),
    (["RShoulderPitch"], [1.0], 1.01, SPEED_OUT_OF_RANGE),
    (["RShoulderPitch"], [1.0], -0.1, SPEED_OUT_OF_RANGE),
])
def test_an_invalid_call_is_refused_and_changes_nothing(names, angles, speed, problem):
    assert joint_angles_problem(names, angles, speed) == problem
    driver = NaoqiDriver(NAMES, START, 0.0)
    with pytest.raises(ValueError, match=problem.replace("(", r"\(").replace("]", r"\]")):
        driver.set_angles(names, angles, speed, 0.0)
    assert driver.state(5.0)[0].tolist() == list(START) and driver.calls == 0


def test_full_speed_and_an_empty_call_are_valid():
    assert joint_angles_problem(["HeadYaw"], [0.1], 1.0) is None
    assert joint_angles_problem([], [], 0.5) is None


def test_the_simulated_pepper_moves_its_joints_by_joint_angles_only():
    pepper = SimulatedPepper("robot", driver=NAOQI_DRIVER)
    joints = PARTS["RArm"].joints
    index = pepper.joint_names.index("RShoulderPitch")
    start = pepper.joint_state(0.0).positions[index]
    target = [c + (0.3 if name == "RShoulderPitch" else 0.0) for name, c in zip(joints, PARTS["RArm"].centre)]
    pepper.controllers["RArm"].submit("goal", joints, [GoalPoint(0.5, target, None, None)], 0.0)
    pepper.update(1.0)
    # The controller runs its goal, but the robot runs naoqi_driver: nothing writes the command to the joint.
    assert pepper.commanded_state(1.0).positions[index] == pytest.approx(target[0])
    assert pepper.joint_state(1.0).positions[index] == start
    assert pepper.joint_angles(["RShoulderPitch"], [start - 0.2], 0.1, 0, 1.0) is None
    later = pepper.joint_state(3.0)
    assert later.positions[index] == pytest.approx(start - 0.2)
    assert later.positions[-3:] == [0.0, 0.0, 0.0] and later.names[-3:] == ("WheelFL", "WheelFR", "WheelB")
    assert pepper.joint_angles(["RShoulderPitch"], [0.0], 2.0, 0, 3.0) == SPEED_OUT_OF_RANGE
    assert pepper.joint_angles(["RShoulderPitch"], [0.1], 0.1, 1, 3.0) is None  # relative
    assert pepper.joint_state(10.0).positions[index] == pytest.approx(start - 0.1)


def test_joint_angles_needs_the_naoqi_driver():
    for driver in ("ideal", NAOQI_DCM):
        with pytest.raises(RuntimeError):
            SimulatedPepper("robot", driver=driver).joint_angles(["HipPitch"], [0.0], 0.1, 0, 0.0)


def test_what_naoqi_driver_is_commanded_is_each_joints_latest_target():
    pepper = SimulatedPepper("robot", driver=NAOQI_DRIVER)
    index = pepper.joint_names.index("RShoulderPitch")
    start = pepper.joint_state(0.0).positions[index]
    assert pepper.driver_commands(0.0).positions == pepper.joint_state(0.0).positions  # no call yet: where it rests
    pepper.joint_angles(["RShoulderPitch"], [start - 0.2], 0.1, 0, 1.0)
    commanded = pepper.driver_commands(1.1)
    assert commanded.positions[index] == pytest.approx(start - 0.2)
    assert commanded.velocities[index] < 0.0 and pepper.driver_commands(9.0).velocities[index] == 0.0
    assert commanded.names == pepper.joint_names


def test_without_naoqi_driver_the_commands_are_the_controllers():
    pepper = SimulatedPepper("robot", driver="naoqi_dcm")
    assert pepper.driver_commands(0.5) == pepper.commanded_state(0.5)
