"""The simulated Pepper's model: controller semantics (joint_trajectory_controller) and base kinematics."""
import math

import numpy
import pytest

from cssr_system.pepper.joint_table import (BASE_MAX_ANGULAR_ACCELERATION, BASE_MAX_ANGULAR_VELOCITY,
                                            BASE_MOVETO_ANGULAR_VELOCITY, BASE_MOVETO_SETTLE_TIME,
                                            BASE_VELOCITY_COMMAND_TIMEOUT, HEAD_PART, JOINTS, PARTS,
                                            WHEEL_JOINTS)
from cssr_system.pepper.simulated_pepper import (COMMANDED, INVALID_GOAL, INVALID_JOINTS, PLATFORMS, SUCCESSFUL,
                                                 GoalPoint, MoveToBase, SimulatedController, SimulatedPepper,
                                                 VelocityBase, action_namespace, base_topic, odometry_topic,
                                                 posture, yaw_quaternion, LimitViolation, MAX_VIOLATIONS_DESCRIBED,
                                                 describe_violations, parse_initial_positions)

LEG = PARTS["Leg"]  # HipPitch, HipRoll, KneePitch
EPSILON = 1e-9


def leg_controller(now=0.0):
    # These tests are about the motion commanded; COMMANDED hardware has no tracking error, so every goal succeeds
    # at its end. test_controller_verdicts.py judges goals with the other velocity reports.
    return SimulatedController("Pelvis_controller", LEG.joints, LEG.centre, now, velocity_report=COMMANDED)


def point(time, positions, velocities=(), accelerations=()):
    return GoalPoint(time, list(positions), list(velocities), list(accelerations))


def close(actual, expected, tolerance=1e-9):
    return numpy.allclose(numpy.asarray(actual, dtype=float), numpy.asarray(expected, dtype=float),
                          atol=tolerance, rtol=0.0)


# -- goal checks ------------------------------------------------------------------------------------
@pytest.mark.parametrize("names, words", [
    (["HipPitch", "HipRoll"], ["missing", "KneePitch"]),
    (["HipPitch", "HipRoll", "KneePitch", "HeadYaw"], ["unknown", "HeadYaw"]),
    (["HipPitch", "HipRoll", "HeadYaw"], ["missing", "KneePitch", "unknown", "HeadYaw"]),
    (["HipPitch", "HipPitch", "KneePitch"], ["missing", "HipRoll", "repeated", "HipPitch"]),
    ([], ["missing"]),
])
def test_wrong_joints_are_rejected_naming_them(names, words):
    controller = leg_controller()
    points = [point(1.0, [0.0] * len(names))]
    acceptance = controller.submit("goal", names, points, 0.0)
    assert not acceptance.accepted
    assert acceptance.error_code == INVALID_JOINTS
    for word in words:
        assert word in acceptance.error_string
    assert controller.active_goal is None


def test_an_empty_trajectory_must_still_name_the_joints():
    acceptance = leg_controller().submit("goal", [], [], 0.0)
    assert acceptance.error_code == INVALID_JOINTS


@pytest.mark.parametrize("points, words", [
    ([point(1.0, [0.0, 0.0])], ["point 0", "2 positions"]),
    ([point(1.0, [0.0] * 3), point(2.0, [0.0] * 4)], ["point 1", "4 positions"]),
    ([point(1.0, [0.0] * 3, [0.0] * 2)], ["velocities"]),
    ([point(1.0, [0.0] * 3, [0.0] * 3, [0.0])], ["accelerations"]),
    ([point(1.0, [0.0] * 3), point(1.0, [0.1] * 3)], ["increase strictly", "point 1"]),
    ([point(2.0, [0.0] * 3), point(1.0, [0.1] * 3)], ["increase strictly"]),
    ([point(1.0, [0.0, float("nan"), 0.0])], ["not finite"]),
    ([point(float("inf"), [0.0] * 3)], ["not finite"]),
])
def test_malformed_points_are_rejected_as_invalid_goal(points, words):
    controller = leg_controller()
    acceptance = controller.submit("goal", list(LEG.joints), points, 0.0)
    assert (acceptance.accepted, acceptance.error_code) == (False, INVALID_GOAL)
    for word in words:
        assert word in acceptance.error_string


def test_points_all_before_the_start_are_rejected():
    controller = leg_controller()
    # The stamp is 5 s ago: both points are in the past.
    acceptance = controller.submit("goal", list(LEG.joints), [point(1.0, [0.0] * 3), point(2.0, [0.0] * 3)],
                                   10.0, stamp=5.0)
    assert (acceptance.accepted, acceptance.error_code) == (False, INVALID_GOAL)
    assert "before the start" in acceptance.error_string
    # A single point at time_from_start 0 with "start now" is dropped too (the controller's rule).
    acceptance = controller.submit("goal", list(LEG.joints), [point(0.0, [0.0] * 3)], 10.0)
    assert acceptance.error_code == INVALID_GOAL


def test_a_rejected_goal_changes_nothing():
    controller = leg_controller()
    controller.submit("running", list(LEG.joints), [point(2.0, [0.1, 0.1, 0.1])], 0.0)
    before = controller.state(1.5)
    controller.submit("bad", ["HipPitch"], [point(1.0, [0.0])], 1.0)
    assert controller.active_goal == "running"
    assert close(controller.state(1.5).positions, before.positions)


def test_past_points_of_a_stamped_goal_are_dropped_and_the_rest_executed():
    controller = leg_controller()
    target = [0.2, 0.1, 0.0]
    # Stamp 1 s ago: the first point (0.5 s) is past, the second (3 s) is 2 s ahead.
    acceptance = controller.submit("goal", list(LEG.joints), [point(0.5, [0.0] * 3), point(3.0, target)],
                                   10.0, stamp=9.0)
    assert acceptance.accepted
    assert controller.goal_end_time == pytest.approx(12.0)
    assert close(controller.state(12.0).positions, target)


# -- interpolation -----------------------------------------------------------------------------------
def test_linear_points_are_reached_at_their_times():
    controller = leg_controller(now=5.0)
    first, second = [0.2, 0.1, 0.05], [-0.3, -0.1, 0.2]
    controller.submit("goal", list(LEG.joints), [point(1.0, first), point(3.0, second)], 5.0)
    assert close(controller.state(6.0).positions, first)
    assert close(controller.state(8.0).positions, second)
    # Linear: constant velocity inside a segment.
    expected = (numpy.array(second) - numpy.array(first)) / 2.0
    assert close(controller.state(7.0).velocities, expected)
    assert close(controller.state(6.5).velocities, expected)


def test_cubic_points_are_reached_with_their_velocities():
    controller = leg_controller()
    first, second = [0.2, 0.1, 0.05], [-0.3, -0.1, 0.2]
    velocities = [0.1, -0.05, 0.02]
    controller.submit("goal", list(LEG.joints),
                      [point(1.0, first, velocities), point(2.5, second, [0.0] * 3)], 0.0)
    state = controller.state(1.0)
    assert close(state.positions, first) and close(state.velocities, velocities)
    assert close(controller.state(2.5).positions, second)
    assert close(controller.state(2.5).velocities, [0.0] * 3)


def test_quintic_points_are_reached_with_their_velocities_and_accelerations():
    controller = leg_controller()
    first, second = [0.2, 0.1, 0.05], [-0.3, -0.1, 0.2]
    velocities, accelerations = [0.1, -0.05, 0.02], [0.3, 0.0, -0.2]
    controller.submit("goal", list(LEG.joints),
                      [point(1.0, first, velocities, accelerations), point(2.0, second, [0.0] * 3, [0.0] * 3)],
                      0.0)
    state = controller.state(1.0)
    assert close(state.positions, first)
    assert close(state.velocities, velocities)
    assert close(state.accelerations, accelerations)
    assert close(controller.state(2.0).positions, second)


def test_joints_may_come_in_any_order():
    controller = leg_controller()
    names = ["KneePitch", "HipPitch", "HipRoll"]  # controller order: HipPitch, HipRoll, KneePitch
    controller.submit("goal", names, [point(1.0, [0.3, -0.2, 0.1])], 0.0)
    assert close(controller.state(1.0).positions, [-0.2, 0.1, 0.3])


def test_the_first_segment_starts_from_the_current_state():
    controller = leg_controller()
    start = controller.state(0.0)
    controller.submit("goal", list(LEG.joints), [point(2.0, [0.3, 0.1, 0.2], [0.0] * 3)], 0.0)
    state = controller.state(0.0)
    assert close(state.positions, start.positions)
    assert close(state.velocities, [0.0] * 3)
    assert close(state.positions, LEG.centre)


def test_a_new_goal_preempts_and_is_spliced_continuously():
    controller = leg_controller()
    controller.submit("first", list(LEG.joints), [point(2.0, [0.4, 0.3, 0.3], [0.0] * 3)], 0.0)
    switch = 0.8
    before = controller.state(switch)
    assert numpy.abs(before.velocities).max() > 0.1  # moving fast when the second goal arrives
    acceptance = controller.submit("second", list(LEG.joints), [point(1.0, [-0.3, -0.2, 0.0], [0.0] * 3)],
                                   switch)
    assert acceptance.accepted and acceptance.preempted_goal == "first"
    assert controller.active_goal == "second"
    at_switch = controller.state(switch)
    assert close(at_switch.positions, before.positions) and close(at_switch.velocities, before.velocities)
    # Continuous just after the switch: position moves by about v*dt, velocity barely changes.
    later = controller.state(switch + 1e-4)
    assert close(later.positions, before.positions + before.velocities * 1e-4, 1e-6)
    assert close(later.velocities, before.velocities, 1e-2)
    # The first goal never succeeds; the second does, at its own end.
    assert controller.update(switch + 0.5) == []
    [outcome] = controller.update(switch + 1.0)
    assert outcome.goal == "second" and outcome.error_code == SUCCESSFUL
    assert close(controller.state(switch + 1.0).positions, [-0.3, -0.2, 0.0])


def test_a_stamped_goal_in_the_future_lets_the_running_motion_continue_until_it_starts():
    controller = leg_controller()
    controller.submit("first", list(LEG.joints), [point(2.0, [0.4, 0.3, 0.3])], 0.0)
    expected, meanwhile = controller.state(1.5), controller.state(1.2)
    acceptance = controller.submit("second", list(LEG.joints), [point(1.0, [0.0] * 3)], 1.0, stamp=1.5)
    assert acceptance.preempted_goal == "first"
    assert close(controller.state(1.2).positions, meanwhile.positions)
    assert close(controller.state(1.5).positions, expected.positions)
    assert close(controller.state(2.5).positions, [0.0] * 3)
    assert controller.goal_end_time == pytest.approx(2.5)


def test_cancel_holds_at_once():
    controller = leg_controller()
    controller.submit("goal", list(LEG.joints), [point(2.0, [0.4, 0.3, 0.3], [0.0] * 3)], 0.0)
    moving = controller.state(1.0)
    assert numpy.abs(moving.velocities).max() > 0.1
    assert not controller.cancel("another goal", 1.0)
    assert controller.cancel("goal", 1.0)
    assert controller.active_goal is None
    for t in (1.0, 1.5, 5.0):
        state = controller.state(t)
        assert close(state.positions, moving.positions)
        assert close(state.velocities, [0.0] * 3)
    assert controller.update(5.0) == []  # a canceled goal never succeeds
    assert not controller.cancel("goal", 5.0)


def test_an_empty_trajectory_stops_and_succeeds():
    controller = leg_controller()
    controller.submit("moving", list(LEG.joints), [point(2.0, [0.4, 0.3, 0.3])], 0.0)
    held = controller.state(1.0).positions
    acceptance = controller.submit("stop", list(LEG.joints), [], 1.0)
    assert acceptance.accepted and acceptance.preempted_goal == "moving"
    assert close(controller.state(3.0).positions, held)
    assert close(controller.state(3.0).velocities, [0.0] * 3)
    assert controller.update(1.0) == []  # the update at 1.0 ran before the goal came
    [outcome] = controller.update(1.02)  # the next one
    assert (outcome.goal, outcome.error_code, outcome.time) == ("stop", SUCCESSFUL, pytest.approx(1.02))


def test_success_comes_once_at_the_end():
    controller = leg_controller()
    controller.submit("goal", list(LEG.joints), [point(1.0, [0.1] * 3), point(2.0, [0.2] * 3)], 0.0)
    assert controller.goal_end_time == pytest.approx(2.0)
    assert controller.update(1.99) == []
    [outcome] = controller.update(2.0)
    assert (outcome.goal, outcome.error_code) == ("goal", SUCCESSFUL)
    assert controller.update(2.1) == [] and controller.active_goal is None
    state = controller.state(3.0)
    assert close(state.positions, [0.2] * 3) and close(state.velocities, [0.0] * 3)


# -- joint limits -------------------------------------------------------------------------------------
def test_points_beyond_a_limit_are_clamped_and_reported():
    controller = leg_controller()
    hip_pitch = JOINTS["HipPitch"]
    knee = JOINTS["KneePitch"]
    acceptance = controller.submit("goal", list(LEG.joints),
                                   [point(1.0, [hip_pitch.upper + 0.5, 0.0, 0.0]),
                                    point(2.0, [0.0, 0.0, knee.lower - 0.1])], 0.0)
    assert acceptance.accepted
    violations = acceptance.limit_violations
    assert [(v.joint, v.point_index) for v in violations] == [("HipPitch", 0), ("KneePitch", 1)]
    assert violations[0].value == pytest.approx(hip_pitch.upper + 0.5)
    assert violations[0].limit == pytest.approx(hip_pitch.upper)
    assert violations[1].limit == pytest.approx(knee.lower)
    assert controller.limit_violation_count == 2
    assert controller.state(1.0).positions[0] == pytest.approx(hip_pitch.upper)
    assert controller.state(2.0).positions[2] == pytest.approx(knee.lower)


def test_the_sampled_state_never_leaves_the_limits():
    controller = leg_controller()
    upper = JOINTS["HipPitch"].upper
    # A cubic through a point at the limit with a large outward velocity overshoots the limit.
    controller.submit("goal", list(LEG.joints),
                      [point(1.0, [upper, 0.0, 0.0], [3.0, 0.0, 0.0]), point(2.0, [0.0] * 3, [0.0] * 3)], 0.0)
    assert controller.limit_violation_count == 0
    overshooting = [controller.state(t) for t in numpy.linspace(1.0, 1.3, 31)]
    assert all(state.positions[0] <= upper for state in overshooting)
    assert any(state.positions[0] == upper and state.velocities[0] == 0.0 for state in overshooting)


# -- cmd_moveto ---------------------------------------------------------------------------------------
def test_moveto_turns_by_the_angle_at_its_speed_then_settles():
    base = MoveToBase(heading=0.2, now=10.0)
    assert base.command(0.0, 0.0, -0.5, 10.0) == "turning"
    duration = 0.5 / BASE_MOVETO_ANGULAR_VELOCITY
    assert base.state(10.0 + duration / 2).heading == pytest.approx(0.2 - 0.25)
    assert base.state(10.0 + duration / 2).angular_velocity == pytest.approx(-BASE_MOVETO_ANGULAR_VELOCITY)
    assert base.state(10.0 + duration).heading == pytest.approx(-0.3)
    assert base.state(10.0 + duration + 0.01).angular_velocity == 0.0
    assert base.busy_until == pytest.approx(10.0 + duration + BASE_MOVETO_SETTLE_TIME)


def test_moveto_drops_commands_while_turning_or_settling():
    base = MoveToBase()
    base.command(0.0, 0.0, 0.4, 0.0)  # turns until 0.4, settles until 1.4
    assert base.command(0.0, 0.0, 1.0, 0.2) == "dropped"  # turning
    assert base.command(0.0, 0.0, 1.0, 1.3) == "dropped"  # settling
    assert base.dropped == 2
    assert base.state(5.0).heading == pytest.approx(0.4)
    assert base.command(0.0, 0.0, 0.3, 1.4) == "turning"  # free again
    assert base.state(5.0).heading == pytest.approx(0.7)
    assert base.executed == 2


def test_moveto_keep_latest_runs_the_last_command_when_free():
    base = MoveToBase(keep_latest=True)
    base.command(0.0, 0.0, 0.4, 0.0)
    assert base.command(0.0, 0.0, 1.0, 0.2) == "queued"
    assert base.command(0.0, 0.0, -0.2, 1.0) == "queued"  # replaces the first queued one
    assert base.state(1.4).heading == pytest.approx(0.4)
    assert base.state(1.5).heading == pytest.approx(0.3)  # started exactly at 1.4
    assert base.state(3.0).heading == pytest.approx(0.2)
    assert (base.executed, base.dropped) == (2, 1)


def test_a_zero_moveto_is_a_no_op():
    base = MoveToBase()
    assert base.command(0.0, 0.0, 0.0, 0.0) == "no-op"
    assert base.state(0.5) == (0.0, 0.0)
    assert base.command(0.0, 0.0, 0.1, 0.1) == "turning"  # the no-op did not make the base busy


def test_moveto_heading_is_unwrapped():
    base = MoveToBase()
    for step in range(3):
        base.command(0.0, 0.0, 2.0, step * 10.0)
    assert base.state(100.0).heading == pytest.approx(6.0)


def test_moveto_ignores_values_that_are_not_finite():
    base = MoveToBase()
    assert base.command(0.0, 0.0, float("nan"), 0.0) == "invalid"
    assert base.state(1.0).heading == 0.0


# -- cmd_vel ------------------------------------------------------------------------------------------
def test_cmd_vel_limits_velocity_and_acceleration():
    base = VelocityBase()
    base.command(0.0, 0.0, 5.0, 0.0)
    assert base.target == BASE_MAX_ANGULAR_VELOCITY
    # Accelerating at the limit: v = a t, heading = a t^2 / 2.
    state = base.state(0.25)
    assert state.angular_velocity == pytest.approx(BASE_MAX_ANGULAR_ACCELERATION * 0.25)
    assert state.heading == pytest.approx(BASE_MAX_ANGULAR_ACCELERATION * 0.25 ** 2 / 2)
    base.command(0.0, 0.0, -5.0, 0.25)
    assert base.target == -BASE_MAX_ANGULAR_VELOCITY
    # Keep commanding: the speed never exceeds the limit and changes at most a*dt per step.
    previous = base.state(0.25).angular_velocity
    for step in range(1, 40):
        now = 0.25 + step * 0.05
        base.command(0.0, 0.0, -5.0, now)
        velocity = base.state(now).angular_velocity
        assert abs(velocity) <= BASE_MAX_ANGULAR_VELOCITY + EPSILON
        assert abs(velocity - previous) <= BASE_MAX_ANGULAR_ACCELERATION * 0.05 + EPSILON
        previous = velocity
    assert previous == pytest.approx(-BASE_MAX_ANGULAR_VELOCITY)


def test_cmd_vel_times_out_and_decelerates():
    velocity, acceleration = 0.6, BASE_MAX_ANGULAR_ACCELERATION
    base = VelocityBase()
    base.command(0.0, 0.0, velocity, 0.0)
    ramp = velocity / acceleration  # 0.25 s
    for now in (0.1, 0.2, 0.3, 0.4, 0.5, 0.6):  # streamed at 10 Hz, last message at 0.6
        base.command(0.0, 0.0, velocity, now)
    last = 0.6
    assert base.state(last + BASE_VELOCITY_COMMAND_TIMEOUT - 0.01).angular_velocity == pytest.approx(velocity)
    assert base.state(last + BASE_VELOCITY_COMMAND_TIMEOUT + 0.1).angular_velocity == pytest.approx(
        velocity - acceleration * 0.1)
    stop = last + BASE_VELOCITY_COMMAND_TIMEOUT + ramp
    assert base.state(stop).angular_velocity == pytest.approx(0.0, abs=1e-9)
    # Exact heading: ramp up, cruise, ramp down.
    cruise = stop - 2 * ramp
    assert base.state(stop + 5.0).heading == pytest.approx(velocity * ramp + velocity * cruise)
    assert base.state(stop + 5.0).angular_velocity == 0.0


def test_cmd_vel_heading_is_the_same_however_often_it_is_sampled():
    coarse, fine = VelocityBase(), VelocityBase()
    for base in (coarse, fine):
        base.command(0.0, 0.0, 1.5, 0.0)
        base.command(0.0, 0.0, -0.7, 0.4)
    for now in numpy.arange(0.0, 3.0, 0.013):
        fine.state(now)
    assert coarse.state(3.0).heading == pytest.approx(fine.state(3.0).heading, abs=1e-9)


def test_cmd_vel_an_explicit_zero_stops():
    base = VelocityBase()
    base.command(0.0, 0.0, 1.0, 0.0)
    base.command(0.0, 0.0, 0.0, 1.0)
    assert base.state(1.0 + 1.0 / BASE_MAX_ANGULAR_ACCELERATION).angular_velocity == pytest.approx(0.0)


# -- the whole robot ----------------------------------------------------------------------------------
def test_platforms_serve_the_controllers_of_the_robot_and_of_the_simulator():
    robot, simulator = PLATFORMS["robot"], PLATFORMS["simulator"]
    assert [action_namespace(robot, key) for key in robot.controller_keys] == [
        "pepper_dcm/RightArm_controller/follow_joint_trajectory",
        "pepper_dcm/LeftArm_controller/follow_joint_trajectory",
        "pepper_dcm/RightHand_controller/follow_joint_trajectory",
        "pepper_dcm/LeftHand_controller/follow_joint_trajectory",
        "pepper_dcm/Pelvis_controller/follow_joint_trajectory",
        "pepper_dcm/Head_controller/follow_joint_trajectory",
    ]
    assert [action_namespace(simulator, key) for key in simulator.controller_keys] == [
        "pepper/RightArm_controller/follow_joint_trajectory",
        "pepper/LeftArm_controller/follow_joint_trajectory",
        "pepper/Pelvis_controller/follow_joint_trajectory",
        "pepper/Head_controller/follow_joint_trajectory",
    ]
    assert (base_topic(robot), base_topic(simulator)) == ("pepper_dcm/cmd_moveto", "pepper/cmd_vel")
    assert (odometry_topic(robot), odometry_topic(simulator)) == ("pepper_dcm/odom", "pepper/odom")
    assert isinstance(SimulatedPepper("robot").base, MoveToBase)
    assert isinstance(SimulatedPepper("simulator").base, VelocityBase)
    with pytest.raises(ValueError):
        SimulatedPepper("gazebo")


@pytest.mark.parametrize("platform", list(PLATFORMS))
def test_joint_state_holds_every_joint_starting_at_rest(platform):
    pepper = SimulatedPepper(platform)
    sample = pepper.joint_state(0.0)
    assert sample.names == tuple(JOINTS) + WHEEL_JOINTS
    positions = dict(zip(sample.names, sample.positions))
    for part in list(PARTS.values()) + [HEAD_PART]:
        for joint, centre in zip(part.joints, part.centre):
            assert positions[joint] == pytest.approx(centre)
    assert all(positions[wheel] == 0.0 for wheel in WHEEL_JOINTS)
    assert sample.velocities == [0.0] * len(sample.names)


def test_joint_states_are_stamped_with_the_control_update_whose_readings_they_report():
    # A joint state broadcaster stamps each message with its update's time: a message taken between two updates
    # reports the earlier one, and saying so keeps the velocity between messages true to their stamps.
    pepper = SimulatedPepper("simulator", now=0.0)  # measured hardware, updates every 0.02 s
    arm = pepper.controllers["RArm"]
    arm.submit("goal", list(arm.joint_names), [point(1.0, [1.0, -0.5, 0.5, 1.0, 0.0])], 0.0)
    readings = [(pepper.joint_state(now).positions, pepper.reading_time(now)) for now in (0.061, 0.079, 0.081)]
    assert [time for _, time in readings] == pytest.approx([0.06, 0.06, 0.08])
    assert readings[0][0] == readings[1][0] != readings[2][0]
    commanded = SimulatedPepper("simulator", now=0.0, velocity_report=COMMANDED)
    assert commanded.reading_time(0.061) == 0.061  # the desired state at that very time


def test_the_simulator_hands_stay_at_their_centre_and_commanded_joints_move():
    pepper = SimulatedPepper("simulator", now=0.0, velocity_report=COMMANDED)  # reports exactly the command
    assert "RHand" not in pepper.controllers
    arm = pepper.controllers["RArm"]
    target = [1.0, -0.5, 0.5, 1.0, 0.0]
    arm.submit("goal", list(arm.joint_names), [point(1.0, target)], 0.0)
    assert [key for key, outcome in pepper.update(1.0)] == ["RArm"]
    positions = dict(zip(*pepper.joint_state(1.0)[:2]))
    assert [positions[joint] for joint in arm.joint_names] == pytest.approx(target)
    assert positions["RHand"] == pytest.approx(PARTS["RHand"].centre[0])


def test_postures():
    assert posture("Leg") == LEG.centre
    assert posture("Head", "zero") == (0.0, 0.0)
    assert posture("RArm", "zero")[1] == JOINTS["RShoulderRoll"].upper  # 0 is outside: clamped
    with pytest.raises(ValueError):
        posture("Leg", "crouch")


def test_yaw_quaternion():
    x, y, z, w = yaw_quaternion(math.pi / 2)
    assert (x, y) == (0.0, 0.0)
    assert (z, w) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)))
    assert math.remainder(2 * math.atan2(*yaw_quaternion(7.0)[2:]), 2 * math.pi) == pytest.approx(7.0 - 2 * math.pi)


def test_limit_violations_are_counted_over_all_controllers():
    pepper = SimulatedPepper("robot")
    for key in ("RHand", "LHand"):
        hand = pepper.controllers[key]
        hand.submit("goal", list(hand.joint_names), [point(1.0, [1.5])], 0.0)
    assert pepper.limit_violation_count == 2


def test_a_goal_beyond_the_limits_is_described_in_one_line_of_its_first_values():
    violations = [LimitViolation("RShoulderPitch", 2.2 + index, 2.0857, index) for index in range(6)]
    line = describe_violations(violations)
    assert line.startswith("point 0 RShoulderPitch = 2.2 beyond its limit 2.0857; point 1 RShoulderPitch = 3.2")
    assert line.count("beyond its limit") == MAX_VIOLATIONS_DESCRIBED
    assert line.endswith("; and 2 more")


def test_named_joints_start_where_initial_positions_says_the_others_at_their_centres():
    positions = parse_initial_positions("KneePitch=0.0022, RShoulderRoll = 0.5,LHand=0.4")
    assert positions == {"KneePitch": 0.0022, "RShoulderRoll": 0.5, "LHand": 0.4}
    pepper = SimulatedPepper("robot", initial_positions=positions)
    state = dict(zip(pepper.joint_names, pepper.joint_state(0.0).positions))
    assert state["KneePitch"] == pytest.approx(0.0022)
    assert state["RShoulderRoll"] == pytest.approx(JOINTS["RShoulderRoll"].upper)  # clamped into its limits
    assert state["LHand"] == pytest.approx(0.4)
    assert state["HipPitch"] == pytest.approx(PARTS["Leg"].centre[0])
    assert parse_initial_positions("") == {}


@pytest.mark.parametrize("text", ["Knee=0.1", "KneePitch=", "KneePitch=nan", "KneePitch"])
def test_initial_positions_that_name_no_joint_or_no_number_are_refused(text):
    with pytest.raises(ValueError):
        parse_initial_positions(text)
