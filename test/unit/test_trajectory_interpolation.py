"""Unit tests of trajectory_interpolation: the controller's interpolation, as a sampler (no ROS)."""
import numpy
import pytest

from cssr_system.pepper.trajectory_interpolation import (CUBIC, LINEAR, QUINTIC, JointTrajectorySpline,
                                                         TrajectoryError, TrajectoryPoint,
                                                         cubic_coefficients, evaluate_polynomial,
                                                         linear_coefficients, quintic_coefficients,
                                                         sample_trajectory)

# Two joints following known polynomials p(t) = sum c_k t^k (absolute time from 0).
QUINTIC_POLYNOMIALS = numpy.array([[0.3, -0.2, 0.15, 0.04, -0.02, 0.003],
                                   [-1.0, 0.5, -0.1, 0.0, 0.01, -0.001]])
CUBIC_POLYNOMIALS = numpy.array([[0.3, -0.2, 0.15, 0.04, 0.0, 0.0],
                                 [-1.0, 0.5, -0.1, -0.02, 0.0, 0.0]])


def polynomial_state(polynomials, t):
    return evaluate_polynomial(polynomials, t)


def points_on(polynomials, times, level, offset=0.0):
    """Points on the polynomials at absolute `times`, carrying `level` derivatives."""
    points = []
    for t in times:
        p, v, a = polynomial_state(polynomials, t)
        points.append(TrajectoryPoint(t - offset, tuple(p), tuple(v) if level >= 1 else None,
                                      tuple(a) if level >= 2 else None))
    return points


def assert_reproduces(spline, polynomials, end_time):
    """The spline equals the polynomials, in position, velocity and acceleration, up to end_time."""
    times = numpy.linspace(0.0, end_time, int(round(end_time * 100)) + 1)
    positions, velocities, accelerations = sample_trajectory(spline, times)
    expected = polynomial_state(polynomials, times[:, None])
    numpy.testing.assert_allclose(positions, expected[0], atol=1e-12)
    numpy.testing.assert_allclose(velocities, expected[1], atol=1e-11)
    numpy.testing.assert_allclose(accelerations, expected[2], atol=1e-10)


def test_quintic_points_reproduce_a_quintic():
    start = polynomial_state(QUINTIC_POLYNOMIALS, 0.0)
    spline = JointTrajectorySpline(*start, points_on(QUINTIC_POLYNOMIALS, [0.7, 1.5, 3.0], 2))
    assert spline.segment_kinds == (QUINTIC,) * 3
    assert_reproduces(spline, QUINTIC_POLYNOMIALS, 3.0)


def test_cubic_points_reproduce_a_cubic_and_ignore_the_start_acceleration():
    p0, v0, _ = polynomial_state(CUBIC_POLYNOMIALS, 0.0)
    spline = JointTrajectorySpline(p0, v0, [5.0, -5.0], points_on(CUBIC_POLYNOMIALS, [0.5, 2.0, 2.4], 1))
    assert spline.segment_kinds == (CUBIC,) * 3
    assert_reproduces(spline, CUBIC_POLYNOMIALS, 2.4)


def test_position_only_points_are_joined_by_straight_lines():
    spline = JointTrajectorySpline([0.0, 1.0], [3.0, 3.0], [1.0, 1.0],
                                   [TrajectoryPoint(1.0, (1.0, 0.0)), TrajectoryPoint(3.0, (0.0, 2.0))])
    assert spline.segment_kinds == (LINEAR, LINEAR)
    positions, velocities, accelerations = sample_trajectory(spline, [0.0, 0.5, 1.5, 2.5])
    numpy.testing.assert_allclose(positions, [[0.0, 1.0], [0.5, 0.5], [0.75, 0.5], [0.25, 1.5]])
    numpy.testing.assert_allclose(velocities, [[1.0, -1.0], [1.0, -1.0], [-0.5, 1.0], [-0.5, 1.0]])
    assert numpy.all(accelerations == 0.0)


def test_a_segment_uses_the_lowest_kind_its_two_ends_carry():
    points = [TrajectoryPoint(1.0, (0.1,), (0.0,), (0.0,)),
              TrajectoryPoint(2.0, (0.2,), (0.1,)),
              TrajectoryPoint(3.0, (0.3,), (), ()),  # empty lists, as in a ROS message: not carried
              TrajectoryPoint(4.0, (0.4,), (0.0,), (0.0,)),
              TrajectoryPoint(5.0, (0.5,), (0.0,), (0.0,))]
    spline = JointTrajectorySpline([0.0], [0.0], [0.0], points)
    assert spline.segment_kinds == (QUINTIC, CUBIC, LINEAR, LINEAR, QUINTIC)


def test_before_the_start_and_after_the_end_the_joint_is_held_at_rest():
    points = points_on(QUINTIC_POLYNOMIALS, [11.0, 12.0], 2, offset=10.0)
    start = polynomial_state(QUINTIC_POLYNOMIALS, 10.0)
    spline = JointTrajectorySpline(*start, points, start_time=10.0)
    assert spline.end_time == 12.0
    for t in (0.0, 9.99):
        positions, velocities, accelerations = spline.sample(t)
        numpy.testing.assert_array_equal(positions, start[0])
        assert numpy.all(velocities == 0.0) and numpy.all(accelerations == 0.0)
    for t in (12.0 + 1e-9, 100.0):
        positions, velocities, accelerations = spline.sample(t)
        numpy.testing.assert_array_equal(positions, points[-1].positions)
        assert numpy.all(velocities == 0.0) and numpy.all(accelerations == 0.0)
    # At the start the spline is in the start state, velocity and acceleration included.
    for sampled, given in zip(spline.sample(10.0), start):
        numpy.testing.assert_allclose(sampled, given, atol=1e-12)


def test_the_start_time_shifts_the_whole_motion():
    start = polynomial_state(QUINTIC_POLYNOMIALS, 0.0)
    points = points_on(QUINTIC_POLYNOMIALS, [0.5, 1.0], 2)
    reference = JointTrajectorySpline(*start, points)
    shifted = JointTrajectorySpline(*start, points, start_time=100.0)
    times = numpy.linspace(-0.1, 1.2, 27)
    for ours, theirs in zip(sample_trajectory(reference, times), sample_trajectory(shifted, times + 100)):
        numpy.testing.assert_allclose(ours, theirs, atol=1e-9)


@pytest.mark.parametrize("level", [0, 1, 2])
@pytest.mark.parametrize("start_time", [0.0, 1234.5])
def test_sample_matches_sample_trajectory(level, start_time):
    """One time (the stop's quick path) and many times (the vectorised one) agree everywhere: before the
    start, exactly at the start and at each knot, inside segments, at the end and after it."""
    start = polynomial_state(QUINTIC_POLYNOMIALS, 0.0)
    knots = [0.5, 1.0, 1.7]
    spline = JointTrajectorySpline(*start, points_on(QUINTIC_POLYNOMIALS, knots, level), start_time=start_time)
    times = numpy.concatenate([numpy.linspace(-0.5, 2.0, 26), [0.0], knots,
                               [1.7 + 1e-12, 1.7 - 1e-12]]) + start_time
    batch = sample_trajectory(spline, times)
    for index, t in enumerate(times):
        for one, many in zip(spline.sample(t), batch):
            assert one.shape == (2,)
            numpy.testing.assert_array_equal(one, many[index])


def test_sample_without_points_holds_the_start_at_rest():
    spline = JointTrajectorySpline([0.2, 0.3], [1.0, 1.0], None, [], start_time=5.0)
    for t in (4.0, 5.0, 6.0):
        positions, velocities, accelerations = spline.sample(t)
        numpy.testing.assert_array_equal(positions, [0.2, 0.3])
        numpy.testing.assert_array_equal(velocities, [0.0, 0.0])
        numpy.testing.assert_array_equal(accelerations, [0.0, 0.0])


def test_points_at_or_before_the_start_are_dropped_like_the_controller_does():
    points = [TrajectoryPoint(0.0, (5.0,), (0.0,), (0.0,)), TrajectoryPoint(1.0, (1.0,), (0.0,), (0.0,))]
    spline = JointTrajectorySpline([0.0], [0.0], [0.0], points)
    assert len(spline.segment_kinds) == 1
    numpy.testing.assert_allclose(spline.sample(0.5)[0], [0.5])  # rest-to-rest quintic midpoint
    with pytest.raises(TrajectoryError):
        JointTrajectorySpline([0.0], [0.0], [0.0], points[:1])


def test_no_points_holds_the_start_position():
    spline = JointTrajectorySpline([0.2, 0.3], [1.0, 1.0], None, [])
    assert spline.end_time == 0.0
    positions, velocities, _ = spline.sample(5.0)
    numpy.testing.assert_array_equal(positions, [0.2, 0.3])
    assert numpy.all(velocities == 0.0)


@pytest.mark.parametrize("points", [
    [TrajectoryPoint(1.0, (0.0,)), TrajectoryPoint(1.0, (0.1,))],  # not strictly increasing
    [TrajectoryPoint(2.0, (0.0,)), TrajectoryPoint(1.0, (0.1,))],
    [TrajectoryPoint(1.0, (0.0, 0.1))],  # wrong number of joints
    [TrajectoryPoint(1.0, (0.0,), (0.0, 0.0))],
    [TrajectoryPoint(1.0, ())],  # no positions
])
def test_goals_the_controller_rejects_raise(points):
    with pytest.raises(TrajectoryError):
        JointTrajectorySpline([0.0], [0.0], [0.0], points)


def test_coefficients_follow_ros_controllers_including_zero_durations():
    # Hermite conditions at both ends for a few random segments.
    rng = numpy.random.default_rng(5)
    p0, v0, a0, p1, v1, a1 = rng.normal(size=(6, 20))
    duration = rng.uniform(0.1, 3.0, 20)
    coefficients = quintic_coefficients(p0, v0, a0, p1, v1, a1, duration)
    for tau, expected in ((0.0, (p0, v0, a0)), (duration, (p1, v1, a1))):
        for got, want in zip(evaluate_polynomial(coefficients, tau), expected):
            numpy.testing.assert_allclose(got, want, atol=1e-9)
    cubic = cubic_coefficients(p0, v0, p1, v1, duration)
    for tau, expected in ((0.0, (p0, v0)), (duration, (p1, v1))):
        for got, want in zip(evaluate_polynomial(cubic, tau)[:2], expected):
            numpy.testing.assert_allclose(got, want, atol=1e-9)
    # Zero duration: the segment is the start state (ros_controllers' rule).
    numpy.testing.assert_array_equal(quintic_coefficients(1.0, 2.0, 3.0, 9.0, 9.0, 9.0, 0.0),
                                     [1.0, 2.0, 1.5, 0.0, 0.0, 0.0])
    numpy.testing.assert_array_equal(cubic_coefficients(1.0, 2.0, 9.0, 9.0, 0.0), [1.0, 2.0, 0, 0, 0, 0])
    numpy.testing.assert_array_equal(linear_coefficients(1.0, 9.0, 0.0), [1.0, 0.0, 0, 0, 0, 0])


def test_segments_computed_together_equal_segments_computed_one_by_one():
    start = polynomial_state(QUINTIC_POLYNOMIALS, 0.0)
    points = points_on(QUINTIC_POLYNOMIALS, [0.5, 1.0, 1.7], 2) + [TrajectoryPoint(2.5, (0.1, 0.2), None, None)]
    one_by_one = JointTrajectorySpline(*start, points)
    together = JointTrajectorySpline(*start, points)
    together.compute_segments()
    assert together.segment_kinds == (QUINTIC, QUINTIC, QUINTIC, LINEAR)
    for segment in range(3):
        assert together._segment_coefficients[segment] is not None, "computed before any sample"
    assert together._segment_coefficients[3] is None, "a segment of another kind is left to its first sample"
    times = numpy.linspace(-0.2, 2.7, 59)
    for ours, theirs in zip(sample_trajectory(together, times), sample_trajectory(one_by_one, times)):
        numpy.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-15)
