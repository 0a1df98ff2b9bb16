"""Unit tests of trajectory_timing, measured on what the controller would execute (no ROS).

Every property is checked on the interpolation joint_trajectory_controller performs
(trajectory_interpolation), sampled densely, not on the numbers time_trajectory returns.
"""
import time
from unittest import mock

import numpy
import pytest
from hypothesis import given, settings, strategies as st
from conftest import ROBOT_PARTS, default_configuration

from cssr_system.motion import trajectory_timing
from cssr_system.motion.trajectory_timing import (TimedTrajectory, speed_caps, time_trajectory,
                                                  to_points)
from cssr_system.motion.waypoints import animated_parts, make_rng, random_waypoints
from cssr_system.pepper.joint_table import JOINTS, PARTS, SPEED_FRACTION
from cssr_system.pepper.trajectory_interpolation import (QUINTIC, JointTrajectorySpline, evaluate_polynomial,
                                                         quintic_coefficients, sample_trajectory)

SAMPLES_PER_SEGMENT = 150
ROUNDING = 1e-9


def spline_of(timed: TimedTrajectory, start_positions, start_velocities=None, start_accelerations=None):
    """The motion the controller makes of `timed`, starting from the given state."""
    return JointTrajectorySpline(start_positions, start_velocities, start_accelerations, to_points(timed))


class Plan:
    """One timed goal and the motion the controller makes of it."""

    def __init__(self, joints, waypoints, start, start_velocity, start_acceleration, gesture_duration):
        self.joints = tuple(joints)
        self.waypoints = numpy.asarray(waypoints, dtype=float)
        self.start = numpy.asarray(start, dtype=float)
        self.start_velocity = numpy.asarray(start_velocity, dtype=float)
        self.start_acceleration = numpy.asarray(start_acceleration, dtype=float)
        self.gesture_duration = gesture_duration
        self.timed = time_trajectory(self.waypoints, self.joints, self.start, self.start_velocity,
                                     gesture_duration, self.start_acceleration)
        self.spline = spline_of(self.timed, self.start, self.start_velocity, self.start_acceleration)
        self.caps = speed_caps(self.joints)
        self.knot_times = numpy.concatenate([[0.0], self.timed.times])
        self.knots = numpy.vstack([self.start, self.waypoints])

    def segment(self, index):
        """Dense samples (times, positions, velocities, accelerations) of one segment, ends included."""
        times = numpy.linspace(self.knot_times[index], self.knot_times[index + 1], SAMPLES_PER_SEGMENT)
        return (times,) + sample_trajectory(self.spline, times)

    def segments(self):
        return range(len(self.timed.times))


def plan_from_rest(config, part_key, rng, start=None):
    motion = animated_parts(config, [part_key])[0]
    waypoints = random_waypoints(motion, config, rng)
    centre = numpy.array(PARTS[part_key].centre)
    start = centre if start is None else start
    zeros = numpy.zeros(len(motion.joints))
    return Plan(motion.joints, waypoints, start, zeros, zeros, config.gesture_duration)


def demanding_configuration(**overrides):
    """Wide, fast motion: the speed cap binds and segments must be stretched."""
    values = dict(selected_range=1.0, arm_maximum_range=(1.0,) * 5, hand_maximum_range=1.0,
                  leg_maximum_range=(1.0,) * 3, gesture_duration=0.1, num_points=40,
                  leg_repeat_factor=4, num_points_leg=3)
    values.update(overrides)
    return default_configuration(**values)


def assert_times_valid(plan):
    times = plan.timed.times
    assert times[0] >= plan.gesture_duration
    assert numpy.all(numpy.diff(times) >= plan.gesture_duration * (1 - 1e-12))
    assert numpy.all(numpy.diff(times) > 0.0)


def assert_under_the_cap(plan, first_allowed=None):
    for index in plan.segments():
        _, _, velocities, _ = plan.segment(index)
        allowed = plan.caps if index or first_allowed is None else first_allowed
        assert numpy.all(numpy.abs(velocities) <= allowed * (1 + ROUNDING)), index


def assert_no_overshoot(plan, include_first=True):
    for index in plan.segments():
        if index == 0 and not include_first:
            continue
        _, positions, _, _ = plan.segment(index)
        low = numpy.minimum(plan.knots[index], plan.knots[index + 1])
        high = numpy.maximum(plan.knots[index], plan.knots[index + 1])
        assert numpy.all(positions >= low - ROUNDING) and numpy.all(positions <= high + ROUNDING), index


def assert_inside_limits(plan):
    lower = numpy.array([JOINTS[name].lower for name in plan.joints])
    upper = numpy.array([JOINTS[name].upper for name in plan.joints])
    for index in plan.segments():
        _, positions, _, _ = plan.segment(index)
        assert numpy.all(positions >= lower - ROUNDING) and numpy.all(positions <= upper + ROUNDING)


def assert_continuous_at_waypoints(plan):
    """Left and right limits of velocity and acceleration agree at every waypoint."""
    spline = plan.spline
    assert spline.segment_kinds == (QUINTIC,) * len(plan.timed.times)
    for index in range(1, len(plan.timed.times)):
        left = evaluate_polynomial(spline.coefficients[index - 1], spline.segment_durations[index - 1])
        right = evaluate_polynomial(spline.coefficients[index], 0.0)
        for order in range(3):
            scale = 1.0 + numpy.abs(right[order]).max()
            numpy.testing.assert_allclose(left[order], right[order], rtol=0, atol=1e-9 * scale)
        # The same through the sampler: just before and just after the waypoint, velocity and
        # acceleration differ by no more than acceleration and jerk allow over 2 epsilon.
        epsilon = 1e-6
        before = spline.sample(plan.knot_times[index] - epsilon)
        after = spline.sample(plan.knot_times[index] + epsilon)
        c_left, c_right = spline.coefficients[index - 1], spline.coefficients[index]
        duration = spline.segment_durations[index - 1]
        jerk = (numpy.abs(6 * c_left[:, 3] + 24 * c_left[:, 4] * duration + 60 * c_left[:, 5] * duration ** 2)
                + numpy.abs(6 * c_right[:, 3]))
        acceleration = numpy.abs(right[2])
        assert numpy.all(numpy.abs(before[1] - after[1]) <= 1.01 *
                         (2 * epsilon * acceleration + epsilon ** 2 * jerk) + 1e-9)
        assert numpy.all(numpy.abs(before[2] - after[2]) <= 1.01 * epsilon * jerk + 1e-9)


def assert_starts_from_the_start_state(plan):
    positions, velocities, accelerations = plan.spline.sample(0.0)
    numpy.testing.assert_allclose(positions, plan.start, atol=1e-12)
    numpy.testing.assert_allclose(velocities, plan.start_velocity, atol=1e-12)
    numpy.testing.assert_allclose(accelerations, plan.start_acceleration, atol=1e-12)


def assert_ends_at_rest(plan):
    assert numpy.all(plan.timed.velocities[-1] == 0.0)
    assert numpy.all(plan.timed.accelerations[-1] == 0.0)
    positions, velocities, accelerations = plan.spline.sample(plan.spline.end_time)
    numpy.testing.assert_allclose(positions, plan.waypoints[-1], atol=1e-9)
    assert numpy.all(numpy.abs(velocities) < 1e-9) and numpy.all(numpy.abs(accelerations) < 1e-6)


def assert_all_properties(plan):
    assert_times_valid(plan)
    assert_starts_from_the_start_state(plan)
    assert_continuous_at_waypoints(plan)
    assert_under_the_cap(plan)
    assert_no_overshoot(plan)
    assert_inside_limits(plan)
    assert_ends_at_rest(plan)


# ---------------------------------------------------------------------------------------------


def test_default_configuration_keeps_the_gesture_rhythm_and_every_property():
    config = default_configuration()
    rng = make_rng(1)
    for motion in animated_parts(config, ROBOT_PARTS):
        plan = plan_from_rest(config, motion.part, rng)
        # Nothing to stretch at the default ranges: one point per gesture duration.
        numpy.testing.assert_allclose(plan.timed.times, numpy.arange(1, 101) * config.gesture_duration)
        assert_all_properties(plan)


@pytest.mark.parametrize("gesture_duration", [0.05, 0.1, 0.5])
def test_demanding_motion_is_stretched_to_the_cap(gesture_duration):
    config = demanding_configuration(gesture_duration=gesture_duration)
    rng = make_rng(2)
    stretched = 0
    for part in ROBOT_PARTS:
        plan = plan_from_rest(config, part, rng)
        stretched += numpy.count_nonzero(numpy.diff(plan.knot_times) > gesture_duration * 1.001)
        assert_all_properties(plan)
    assert stretched > 0


def test_random_configurations_from_rest_meet_every_property():
    rng = numpy.random.default_rng(11)
    for _ in range(25):
        config = demanding_configuration(
            selected_range=float(rng.uniform(0.1, 1.0)),
            arm_maximum_range=tuple(float(x) for x in rng.uniform(0.0, 1.0, 5)),
            hand_maximum_range=float(rng.uniform(0.0, 1.0)),
            leg_maximum_range=tuple(float(x) for x in rng.uniform(0.0, 1.0, 3)),
            gesture_duration=float(rng.choice([0.05, 0.3, 1.0, 2.5])),
            num_points=int(rng.integers(1, 30)), leg_repeat_factor=1, num_points_leg=1)
        part = str(rng.choice(ROBOT_PARTS))
        lower = numpy.array([JOINTS[name].lower for name in PARTS[part].joints])
        upper = numpy.array([JOINTS[name].upper for name in PARTS[part].joints])
        assert_all_properties(plan_from_rest(config, part, rng, start=rng.uniform(lower, upper)))


@settings(max_examples=30, deadline=None)
@given(data=st.data(), count=st.integers(1, 12), gesture_duration=st.sampled_from([0.05, 0.2, 1.0, 3.0]),
       part=st.sampled_from(["RArm", "LHand", "Leg"]))
def test_arbitrary_waypoints_meet_every_property(data, count, gesture_duration, part):
    joints = PARTS[part].joints
    columns = []
    for name in joints:
        limits = JOINTS[name]
        values = st.floats(limits.lower, limits.upper, allow_nan=False)
        # Repeated values exercise flat segments and turning points.
        columns.append(data.draw(st.lists(st.one_of(values, st.just(limits.lower), st.just(0.0 if
                                                    limits.lower < 0.0 < limits.upper else limits.upper)),
                                          min_size=count + 1, max_size=count + 1)))
    knots = numpy.array(columns).T
    zeros = numpy.zeros(len(joints))
    assert_all_properties(Plan(joints, knots[1:], knots[0], zeros, zeros, gesture_duration))


def test_a_far_start_lengthens_the_first_segment_only():
    config = default_configuration()
    # An arm left raised by a gesture.
    start = numpy.array([-1.2, -1.0, 1.3, 0.3, 1.2])
    plan = plan_from_rest(config, "RArm", make_rng(4), start=start)
    distance = numpy.abs(plan.waypoints[0] - start)
    first = plan.timed.times[0]
    # A rest-to-rest move peaks at 1.875 times its mean speed at least.
    assert first >= (1.875 * distance / plan.caps).max()
    assert first > 2.0 * config.gesture_duration
    numpy.testing.assert_allclose(numpy.diff(plan.timed.times), config.gesture_duration)
    assert_all_properties(plan)


def test_a_start_inside_a_running_goal_continues_smoothly():
    """The next goal starts from the state of the current one (what the controller splices from)."""
    rng = numpy.random.default_rng(12)
    for gesture_duration in (0.5, 1.0, 2.0):
        config = default_configuration(gesture_duration=gesture_duration, num_points=20,
                                       leg_repeat_factor=2, num_points_leg=2)
        for part in ROBOT_PARTS:
            previous = plan_from_rest(config, part, rng)
            for _ in range(2):
                state = previous.spline.sample(rng.uniform(0.0, previous.spline.end_time))
                motion = animated_parts(config, [part])[0]
                plan = Plan(motion.joints, random_waypoints(motion, config, rng), *state,
                            gesture_duration)
                assert_times_valid(plan)
                assert_starts_from_the_start_state(plan)
                assert_continuous_at_waypoints(plan)
                assert_under_the_cap(plan)
                assert_no_overshoot(plan, include_first=False)  # the first segment may overshoot
                assert_inside_limits(plan)
                assert_ends_at_rest(plan)


def test_a_start_faster_than_the_cap_is_not_sped_up():
    joints = PARTS["LArm"].joints
    caps = speed_caps(joints)
    # A gesture swinging the arm away from the rest posture faster than the cap. Turning it back
    # without ever exceeding its own speed takes long enough to leave the joint limits (shoulder
    # roll): speed comes first, so limits are not checked here.
    start = numpy.array([(JOINTS[name].lower + JOINTS[name].upper) / 2.0 for name in joints])
    away = numpy.where(start >= numpy.array(PARTS["LArm"].centre), 1.0, -1.0)
    start_velocity = 1.5 * caps * away
    config = default_configuration(num_points=10)
    motion = animated_parts(config, ["LArm"])[0]
    plan = Plan(joints, random_waypoints(motion, config, make_rng(8)), start, start_velocity,
                numpy.zeros(5), config.gesture_duration)
    assert_under_the_cap(plan, first_allowed=numpy.abs(start_velocity))
    assert_no_overshoot(plan, include_first=False)
    assert_continuous_at_waypoints(plan)
    assert_ends_at_rest(plan)


def test_held_joints_stay_exactly_at_their_centre():
    config = default_configuration(behaviour=frozenset({"hands"}), num_points=30)
    rng = make_rng(9)
    for motion in animated_parts(config, ["RArm", "LArm"]):
        plan = plan_from_rest(config, motion.part, rng)
        held = ~numpy.array(motion.moving)
        assert held.sum() == 3
        times = numpy.linspace(-1.0, plan.spline.end_time + 1.0, 20000)
        positions, velocities, _ = sample_trajectory(plan.spline, times)
        assert numpy.all(positions[:, held] == plan.start[held])
        assert numpy.all(velocities[:, held] == 0.0)
        assert numpy.all(plan.timed.velocities[:, held] == 0.0)


def test_the_flow_passes_through_waypoints_without_stopping():
    """Not stop-and-go: where the path keeps its direction, the waypoint is passed moving."""
    config = default_configuration()
    plan = plan_from_rest(config, "RArm", make_rng(10))
    steps = numpy.diff(plan.knots, axis=0)
    passing = steps[:-1] * steps[1:] > 0.0  # same direction on both sides of the waypoint
    assert numpy.all(plan.timed.velocities[:-1][passing] != 0.0)
    turning = steps[:-1] * steps[1:] < 0.0
    assert numpy.all(plan.timed.velocities[:-1][turning] == 0.0)


def test_a_single_waypoint_is_reached_at_rest():
    config = default_configuration(num_points=1, leg_repeat_factor=1, num_points_leg=1)
    plan = plan_from_rest(config, "LArm", make_rng(3))
    assert plan.timed.times.shape == (1,)
    assert_all_properties(plan)


def test_zero_accelerations_with_slopes_up_to_twice_the_secant_are_monotone():
    """The fact the velocity choice relies on (module docstring), measured with the sampler."""
    slopes = numpy.linspace(0.0, 2.0, 41)
    m0, m1 = numpy.meshgrid(slopes, slopes)
    coefficients = quintic_coefficients(0.0, m0, 0.0, 1.0, m1, 0.0, 1.0)
    s = numpy.linspace(0.0, 1.0, 401)[:, None, None]
    _, velocity, _ = evaluate_polynomial(coefficients[None], s)
    assert velocity.min() >= -1e-12


def test_points_are_plain_floats_ready_for_a_message():
    config = default_configuration(num_points=5, leg_repeat_factor=1, num_points_leg=5)
    plan = plan_from_rest(config, "Leg", make_rng(5))
    points = to_points(plan.timed)
    assert len(points) == 5
    for index, point in enumerate(points):
        assert point.time == plan.timed.times[index]
        for values in (point.positions, point.velocities, point.accelerations):
            assert isinstance(values, tuple) and len(values) == 3
            assert all(type(value) is float for value in values)
    assert points[-1].velocities == (0.0, 0.0, 0.0) and points[-1].accelerations == (0.0, 0.0, 0.0)
    assert isinstance(plan.timed, TimedTrajectory)


def test_speed_caps_are_a_fraction_of_the_maximum_velocity():
    joints = PARTS["Leg"].joints
    numpy.testing.assert_allclose(speed_caps(joints),
                                  [SPEED_FRACTION * JOINTS[name].max_velocity for name in joints])


def test_invalid_input_raises():
    joints = PARTS["Leg"].joints
    with pytest.raises(ValueError):
        time_trajectory(numpy.zeros((3, 2)), joints, numpy.zeros(3), numpy.zeros(3), 1.0)
    with pytest.raises(ValueError):
        time_trajectory(numpy.zeros((3, 3)), joints, numpy.zeros(3), numpy.zeros(3), 0.0)


@pytest.mark.parametrize("configuration", [default_configuration(), demanding_configuration(num_points=100)])
def test_a_hundred_waypoints_of_five_joints_take_well_under_50_ms(configuration):
    motion = animated_parts(configuration, ["RArm"])[0]
    waypoints = random_waypoints(motion, configuration, make_rng(6))
    start = numpy.array(PARTS["RArm"].centre)
    durations = []
    for _ in range(5):
        began = time.perf_counter()
        time_trajectory(waypoints, motion.joints, start, numpy.zeros(5), configuration.gesture_duration)
        durations.append(time.perf_counter() - began)
    assert min(durations) < 0.05


def test_a_return_home_from_a_moving_joint_brakes_inside_its_band():
    # The node's return to the centre on disable: a single waypoint (the centre), from wherever a
    # running goal has the joints, bounded by the band they were animated in. The hardest case: a
    # goal swinging from edge to edge of the band, interrupted just before it reaches an edge.
    configuration = default_configuration()
    worst_outside = 0.0
    for motion in animated_parts(configuration, ROBOT_PARTS):
        lower = numpy.array([b.lower for b in motion.bounds])
        upper = numpy.array([b.upper for b in motion.bounds])
        centre = numpy.array([b.centre for b in motion.bounds])
        swing = numpy.array([lower, upper] * 5)
        running = time_trajectory(swing, motion.joints, centre, numpy.zeros(len(centre)),
                                  configuration.gesture_duration)
        spline = spline_of(running, centre)
        for before_edge in (0.05, 0.1, 0.2, 0.3, 0.4):
            start = spline.sample(float(running.times[4] - before_edge))
            home = time_trajectory(centre[None, :], motion.joints, start[0], start[1], 0.5,
                                   start_accelerations=start[2], position_bounds=(lower, upper))
            positions, velocities, _ = sample_trajectory(
                spline_of(home, *start), numpy.linspace(0.0, home.times[-1], 400))
            worst_outside = max(worst_outside, float(numpy.max(numpy.maximum(
                lower - positions, positions - upper))))
            numpy.testing.assert_allclose(home.positions[-1], centre, atol=1e-12)
            assert home.times[-1] <= 2.0
            assert numpy.all(numpy.abs(velocities) <= speed_caps(motion.joints) * (1 + 1e-9))
    assert worst_outside <= 1e-6, "a return home left its band by {} rad".format(worst_outside)


@settings(max_examples=150, deadline=None)
@given(data=st.data(), part=st.sampled_from(ROBOT_PARTS), gesture_duration=st.sampled_from([0.05, 0.5, 1.0]),
       bounded=st.booleans())
def test_a_single_waypoint_is_timed_as_the_rounds_would(data, part, gesture_duration, bounded):
    """The quick path of a single waypoint (every stop plans one per part) gives exactly what the general
    rounds give, from starts at rest, moving, accelerating, inside and outside the band."""
    joints = PARTS[part].joints
    motion = {m.part: m for m in animated_parts(default_configuration(), ROBOT_PARTS)}[part]
    lower = numpy.array([b.lower for b in motion.bounds])
    upper = numpy.array([b.upper for b in motion.bounds])
    caps = speed_caps(joints)
    unit = st.floats(-1.0, 1.0)
    draw = lambda: numpy.array([data.draw(unit) for _ in joints])  # noqa: E731
    limits_low = numpy.array([JOINTS[name].lower for name in joints])
    limits_high = numpy.array([JOINTS[name].upper for name in joints])
    start = limits_low + (limits_high - limits_low) * (draw() + 1.0) / 2.0
    velocity = draw() * caps * data.draw(st.sampled_from([0.0, 0.5, 1.2]))
    acceleration = draw() * caps * data.draw(st.sampled_from([0.0, 2.0, 10.0]))
    target = numpy.array([b.centre for b in motion.bounds])[None, :]
    bounds = (lower, upper) if bounded else None
    quick = time_trajectory(target, joints, start, velocity, gesture_duration, start_accelerations=acceleration,
                            position_bounds=bounds)
    by_rounds = trajectory_timing._time_by_rounds
    with mock.patch.object(trajectory_timing, "_time_single_waypoint",
                           lambda first, waypoints, guess: by_rounds(first, waypoints, numpy.array([guess]))):
        rounds = time_trajectory(target, joints, start, velocity, gesture_duration,
                                 start_accelerations=acceleration, position_bounds=bounds)
    for ours, theirs in zip(quick, rounds):
        numpy.testing.assert_array_equal(ours, theirs)
