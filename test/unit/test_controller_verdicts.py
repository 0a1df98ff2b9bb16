"""The simulated Pepper's verdicts on goals (pepper/simulated_pepper.py): a control loop at a fixed rate reads the
hardware, and at the end of a goal checks the goal tolerances, as joint_trajectory_controller does."""
import math
import re

import numpy
import pytest

from cssr_system.motion.trajectory_timing import time_trajectory
from cssr_system.pepper.joint_table import CONTROLLER_JOINTS, HEAD_PART, PARTS
from cssr_system.pepper.simulated_pepper import (COMMANDED, GOAL_TOLERANCE_VIOLATED, MEASURED,
                                                 PATH_TOLERANCE_VIOLATED, PLATFORMS, SUCCESSFUL, ZERO, GoalPoint,
                                                 GoalTolerances, JointTolerance, SimulatedController, SimulatedPepper,
                                                 check_loop_settings, controller_posture)

ARM = CONTROLLER_JOINTS["RArm"]  # RShoulderPitch, RShoulderRoll, RElbowYaw, RElbowRoll, RWristYaw
CENTRE = numpy.array(controller_posture("RArm"))
OFFSET = 0.1  # rad: how far from the centre the arm is when it returns there
ROBOT_RATE = 12.0  # Hz: the robot's driver runs its controllers at this rate


def arm(rate=50.0, report=MEASURED, start=None, now=0.0, **constraints):
    return SimulatedController("RightArm_controller", ARM, CENTRE if start is None else start, now, rate, report,
                               **constraints)


def return_to_centre():
    """The node's return to the centre from OFFSET away: one rest-to-rest quintic point, 0.5 s."""
    start = CENTRE + OFFSET
    timed = time_trajectory(numpy.array([CENTRE]), ARM, start, numpy.zeros(len(ARM)), 0.5)
    points = [GoalPoint(float(time), list(positions), list(velocities), list(accelerations))
              for time, positions, velocities, accelerations in zip(timed.times, timed.positions, timed.velocities,
                                                                    timed.accelerations)]
    assert [point.time_from_start for point in points] == [0.5]
    return start, points


def linear(target, duration):
    """One point without velocities: the controller moves at a constant speed and arrives moving."""
    return [GoalPoint(duration, list(target))]


def everyone(**fields):
    return [JointTolerance(joint, **fields) for joint in ARM]


# -- the end of a goal -------------------------------------------------------------------------------
@pytest.mark.parametrize("report", [MEASURED, ZERO, COMMANDED])
def test_a_goal_at_rest_succeeds_at_the_first_update_past_its_end(report):
    controller = arm(report=report)
    controller.submit("goal", ARM, linear(CENTRE, 0.5), 0.013)  # ends at 0.513, between updates
    assert controller.update(0.519) == []
    [outcome] = controller.update(0.6)
    assert (outcome.goal, outcome.error_code, outcome.error_string) == ("goal", SUCCESSFUL, "")
    assert outcome.time == pytest.approx(0.52)
    assert controller.active_goal is None


@pytest.mark.parametrize("rate", [50.0, ROBOT_RATE])
def test_the_return_to_the_centre_aborts_with_measured_velocities(rate):
    # The fault of the node's return to the centre: the quintic arrives at rest, but the velocity measured over
    # the last period is still above 0.01 rad/s at the end, and the goal time is 0.
    start, points = return_to_centre()
    controller = arm(rate, MEASURED, start)
    controller.submit("goal", ARM, points, 0.0)
    [outcome] = controller.update(2.0)
    assert outcome.error_code == GOAL_TOLERANCE_VIOLATED
    assert outcome.time == pytest.approx(0.5)
    assert re.fullmatch(r"RShoulderPitch goal error -0\.\d{6}", outcome.error_string), outcome.error_string
    assert numpy.allclose(controller.state(2.0).positions, CENTRE)  # the verdict does not change the motion


@pytest.mark.parametrize("rate", [50.0, ROBOT_RATE])
def test_the_return_to_the_centre_succeeds_when_no_velocity_is_reported(rate):
    start, points = return_to_centre()
    controller = arm(rate, ZERO, start)
    controller.submit("goal", ARM, points, 0.0)
    [outcome] = controller.update(2.0)
    assert (outcome.error_code, outcome.time) == (SUCCESSFUL, pytest.approx(0.5))


@pytest.mark.parametrize("rate", [50.0, ROBOT_RATE])
@pytest.mark.parametrize("where", ["goal", "controller"])
def test_a_goal_time_lets_the_return_to_the_centre_settle(rate, where):
    start, points = return_to_centre()
    controller = arm(rate, MEASURED, start, goal_time=0.5 if where == "controller" else 0.0)
    controller.submit("goal", ARM, points, 0.0,
                      tolerances=GoalTolerances(goal_time=0.5) if where == "goal" else None)
    [outcome] = controller.update(2.0)
    assert outcome.error_code == SUCCESSFUL
    # The joints stop at the end; the velocity measured over the next one or two periods falls inside.
    assert 0.5 < outcome.time <= 0.5 + 2.0 / rate + 1e-9


def test_a_negative_goal_time_tolerance_sets_the_goal_time_to_zero():
    start, points = return_to_centre()
    controller = arm(50.0, MEASURED, start, goal_time=0.5)
    controller.submit("goal", ARM, points, 0.0, tolerances=GoalTolerances(goal_time=-1.0))
    [outcome] = controller.update(2.0)
    assert (outcome.error_code, outcome.time) == (GOAL_TOLERANCE_VIOLATED, pytest.approx(0.5))


def test_a_negative_goal_tolerance_disables_the_check():
    start, points = return_to_centre()
    controller = arm(50.0, MEASURED, start)
    controller.submit("goal", ARM, points, 0.0, tolerances=GoalTolerances(goal=everyone(velocity=-1.0)))
    [outcome] = controller.update(2.0)
    assert (outcome.error_code, outcome.time) == (SUCCESSFUL, pytest.approx(0.5))


def test_a_zero_goal_tolerance_keeps_the_controllers():
    start, points = return_to_centre()
    controller = arm(50.0, MEASURED, start)
    controller.submit("goal", ARM, points, 0.0, tolerances=GoalTolerances(goal=everyone()))
    assert controller.update(2.0)[0].error_code == GOAL_TOLERANCE_VIOLATED


def test_the_stopped_velocity_tolerance_is_the_controllers_setting():
    start, points = return_to_centre()
    controller = arm(50.0, MEASURED, start, stopped_velocity_tolerance=0.05)
    controller.submit("goal", ARM, points, 0.0)
    assert controller.update(2.0)[0].error_code == SUCCESSFUL


@pytest.mark.parametrize("goal_time, verdict, at", [(0.0, GOAL_TOLERANCE_VIOLATED, 0.5),
                                                    (0.05, GOAL_TOLERANCE_VIOLATED, 0.5),
                                                    (0.1, SUCCESSFUL, 7.0 / ROBOT_RATE)])
def test_a_violated_goal_position_aborts_once_the_goal_time_is_over(goal_time, verdict, at):
    # At 12 Hz a linear motion ending at 0.44 s is first judged at 0.5 s, where the joints report where they were
    # sent at 5/12 s: still short of the target. They are there at the next update, 7/12 s.
    target = CENTRE + numpy.array([0.5, 0.0, 0.0, 0.0, 0.0])
    controller = arm(ROBOT_RATE, ZERO)
    tolerances = GoalTolerances(goal=[JointTolerance("RShoulderPitch", position=0.01)], goal_time=goal_time)
    controller.submit("goal", ARM, linear(target, 0.44), 0.0, tolerances=tolerances)
    [outcome] = controller.update(2.0)
    assert (outcome.error_code, outcome.time) == (verdict, pytest.approx(at))
    if verdict == GOAL_TOLERANCE_VIOLATED:
        error = 0.5 * (0.44 - 5.0 / ROBOT_RATE) / 0.44
        assert outcome.error_string == "RShoulderPitch goal error {:f}".format(error)


def test_the_error_string_is_printed_as_the_controller_prints_a_double():
    # Six decimals, whatever failed: here the velocity fails and the position error is shown.
    start, points = return_to_centre()
    controller = arm(50.0, MEASURED, start)
    controller.submit("goal", ARM, points, 0.0)
    [outcome] = controller.update(0.5)  # the verdict's update is the last one
    error = controller.last_update.error.positions[0]
    assert outcome.error_string == "RShoulderPitch goal error " + "%f" % error
    assert abs(error) < 1e-3 and abs(controller.last_update.error.velocities[0]) > 0.01


def test_every_joint_must_be_inside_and_the_first_outside_is_named():
    start, points = return_to_centre()
    controller = arm(50.0, MEASURED, start)
    unchecked = GoalTolerances(goal=[JointTolerance("RShoulderPitch", velocity=-1.0),
                                     JointTolerance("RShoulderRoll", velocity=-1.0)])
    controller.submit("goal", ARM, points, 0.0, tolerances=unchecked)
    [outcome] = controller.update(2.0)
    assert outcome.error_string.startswith("RElbowYaw goal error ")


# -- the path -------------------------------------------------------------------------------------------
def test_a_path_tolerance_violation_aborts_during_the_motion():
    target = CENTRE + numpy.array([0.5, 0.0, 0.0, 0.0, 0.0])
    controller = arm(50.0, MEASURED)
    tolerances = GoalTolerances(path=[JointTolerance("RShoulderPitch", position=0.001)])
    controller.submit("goal", ARM, linear(target, 1.0), 0.0, tolerances=tolerances)
    # At the first update the joint still reports the start, the command is 0.5 rad/s * 0.02 s ahead.
    [outcome] = controller.update(0.02)
    assert (outcome.error_code, outcome.time) == (PATH_TOLERANCE_VIOLATED, pytest.approx(0.02))
    assert outcome.error_string == "RShoulderPitch path error 0.010000"
    assert controller.active_goal is None
    assert controller.update(2.0) == []
    assert numpy.allclose(controller.state(2.0).positions, target)  # the motion runs on


def test_a_loose_path_tolerance_is_met():
    target = CENTRE + numpy.array([0.5, 0.0, 0.0, 0.0, 0.0])
    controller = arm(50.0, COMMANDED)
    tolerances = GoalTolerances(path=everyone(position=0.02, velocity=0.001))
    controller.submit("goal", ARM, linear(target, 1.0), 0.0, tolerances=tolerances)
    assert controller.update(2.0)[0].error_code == SUCCESSFUL


# -- the loop and the hardware ----------------------------------------------------------------------------
def test_the_hardware_reports_the_last_command_and_its_change_over_a_period():
    target = CENTRE + numpy.array([0.3, -0.2, 0.1, 0.2, 0.0])
    controller = arm(50.0, MEASURED)
    controller.submit("goal", ARM, [GoalPoint(1.0, list(target), [0.0] * 5)], 0.0)
    previous, fastest = None, 0.0
    for step in range(1, 60):
        controller.update(step * 0.02)
        update = controller.last_update
        assert update.time == pytest.approx(step * 0.02)
        if previous is not None:
            assert numpy.array_equal(update.actual.positions, previous.desired.positions)
            assert numpy.allclose(update.actual.velocities,
                                  (update.actual.positions - previous.actual.positions) / 0.02, atol=1e-12)
        previous, fastest = update, max(fastest, numpy.abs(update.actual.velocities).max())
    assert fastest > 0.1 and not previous.actual.velocities.any()  # it moved, and it is at rest again


def test_updates_run_at_whole_periods_from_the_start_whenever_the_caller_asks():
    controller = arm(ROBOT_RATE, ZERO, now=10.0)
    controller.submit("goal", ARM, linear(CENTRE + 0.1, 1.0), 10.0)
    controller.update(10.3)
    assert controller.last_update.time == pytest.approx(10.0 + 3.0 / ROBOT_RATE)
    controller.update(10.3)
    assert controller.last_update.time == pytest.approx(10.0 + 3.0 / ROBOT_RATE)


def test_zero_reports_no_velocity_and_commanded_reports_the_desired_state():
    target = CENTRE + 0.2
    zero, commanded = arm(report=ZERO), arm(report=COMMANDED)
    for controller in (zero, commanded):
        controller.submit("goal", ARM, linear(target, 1.0), 0.0)
        controller.update(0.5)
    assert not zero.last_update.actual.velocities.any()
    assert numpy.allclose(zero.reported_state(0.5).positions, zero.state(0.48).positions)
    assert numpy.array_equal(commanded.reported_state(0.5).positions, commanded.state(0.5).positions)
    assert numpy.array_equal(commanded.reported_state(0.51).velocities, commanded.state(0.51).velocities)


def test_a_long_idle_time_costs_nothing_and_changes_nothing():
    controller = arm()
    assert controller.update(1e7) == []
    controller.submit("goal", ARM, linear(CENTRE, 0.5), 1e7)
    [outcome] = controller.update(1e7 + 1.0)
    assert outcome.error_code == SUCCESSFUL


def test_a_goal_that_ended_before_the_next_event_keeps_its_verdict():
    # The updates due before an event run first: the first goal's end is judged before the second goal comes.
    start, points = return_to_centre()
    controller = arm(50.0, MEASURED, start)
    controller.submit("first", ARM, points, 0.0)
    acceptance = controller.submit("second", ARM, linear(CENTRE, 0.5), 0.7)
    assert acceptance.accepted and acceptance.preempted_goal is None
    assert not controller.cancel("first", 0.7)
    assert [(outcome.goal, outcome.error_code) for outcome in controller.update(2.0)] == [
        ("first", GOAL_TOLERANCE_VIOLATED), ("second", SUCCESSFUL)]


def test_a_command_topic_trajectory_is_never_judged():
    start, points = return_to_centre()
    controller = arm(50.0, MEASURED, start)
    controller.submit("goal", ARM, linear(start, 5.0), 0.0)
    acceptance = controller.command(ARM, points, 0.1)
    assert acceptance.accepted and acceptance.preempted_goal == "goal"
    assert controller.update(3.0) == []
    assert numpy.allclose(controller.state(3.0).positions, CENTRE)


def test_a_stop_goal_succeeds_at_the_next_update_whatever_it_asks():
    controller = arm(50.0, MEASURED)
    controller.submit("moving", ARM, linear(CENTRE + 0.3, 1.0), 0.0)
    controller.submit("stop", ARM, [], 0.5, tolerances=GoalTolerances(goal=everyone(position=1e-9)))
    [outcome] = controller.update(0.52)
    assert (outcome.goal, outcome.error_code, outcome.time) == ("stop", SUCCESSFUL, pytest.approx(0.52))


# -- joint order -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("platform", list(PLATFORMS))
def test_each_controller_lists_its_joints_in_the_robots_order(platform):
    pepper = SimulatedPepper(platform)
    for key, controller in pepper.controllers.items():
        assert controller.joint_names == CONTROLLER_JOINTS[key]
        own = HEAD_PART if key == HEAD_PART.key else PARTS[key]
        assert sorted(controller.joint_names) == sorted(own.joints)
        by_name = dict(zip(own.joints, own.centre))  # it starts at the part's centre, joint by joint
        assert controller.state(0.0).positions.tolist() == [by_name[joint] for joint in controller.joint_names]
    assert CONTROLLER_JOINTS["LArm"] == ("LShoulderPitch", "LShoulderRoll", "LElbowYaw", "LElbowRoll", "LWristYaw")
    assert CONTROLLER_JOINTS["Leg"] == ("HipRoll", "HipPitch", "KneePitch")
    assert CONTROLLER_JOINTS["Head"] == ("HeadYaw", "HeadPitch")


def test_a_goal_in_the_nodes_joint_order_is_mapped_by_name():
    pepper = SimulatedPepper("robot", velocity_report=COMMANDED)
    leg = pepper.controllers["Leg"]
    names = PARTS["Leg"].joints  # HipPitch, HipRoll, KneePitch
    target = {"HipPitch": -0.3, "HipRoll": 0.1, "KneePitch": 0.2}
    tolerances = GoalTolerances(goal=[JointTolerance("KneePitch", position=1e-6)])
    leg.submit("goal", names, [GoalPoint(1.0, [target[name] for name in names])], 0.0, tolerances=tolerances)
    assert [outcome.error_code for _, outcome in pepper.update(1.0)] == [SUCCESSFUL]
    assert leg.state(1.0).positions.tolist() == pytest.approx([target[name] for name in leg.joint_names])
    positions = dict(zip(*pepper.joint_state(1.0)[:2]))
    assert {name: positions[name] for name in names} == pytest.approx(target)


def test_joint_states_report_what_the_hardware_reports():
    pepper = SimulatedPepper("robot")  # MEASURED
    arm_ = pepper.controllers["RArm"]
    arm_.submit("goal", ARM, linear(CENTRE + numpy.array([0.2, -0.2, 0.2, 0.2, 0.2]), 1.0), 0.0)
    sample = pepper.joint_state(0.51)
    reported = dict(zip(sample.names, zip(sample.positions, sample.velocities)))
    actual = arm_.last_update.actual
    assert arm_.last_update.time == pytest.approx(0.5)
    for index, joint in enumerate(ARM):
        assert reported[joint] == pytest.approx((actual.positions[index], actual.velocities[index]))
        assert abs(reported[joint][1]) == pytest.approx(0.2)


# -- settings --------------------------------------------------------------------------------------------
@pytest.mark.parametrize("settings, name", [
    ((0.0, MEASURED, 0.0, 0.01), "control_rate"),
    ((math.inf, MEASURED, 0.0, 0.01), "control_rate"),
    (("50", MEASURED, 0.0, 0.01), "control_rate"),
    ((50.0, "exact", 0.0, 0.01), "velocity_report"),
    ((50.0, MEASURED, -0.1, 0.01), "goal_time"),
    ((50.0, MEASURED, 0.0, float("nan")), "stopped_velocity_tolerance"),
])
def test_bad_loop_settings_are_named(settings, name):
    with pytest.raises(ValueError, match="^" + name):
        check_loop_settings(*settings)
    with pytest.raises(ValueError, match=name):
        SimulatedPepper("robot", control_rate=settings[0], velocity_report=settings[1], goal_time=settings[2],
                        stopped_velocity_tolerance=settings[3])


def test_tolerances_as_the_action_message_carries_them():
    control_msgs = pytest.importorskip("control_msgs.msg")
    start, points = return_to_centre()
    controller = arm(50.0, MEASURED, start)
    goal = control_msgs.FollowJointTrajectoryGoal()
    goal.goal_tolerance = [control_msgs.JointTolerance(name=joint, velocity=-1.0) for joint in ARM]
    tolerances = GoalTolerances(goal.path_tolerance, goal.goal_tolerance, goal.goal_time_tolerance.to_sec())
    controller.submit("goal", ARM, points, 0.0, tolerances=tolerances)
    assert controller.update(2.0)[0].error_code == SUCCESSFUL
