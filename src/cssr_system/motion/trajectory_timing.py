"""Timing random waypoints into a goal the controller plays smoothly, slowly and without overshoot.

Knots are the start state (index 0: position, velocity, acceleration given) and the N waypoints; the
controller joins consecutive knots with Hermite quintics (trajectory_interpolation). Because every knot
carries one velocity and one acceleration shared by its two segments, velocity and acceleration are
continuous by construction. What remains to choose:

* Velocities (shape preserving, after Fritsch-Carlson / Fritsch-Butland, as in PCHIP): zero where the
  path turns back or stays (the secants on both sides differ in sign or one is zero), otherwise the
  weighted harmonic mean of the two secants, capped at twice the smaller one. With zero accelerations a
  quintic whose normalised end slopes m0 = v0 T / dp and m1 = v1 T / dp lie in [0, 2] is monotone
  (its derivative is 30 s^2 (1-s)^2 (1 - m) + m >= 0.125 for m0 = m1 = m = 2, the worst case), so no
  segment leaves the interval of its two waypoints. The last waypoint is at rest (v = a = 0).
* Accelerations: the mean of the two one-sided second derivatives of the cubic Hermite at each knot (a
  C2-like estimate), then limited: the derivative of a segment's normalised quintic is linear in
  (a0, a1), so its monotone set is convex and holds (0, 0); scaling the end accelerations of a segment
  by the largest lambda in LIMIT_SCALES for which the corners of the box [0, lambda a0] x [0, lambda a1]
  are monotone keeps every smaller pair monotone too, so one pass of "knot scale = min over its two
  segments" keeps all segments monotone. Monotonicity is certified with Bernstein coefficients on
  SUBINTERVALS pieces of [0, 1] (a polynomial lies inside the hull of its Bernstein coefficients), which
  is conservative, never optimistic.
* Durations: every segment lasts gesture_duration at least. The peak speed of each segment, bounded
  above by the same Bernstein hull, must not exceed SPEED_FRACTION of the joint's maximum: offending
  segments are stretched by their excess until none is left, then (if rounds run out) all durations are
  scaled uniformly, which scales every waypoint velocity by 1/r and acceleration by 1/r^2 and so every
  peak by 1/r exactly. The first segment, from an arbitrary start state, is timed by a search over its
  duration: the shortest that keeps its speed under the cap, its positions inside the URDF limits, and,
  for joints starting at rest, its motion monotone.
"""
import math
from typing import List, NamedTuple, Sequence

import numpy

from cssr_system.pepper.joint_table import JOINTS, speed_limit
from cssr_system.pepper.trajectory_interpolation import TrajectoryPoint, points_from_arrays, quintic_coefficients

SUBINTERVALS = 16  # pieces of [0, 1] for the Bernstein bounds
LIMIT_SCALES = (1.0, 0.5, 0.25, 0.125)  # tried in order; 0 is always monotone
MAX_STRETCH_ROUNDS = 12
STRETCH_MARGIN = 1.02  # overshoot the needed stretch a little so the rounds converge fast
FIRST_SEGMENT_GROWTH = 1.05  # ratio between durations tried for the first segment
SLOPE_LIMIT = 2.0  # normalised end slopes in [0, 2] keep a quintic with zero accelerations monotone
MONOTONE_TOLERANCE = 1e-12
LIMIT_TOLERANCE = 1e-9  # rad: rounding of a motion that ends exactly at a joint limit


class TimedTrajectory(NamedTuple):
    """The points of one goal: times from the goal's start and, per point and joint, p, v, a."""

    times: numpy.ndarray  # (N,) strictly increasing, the first >= gesture_duration
    positions: numpy.ndarray  # (N, J) the waypoints
    velocities: numpy.ndarray  # (N, J) last row zero
    accelerations: numpy.ndarray  # (N, J) last row zero


def speed_caps(joint_names: Sequence[str]) -> numpy.ndarray:
    """Highest commanded speed per joint (SPEED_FRACTION of the URDF maximum)."""
    return numpy.array([speed_limit(name) for name in joint_names])


# ---------------------------------------------------------------------------------------------
# Bernstein bounds of polynomials on [0, 1]


def _bernstein_matrix(degree: int, pieces: int) -> numpy.ndarray:
    """M such that power coefficients c (degree+1) -> c @ M are the Bernstein coefficients of the
    polynomial on each of `pieces` equal sub-intervals of [0, 1], concatenated."""
    n = degree
    to_bernstein = numpy.zeros((n + 1, n + 1))  # local power -> Bernstein: b_k = sum C(k,i)/C(n,i) l_i
    for k in range(n + 1):
        for i in range(k + 1):
            to_bernstein[k, i] = _comb(k, i) / _comb(n, i)
    blocks = []
    width = 1.0 / pieces
    for piece in range(pieces):
        origin = piece * width
        shift = numpy.zeros((n + 1, n + 1))  # global power -> local power on [origin, origin + width]
        for j in range(n + 1):
            for i in range(j + 1):
                shift[i, j] = _comb(j, i) * origin ** (j - i) * width ** i
        blocks.append(to_bernstein @ shift)
    return numpy.concatenate(blocks, axis=0).T


def _comb(n: int, k: int) -> int:
    return math.factorial(n) // (math.factorial(k) * math.factorial(n - k))


_BERNSTEIN_4 = _bernstein_matrix(4, SUBINTERVALS)
_BERNSTEIN_5 = _bernstein_matrix(5, SUBINTERVALS)

# Derivative of the normalised quintic q(s) = (p(sT) - p0) / dp as power coefficients of s, linear in
# (1, m0, m1, alpha0, alpha1) with m = v T / dp and alpha = a T^2 / dp.
_NORMALISED_DERIVATIVE = numpy.array([
    [0.0, 0.0, 30.0, -60.0, 30.0],  # the step from 0 to 1
    [1.0, 0.0, -18.0, 32.0, -15.0],  # start slope
    [0.0, 0.0, -12.0, 28.0, -15.0],  # end slope
    [0.0, 1.0, -4.5, 6.0, -2.5],  # start acceleration
    [0.0, 0.0, 1.5, -4.0, 2.5],  # end acceleration
])
_NORMALISED_DERIVATIVE_BERNSTEIN = _NORMALISED_DERIVATIVE @ _BERNSTEIN_4


def _monotone(m0, m1, alpha0, alpha1) -> numpy.ndarray:
    """True where the normalised quintic is certified non-decreasing on [0, 1] (broadcasts)."""
    m0, m1, alpha0, alpha1 = numpy.broadcast_arrays(m0, m1, alpha0, alpha1)
    parameters = numpy.stack([numpy.ones_like(m0), m0, m1, alpha0, alpha1], axis=-1)
    return (parameters @ _NORMALISED_DERIVATIVE_BERNSTEIN).min(axis=-1) >= -MONOTONE_TOLERANCE


def _segment_polynomials(p0, v0, a0, p1, v1, a1, duration) -> numpy.ndarray:
    """Power coefficients in normalised time s = tau / T of each segment's position (..., 6)."""
    coefficients = quintic_coefficients(p0, v0, a0, p1, v1, a1, duration)
    powers = numpy.asarray(duration, dtype=float)[..., None] ** numpy.arange(6)
    return coefficients * powers


def _speed_bound(polynomials, duration) -> numpy.ndarray:
    """Upper bound of |velocity| over each segment, from normalised position polynomials (..., 6)."""
    derivative = polynomials[..., 1:] * numpy.arange(1, 6)
    hull = derivative @ _BERNSTEIN_4
    return numpy.abs(hull).max(axis=-1) / numpy.asarray(duration, dtype=float)


def _position_hull(polynomials):
    """Lower and upper bounds of position over each segment."""
    hull = polynomials @ _BERNSTEIN_5
    return hull.min(axis=-1), hull.max(axis=-1)


# ---------------------------------------------------------------------------------------------
# Knot velocities and accelerations


def _knot_derivatives(knots, durations, start_velocity, start_acceleration, first_checked):
    """Velocities and accelerations at every knot (K = N + 1 rows) for the given durations."""
    count = knots.shape[0] - 1  # segments
    steps = numpy.diff(knots, axis=0)
    secants = steps / durations[:, None]
    velocities = numpy.zeros_like(knots)
    accelerations = numpy.zeros_like(knots)
    velocities[0] = start_velocity
    accelerations[0] = start_acceleration
    if count >= 2:
        left, right = secants[:-1], secants[1:]
        h_left, h_right = durations[:-1, None], durations[1:, None]
        w_left, w_right = 2.0 * h_right + h_left, h_right + 2.0 * h_left
        same_sign = left * right > 0.0
        with numpy.errstate(divide="ignore", invalid="ignore", over="ignore"):
            harmonic = (w_left + w_right) / (w_left / left + w_right / right)
        magnitude = numpy.minimum(numpy.abs(harmonic), SLOPE_LIMIT * numpy.minimum(numpy.abs(left),
                                                                                   numpy.abs(right)))
        velocities[1:-1] = numpy.where(same_sign, numpy.sign(left) * magnitude, 0.0)
        # Mean of the cubic Hermite's second derivatives at the end of the left segment and at the
        # start of the right one.
        v_prev, v_here, v_next = velocities[:-2], velocities[1:-1], velocities[2:]
        end_of_left = (-6.0 * left + 2.0 * v_prev + 4.0 * v_here) / h_left
        start_of_right = (6.0 * right - 4.0 * v_here - 2.0 * v_next) / h_right
        candidates = 0.5 * (end_of_left + start_of_right)
        # Tiny steps can overflow the normalised values: inf or NaN is never certified, scale 0.
        with numpy.errstate(over="ignore", invalid="ignore"):
            accelerations[1:-1] = candidates * _acceleration_scales(
                steps, durations, velocities, candidates, first_checked)
    return velocities, accelerations


def _acceleration_scales(steps, durations, velocities, candidates, first_checked):
    """Scale in [0, 1] per interior knot and joint keeping every checked segment monotone.

    Checked segments: those between waypoints, and the first one for joints that start at rest.
    """
    count, joints = steps.shape
    # End accelerations of every segment (zero at the start knot: it is fixed and, where checked, 0).
    alpha_start = numpy.zeros((count, joints))
    alpha_end = numpy.zeros((count, joints))
    alpha_start[1:] = candidates
    alpha_end[:-1] = candidates
    flat = steps == 0.0
    safe_steps = numpy.where(flat, 1.0, steps)
    T = durations[:, None]
    m0 = velocities[:-1] * T / safe_steps
    m1 = velocities[1:] * T / safe_steps
    m0[0] = numpy.where(first_checked, m0[0], 0.0)
    a0 = alpha_start * T * T / safe_steps
    a1 = alpha_end * T * T / safe_steps
    segment_scale = numpy.zeros((count, joints))
    unresolved = ~flat
    for scale in LIMIT_SCALES:
        if not unresolved.any():
            break
        s0, s1 = scale * a0[unresolved], scale * a1[unresolved]
        n0, n1 = m0[unresolved], m1[unresolved]
        ok = (_monotone(n0, n1, s0, s1) & _monotone(n0, n1, s0, 0.0 * s1)
              & _monotone(n0, n1, 0.0 * s0, s1))
        resolved = numpy.zeros_like(unresolved)
        resolved[unresolved] = ok
        segment_scale[resolved] = scale
        unresolved &= ~resolved
    checked = numpy.ones((count, joints), dtype=bool)
    checked[0] = first_checked
    segment_scale[~checked] = 1.0  # unchecked segments do not limit their knots
    return numpy.minimum(segment_scale[:-1], segment_scale[1:])


# ---------------------------------------------------------------------------------------------
# The first segment


class _FirstSegment(NamedTuple):
    """What the first segment must join: the start state and the first waypoint's state."""

    start: numpy.ndarray
    start_velocity: numpy.ndarray
    start_acceleration: numpy.ndarray
    caps: numpy.ndarray
    lower: numpy.ndarray
    upper: numpy.ndarray
    at_rest: numpy.ndarray  # joints starting with zero velocity and acceleration
    minimum: float  # gesture_duration


def _first_segment_grades(first: _FirstSegment, end, end_velocity, end_acceleration, durations):
    """For each candidate duration: grade (0 all met; 1 not monotone from rest; 2 outside the joint
    limits; 3 over the speed cap), speed excess (peak bound / allowed) and distance outside the
    limits."""
    T = numpy.asarray(durations, dtype=float)[:, None]
    polynomials = _segment_polynomials(first.start, first.start_velocity, first.start_acceleration,
                                       end, end_velocity, end_acceleration, T)
    # A start faster than the cap cannot be helped: the segment must only not speed it up.
    allowed_speed = numpy.maximum(first.caps, numpy.abs(first.start_velocity))
    speed_excess = (_speed_bound(polynomials, T) / allowed_speed).max(axis=1)
    low, high = _position_hull(polynomials)
    inside = ((first.start >= first.lower) & (first.start <= first.upper)
              & (end >= first.lower) & (end <= first.upper))
    outside = numpy.maximum(numpy.maximum(first.lower - low, high - first.upper), 0.0)
    limit_excess = numpy.where(inside, outside, 0.0).max(axis=1)
    within_limits = limit_excess <= LIMIT_TOLERANCE
    step = end - first.start
    checked = first.at_rest & (step != 0.0)
    safe_step = numpy.where(checked, step, 1.0)
    monotone = _monotone(0.0, end_velocity * T / safe_step, 0.0, end_acceleration * T * T / safe_step)
    monotone = (monotone | ~checked).all(axis=1)
    fast_enough = speed_excess <= 1.0
    grade = numpy.where(fast_enough & within_limits & monotone, 0,
                        numpy.where(fast_enough & within_limits, 1, numpy.where(fast_enough, 2, 3)))
    return grade, speed_excess, limit_excess


def _first_segment_duration(first: _FirstSegment, end, end_velocity, end_acceleration):
    """The shortest duration >= gesture_duration, on a geometric grid, with the best grade, and that
    grade. When none is inside the limits, the least outside among those fast enough; when none is
    fast enough, the least fast. (Possible only from a moving start: from rest, waiting long enough
    always works.)"""
    distance = numpy.abs(end - first.start)
    longest = max(first.minimum, 8.0 * float(numpy.max(distance / first.caps)) + 4.0 * first.minimum)
    count = int(math.ceil(math.log(longest / first.minimum) / math.log(FIRST_SEGMENT_GROWTH))) + 1
    durations = first.minimum * FIRST_SEGMENT_GROWTH ** numpy.arange(count)
    grade, speed_excess, limit_excess = _first_segment_grades(first, end, end_velocity,
                                                              end_acceleration, durations)
    best = int(grade.min())
    if best == 3:
        index = int(numpy.argmin(speed_excess))
    elif best == 2:
        index = int(numpy.argmin(numpy.where(grade == 2, limit_excess, numpy.inf)))
    else:
        index = int(numpy.argmax(grade == best))
    return float(durations[index]), best


# ---------------------------------------------------------------------------------------------


def _segment_speed_excess(knots, velocities, accelerations, durations, caps):
    """Peak speed bound / cap of every segment (N, J)."""
    polynomials = _segment_polynomials(knots[:-1], velocities[:-1], accelerations[:-1], knots[1:],
                                       velocities[1:], accelerations[1:], durations[:, None])
    return _speed_bound(polynomials, durations[:, None]) / caps


def time_trajectory(waypoints, joint_names: Sequence[str], start_positions, start_velocities,
                    gesture_duration: float, start_accelerations=None,
                    position_bounds=None) -> TimedTrajectory:
    """Times, velocities and accelerations for `waypoints` (N, J), starting from the joints' state.

    Points are at least `gesture_duration` apart, the first at `gesture_duration` or later; the motion
    the controller interpolates through them is continuous in velocity and acceleration, ends at rest,
    keeps every joint under its speed cap and does not overshoot between waypoints (see the module
    docstring). The first segment from a start at rest is monotone and capped too. From a moving
    start it may overshoot, and in rare cases (a start accelerating hard, near the cap or a limit,
    while gesture_duration forbids braking sooner) exceed the cap or a limit: the least bad timing
    is then chosen.

    `position_bounds` (lower, upper), each of shape (J,), narrows the joint limits the first segment
    must respect, e.g. to the animation band: where the start and the first waypoint lie inside it,
    a moving start brakes in time instead of overshooting out of it.
    """
    waypoints = numpy.array(waypoints, dtype=float, ndmin=2)
    count, joints = waypoints.shape
    if count < 1 or joints != len(joint_names):
        raise ValueError("waypoints must have shape (N >= 1, {})".format(len(joint_names)))
    if not gesture_duration > 0.0:
        raise ValueError("gesture_duration must be > 0")
    start = numpy.asarray(start_positions, dtype=float).reshape(joints)
    start_velocity = numpy.asarray(start_velocities, dtype=float).reshape(joints)
    start_acceleration = (numpy.zeros(joints) if start_accelerations is None
                          else numpy.asarray(start_accelerations, dtype=float).reshape(joints))
    caps = speed_caps(joint_names)
    lower = numpy.array([JOINTS[name].lower for name in joint_names])
    upper = numpy.array([JOINTS[name].upper for name in joint_names])
    if position_bounds is not None:
        lower = numpy.maximum(lower, numpy.asarray(position_bounds[0], dtype=float).reshape(joints))
        upper = numpy.minimum(upper, numpy.asarray(position_bounds[1], dtype=float).reshape(joints))
    at_rest = (start_velocity == 0.0) & (start_acceleration == 0.0)

    first = _FirstSegment(start, start_velocity, start_acceleration, caps, lower, upper, at_rest,
                          float(gesture_duration))
    durations = numpy.full(count, float(gesture_duration))
    # First guess of the first segment: a rest-to-rest quintic peaks at 1.875 times its mean speed.
    first_step = numpy.abs(waypoints[0] - start)
    durations[0] = max(gesture_duration, 1.9 * float(numpy.max(first_step / caps)))
    if count == 1:
        return _time_single_waypoint(first, waypoints, float(durations[0]))
    return _time_by_rounds(first, waypoints, durations)


def _time_by_rounds(first: _FirstSegment, waypoints, durations) -> TimedTrajectory:
    """time_trajectory's rounds, from the first guess of the durations."""
    knots = numpy.vstack([first.start, waypoints])
    converged, first_grade, velocities, accelerations = _stretch_rounds(first, knots, durations)
    if not converged:
        velocities, accelerations = _scale_uniformly(first, knots, durations)
    if not converged or first_grade != 0:
        velocities, accelerations, durations = _time_first_segment_last(first, knots, velocities, accelerations,
                                                                        durations)
    return TimedTrajectory(numpy.cumsum(durations), waypoints.copy(), velocities[1:].copy(),
                           accelerations[1:].copy())


def _derivatives(first: _FirstSegment, knots, durations):
    """The knots' velocities and accelerations for `durations` (they depend on the durations)."""
    return _knot_derivatives(knots, durations, first.start_velocity, first.start_acceleration, first.at_rest)


def _between_waypoints_excess(first: _FirstSegment, knots, durations, velocities, accelerations):
    """Per segment between waypoints, its largest peak speed as a multiple of its joint's cap."""
    excess = _segment_speed_excess(knots, velocities, accelerations, durations, first.caps)[1:]
    return excess.max(axis=1, initial=0.0)


def _stretch_rounds(first: _FirstSegment, knots, durations):
    """The rounds proper, changing `durations` in place: (whether all was met, the first segment's grade,
    the knots' velocities and accelerations of the last round)."""
    # Rounds: re-time the first segment if it fails, stretch the segments between waypoints that are
    # too fast, recompute the knots' derivatives (they depend on the durations), until all is met.
    # From a moving start the first segment may be unable to meet everything: then stop as soon as
    # the rest is met.
    give_up_first = False
    for _ in range(MAX_STRETCH_ROUNDS):
        velocities, accelerations = _derivatives(first, knots, durations)
        first_grade = int(_first_segment_grades(first, knots[1], velocities[1], accelerations[1],
                                                durations[:1])[0][0])
        excess = _between_waypoints_excess(first, knots, durations, velocities, accelerations)
        too_fast = excess > 1.0
        if not too_fast.any() and (first_grade == 0 or give_up_first):
            return True, first_grade, velocities, accelerations
        if first_grade != 0:
            give_up_first = _lengthen_first_segment(first, knots, velocities, accelerations, durations)
        durations[1:][too_fast] *= excess[too_fast] * STRETCH_MARGIN
    return False, first_grade, velocities, accelerations


def _lengthen_first_segment(first: _FirstSegment, knots, velocities, accelerations, durations) -> bool:
    """Lengthen durations[0] to the first segment's search result, in place; whether the rounds should stop
    trying to meet everything on it (a moving start whose best timing still fails)."""
    duration, achievable = _first_segment_duration(first, knots[1], velocities[1], accelerations[1])
    # Only lengthen: the first waypoint's derivatives follow the first duration, and
    # going back and forth between two durations would never settle.
    durations[0] = max(durations[0], duration)
    return achievable > 0 and not first.at_rest.all()


def _scale_uniformly(first: _FirstSegment, knots, durations):
    """After rounds that did not converge: scale every duration in place until no segment between
    waypoints is too fast (four tries at most); the knots' velocities and accelerations then."""
    # Uniform scaling divides every peak between waypoints by the same factor.
    for _ in range(4):
        velocities, accelerations = _derivatives(first, knots, durations)
        worst = float(_between_waypoints_excess(first, knots, durations, velocities, accelerations).max(initial=0.0))
        if worst <= 1.0:
            break
        durations *= worst * (1.0 + 1e-9)
    return _derivatives(first, knots, durations)


def _time_first_segment_last(first: _FirstSegment, knots, velocities, accelerations, durations):
    """Time the first segment for the final derivatives of the waypoints, and stop and go at every waypoint
    when something is still unmet: (velocities, accelerations, durations)."""
    # The waypoints' derivatives are final now: time the first segment for them.
    durations[0], first_grade = _first_segment_duration(first, knots[1], velocities[1], accelerations[1])
    too_fast_left = _between_waypoints_excess(first, knots, durations, velocities, accelerations).max(initial=0.0) > 1.0
    if too_fast_left or first_grade != 0:
        velocities, accelerations, durations, _ = _stop_and_go(
            first, knots, velocities, accelerations, durations, first_grade, too_fast_left)
    return velocities, accelerations, durations


def _time_single_waypoint(first: _FirstSegment, waypoints, guess: float) -> TimedTrajectory:
    """What the rounds of time_trajectory come to for one waypoint (a return to the centre), in one or two
    gradings instead of two rounds of them: the waypoint is reached at rest whatever the duration, so nothing else
    depends on it. The first guess where it meets everything, else the first segment's search (the rounds keep
    the guess only while it meets everything, and end with the search)."""
    end = waypoints[0]
    zeros = numpy.zeros_like(end)
    duration = guess
    if int(_first_segment_grades(first, end, zeros, zeros, [guess])[0][0]) != 0:
        duration, _ = _first_segment_duration(first, end, zeros, zeros)
    zero_row = numpy.zeros((1, end.size))
    return TimedTrajectory(numpy.array([duration]), waypoints.copy(), zero_row, zero_row.copy())


def _stop_and_go(first, knots, velocities, accelerations, durations, first_grade, must):
    """Last resort, not expected in practice: rest at every waypoint. Each segment between waypoints
    is then a rest-to-rest quintic, monotone, whose peak speed is exactly 1.875 times its mean, and
    the first segment ends at rest. Used when it is needed for the cap (`must`) or when it times the
    first segment better."""
    stopped_velocities = velocities.copy()
    stopped_accelerations = accelerations.copy()
    stopped_velocities[1:] = 0.0
    stopped_accelerations[1:] = 0.0
    steps = numpy.abs(numpy.diff(knots, axis=0))[1:]
    needed = (1.875 * (1.0 + 1e-9) * steps / first.caps).max(axis=1, initial=0.0)
    stopped_durations = durations.copy()
    stopped_durations[1:] = numpy.maximum(durations[1:], needed)
    stopped_durations[0], stopped_grade = _first_segment_duration(first, knots[1], stopped_velocities[1],
                                                                  stopped_accelerations[1])
    if must or stopped_grade < first_grade:
        return stopped_velocities, stopped_accelerations, stopped_durations, stopped_grade
    return velocities, accelerations, durations, first_grade


def to_points(timed: TimedTrajectory) -> List[TrajectoryPoint]:
    """The goal's points (plain floats, ready for trajectory_msgs/JointTrajectoryPoint)."""
    return points_from_arrays(timed.times, timed.positions, timed.velocities, timed.accelerations)
