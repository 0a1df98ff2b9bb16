"""What joint_trajectory_controller (ROS 1, ros_controllers) executes for one FollowJointTrajectory goal.

The controller interpolates every joint separately, segment by segment. A segment joins two states
(p0, v0, a0) at time t0 and (p1, v1, a1) at t1 = t0 + T; with tau = t - t0 it is the polynomial
    linear   p0 + (p1 - p0) / T * tau                       (a point without velocities)
    cubic    the Hermite cubic through p0, v0, p1, v1        (velocities, no accelerations)
    quintic  the Hermite quintic through p0, v0, a0, p1, v1, a1  (velocities and accelerations)
and a segment uses the lowest kind both of its ends carry. The first segment starts from the state the
controller is in when the goal starts (always complete: position, velocity, acceleration), so its kind
is that of the first point. Outside a segment the controller holds its end position with zero velocity
and acceleration. The coefficients below are those of ros_controllers' QuinticSplineSegment, including
its rules for a zero duration, so that a simulated robot moves exactly as the real controller would.

Pure Python and numpy: no ROS import.

Typical use (a simulated controller receiving a goal at time `now`):
    spline = JointTrajectorySpline(current_positions, current_velocities, current_accelerations,
                                   [TrajectoryPoint(p.time_from_start.to_sec(), p.positions,
                                                    p.velocities, p.accelerations) for p in points],
                                   start_time=now)
    positions, velocities, accelerations = spline.sample(t)
"""
import bisect
from typing import List, NamedTuple, Optional, Sequence, Tuple

import numpy

LINEAR = "linear"
CUBIC = "cubic"
QUINTIC = "quintic"
_KINDS = (LINEAR, CUBIC, QUINTIC)  # index = how many derivatives both ends carry


class TrajectoryPoint(NamedTuple):
    """One point of a goal, as in trajectory_msgs/JointTrajectoryPoint (joints in the goal's order)."""

    time: float  # time_from_start, s
    positions: Sequence[float]
    velocities: Optional[Sequence[float]] = None  # None or empty: not carried
    accelerations: Optional[Sequence[float]] = None  # None or empty: not carried


class TrajectoryError(ValueError):
    """A goal the controller would reject (its message says why)."""


def linear_coefficients(p0, p1, duration) -> numpy.ndarray:
    """Coefficients c[..., 0..5] of p(tau) = sum c_k tau^k for a linear segment (broadcasts)."""
    p0, p1, duration = numpy.broadcast_arrays(*(numpy.asarray(x, dtype=float) for x in (p0, p1, duration)))
    coefficients = numpy.zeros(p0.shape + (6,))
    coefficients[..., 0] = p0
    safe = numpy.where(duration == 0.0, 1.0, duration)
    coefficients[..., 1] = numpy.where(duration == 0.0, 0.0, (p1 - p0) / safe)
    return coefficients


def cubic_coefficients(p0, v0, p1, v1, duration) -> numpy.ndarray:
    """Coefficients of the Hermite cubic through (p0, v0) and (p1, v1) over `duration` (broadcasts)."""
    p0, v0, p1, v1, duration = numpy.broadcast_arrays(
        *(numpy.asarray(x, dtype=float) for x in (p0, v0, p1, v1, duration))
    )
    zero = duration == 0.0
    T = numpy.where(zero, 1.0, duration)
    coefficients = numpy.zeros(p0.shape + (6,))
    coefficients[..., 0] = p0
    coefficients[..., 1] = v0
    coefficients[..., 2] = numpy.where(zero, 0.0, (-3.0 * p0 + 3.0 * p1 - 2.0 * v0 * T - v1 * T) / T ** 2)
    coefficients[..., 3] = numpy.where(zero, 0.0, (2.0 * p0 - 2.0 * p1 + v0 * T + v1 * T) / T ** 3)
    return coefficients


def quintic_coefficients(p0, v0, a0, p1, v1, a1, duration) -> numpy.ndarray:
    """Coefficients of the Hermite quintic through (p0, v0, a0) and (p1, v1, a1) (broadcasts)."""
    p0, v0, a0, p1, v1, a1, duration = numpy.broadcast_arrays(
        *(numpy.asarray(x, dtype=float) for x in (p0, v0, a0, p1, v1, a1, duration))
    )
    zero = duration == 0.0
    T = numpy.where(zero, 1.0, duration)
    T2 = T * T
    coefficients = numpy.zeros(p0.shape + (6,))
    coefficients[..., 0] = p0
    coefficients[..., 1] = v0
    coefficients[..., 2] = 0.5 * a0
    coefficients[..., 3] = numpy.where(
        zero, 0.0,
        (-20.0 * p0 + 20.0 * p1 - 3.0 * a0 * T2 + a1 * T2 - 12.0 * v0 * T - 8.0 * v1 * T) / (2.0 * T ** 3),
    )
    coefficients[..., 4] = numpy.where(
        zero, 0.0,
        (30.0 * p0 - 30.0 * p1 + 3.0 * a0 * T2 - 2.0 * a1 * T2 + 16.0 * v0 * T + 14.0 * v1 * T)
        / (2.0 * T ** 4),
    )
    coefficients[..., 5] = numpy.where(
        zero, 0.0,
        (-12.0 * p0 + 12.0 * p1 - a0 * T2 + a1 * T2 - 6.0 * v0 * T - 6.0 * v1 * T) / (2.0 * T ** 5),
    )
    return coefficients


def evaluate_polynomial(coefficients, tau) -> Tuple[numpy.ndarray, numpy.ndarray, numpy.ndarray]:
    """Position, velocity and acceleration of sum c_k tau^k (Horner; c[..., k], tau broadcasts)."""
    c = numpy.asarray(coefficients, dtype=float)
    tau = numpy.asarray(tau, dtype=float)
    position = c[..., 5]
    velocity = 5.0 * c[..., 5]
    acceleration = 20.0 * c[..., 5]
    for k in (4, 3, 2, 1, 0):
        position = position * tau + c[..., k]
        if k >= 1:
            velocity = velocity * tau + k * c[..., k]
        if k >= 2:
            acceleration = acceleration * tau + k * (k - 1) * c[..., k]
    return position, velocity, acceleration


def _optional_vector(values, size: int, what: str) -> Optional[numpy.ndarray]:
    if values is None or len(values) == 0:
        return None
    vector = numpy.asarray(values, dtype=float).reshape(-1)
    if vector.size != size:
        raise TrajectoryError("{} has {} values, expected {}".format(what, vector.size, size))
    return vector


def _point_states(points: Sequence[TrajectoryPoint], joints: int) -> list:
    """(time from start, positions, velocities or None, accelerations or None) of each point, as vectors; raises
    TrajectoryError for the first point the controller would reject."""
    times = [float(point.time) for point in points]
    fields = [[point.positions for point in points], [point.velocities for point in points],
              [point.accelerations for point in points]]
    if all(later > earlier for earlier, later in zip(times, times[1:])):
        rows = [_uniform_rows(values, joints) for values in fields]
        if rows[0] is not None and all(row is not None or not any(map(_carried, values))
                                       for row, values in zip(rows[1:], fields[1:])):
            # Every point alike (as a planner sends them): each field converted at once, not point by point.
            return list(zip(times, rows[0], *(row if row is not None else [None] * len(times) for row in rows[1:])))
    return [_checked_point_state(index, point, joints, times[index - 1] if index else None)
            for index, point in enumerate(points)]


def _carried(values) -> bool:
    return values is not None and len(values) > 0


def _uniform_rows(values, joints: int) -> Optional[list]:
    """The float rows of `values` (one sequence a point) when every point has `joints` of them, else None."""
    if not values or joints == 0 or not all(row is not None and len(row) == joints for row in values):
        return None
    return list(numpy.array(values, dtype=float).reshape(len(values), joints))


def _checked_point_state(index: int, point: TrajectoryPoint, joints: int, previous_time: Optional[float]) -> tuple:
    time = float(point.time)
    if previous_time is not None and not time > previous_time:
        raise TrajectoryError("point {}: time_from_start {} is not after the previous point's {}"
                              .format(index, time, previous_time))
    positions = _optional_vector(point.positions, joints, "point {} positions".format(index))
    if positions is None:
        raise TrajectoryError("point {} has no positions".format(index))
    velocities = _optional_vector(point.velocities, joints, "point {} velocities".format(index))
    accelerations = _optional_vector(point.accelerations, joints, "point {} accelerations".format(index))
    return time, positions, velocities, accelerations


class JointTrajectorySpline:
    """The motion joint_trajectory_controller commands for one goal, for every joint of the goal.

    `points[i].time` is the time from the goal's start; `start_time` is when the goal starts (the
    controller's clock). The first segment runs from the start state at `start_time` to the first point
    after it. Like the controller: times must be strictly increasing; points at or before the start are
    dropped (all of them dropped: the goal is rejected); no points means "hold the start position".
    A start velocity or acceleration of None is zero (the controller's state always has both).
    Raises TrajectoryError for what the controller would reject.
    """

    def __init__(self, start_positions, start_velocities, start_accelerations,
                 points: Sequence[TrajectoryPoint], start_time: float = 0.0):
        p0 = numpy.asarray(start_positions, dtype=float).reshape(-1)
        joints = p0.size
        v0 = _optional_vector(start_velocities, joints, "start velocities")
        a0 = _optional_vector(start_accelerations, joints, "start accelerations")
        self.start_time = float(start_time)
        self.start_positions = p0
        self.joint_count = joints

        # (absolute time, positions, velocities or None, accelerations or None) of each point after the start
        states = [(self.start_time + state[0],) + state[1:] for state in _point_states(points, joints)
                  if state[0] > 0.0]
        if points and not states:
            raise TrajectoryError("every point occurs at or before the start of the goal")

        start_state = (self.start_time, p0,
                       numpy.zeros(joints) if v0 is None else v0,
                       numpy.zeros(joints) if a0 is None else a0)
        # Segment i runs from self._states[i] to self._states[i + 1]. Its polynomial is computed
        # when first sampled (a goal is often sampled at one instant only), or with every other
        # quintic by compute_segments.
        self._states = [start_state] + states
        self._segment_coefficients: List[Optional[numpy.ndarray]] = [None] * len(states)
        self._segments_computed = False  # every quintic segment's polynomial is known
        self._segment_start_list = [state[0] for state in self._states[:-1]]
        self.segment_start_times = numpy.array(self._segment_start_list, dtype=float)
        self.segment_durations = numpy.array(
            [end[0] - begin[0] for begin, end in zip(self._states, self._states[1:])], dtype=float)
        self.segment_kinds: Tuple[str, ...] = tuple(
            _KINDS[min(_level(begin), _level(end))] for begin, end in zip(self._states, self._states[1:]))
        self.final_positions = states[-1][1].copy() if states else p0.copy()
        self._end_time = states[-1][0] if states else self.start_time

    def segment_coefficients(self, segment: int) -> numpy.ndarray:
        """Polynomial of one segment, shape (joints, 6): position = sum_k c_k (t - segment start)^k."""
        cached = self._segment_coefficients[segment]
        if cached is None:
            begin, end = self._states[segment], self._states[segment + 1]
            level = min(_level(begin), _level(end))
            duration = end[0] - begin[0]
            if level == 0:
                cached = linear_coefficients(begin[1], end[1], duration)
            elif level == 1:
                cached = cubic_coefficients(begin[1], begin[2], end[1], end[2], duration)
            else:
                cached = quintic_coefficients(begin[1], begin[2], begin[3], end[1], end[2], end[3],
                                              duration)
            self._segment_coefficients[segment] = cached
        return cached

    def compute_segments(self) -> None:
        """Computes the polynomial of every quintic segment not computed yet in one vectorised call (a hundred
        calls of one segment each cost ~25 times as much), so that a later sample only evaluates one. Called
        again, it returns at once."""
        if self._segments_computed:
            return
        self._segments_computed = True
        missing = [index for index, kind in enumerate(self.segment_kinds)
                   if kind == QUINTIC and self._segment_coefficients[index] is None]
        if not missing:
            return
        begins = [self._states[index] for index in missing]
        ends = [self._states[index + 1] for index in missing]
        computed = quintic_coefficients(_stacked(begins, 1), _stacked(begins, 2), _stacked(begins, 3),
                                        _stacked(ends, 1), _stacked(ends, 2), _stacked(ends, 3),
                                        self.segment_durations[missing][:, None])
        for index, coefficients in zip(missing, computed):
            self._segment_coefficients[index] = coefficients

    @property
    def coefficients(self) -> numpy.ndarray:
        """coefficients[segment, joint, k] of every segment."""
        if not self._segment_coefficients:
            return numpy.zeros((0, self.joint_count, 6))
        self.compute_segments()
        return numpy.array([self.segment_coefficients(i) for i in range(len(self._segment_coefficients))])

    @property
    def end_time(self) -> float:
        """Absolute time of the last point (the start time when there is none)."""
        return self._end_time

    def sample(self, t: float) -> Tuple[numpy.ndarray, numpy.ndarray, numpy.ndarray]:
        """Positions, velocities, accelerations (each shape (joints,)) at absolute time t.

        Before the start: the start position, at rest (what the controller's first segment reports for
        a time before it). After the end: the last positions, at rest. The same as `sample_trajectory` at one
        time, without its array bookkeeping: a stop samples each part's spline once, and must be quick.
        """
        t = float(t)
        if not self._segment_start_list or t < self._segment_start_list[0]:
            return self.start_positions.copy(), numpy.zeros(self.joint_count), numpy.zeros(self.joint_count)
        if t > self.end_time:
            return self.final_positions.copy(), numpy.zeros(self.joint_count), numpy.zeros(self.joint_count)
        segment = bisect.bisect_right(self._segment_start_list, t) - 1
        return evaluate_polynomial(self.segment_coefficients(segment), t - self._segment_start_list[segment])


def _stacked(states, k: int) -> numpy.ndarray:
    """Item k (1 positions, 2 velocities, 3 accelerations) of each state, one row per state."""
    return numpy.array([state[k] for state in states])


def _level(state) -> int:
    """How many derivatives a state carries: 0 positions, 1 velocities too, 2 accelerations too."""
    if state[2] is None:
        return 0
    return 1 if state[3] is None else 2


def sample_trajectory(spline: JointTrajectorySpline, times) -> Tuple[numpy.ndarray, numpy.ndarray,
                                                                     numpy.ndarray]:
    """Vectorised JointTrajectorySpline.sample: arrays of shape (len(times), joints)."""
    times = numpy.asarray(times, dtype=float).reshape(-1)
    count, joints = times.size, spline.joint_count
    positions = numpy.empty((count, joints))
    velocities = numpy.zeros((count, joints))
    accelerations = numpy.zeros((count, joints))
    if spline.segment_start_times.size == 0:
        positions[:] = spline.start_positions
        return positions, velocities, accelerations
    segment = numpy.searchsorted(spline.segment_start_times, times, side="right") - 1
    before = segment < 0
    after = times > spline.end_time
    inside = ~before & ~after
    positions[before] = spline.start_positions
    positions[after] = spline.final_positions
    if inside.any():
        index = segment[inside]
        tau = (times[inside] - spline.segment_start_times[index])[:, None]
        used, which = numpy.unique(index, return_inverse=True)
        coefficients = numpy.array([spline.segment_coefficients(int(i)) for i in used])[which]
        p, v, a = evaluate_polynomial(coefficients, tau)
        positions[inside], velocities[inside], accelerations[inside] = p, v, a
    return positions, velocities, accelerations


def points_from_arrays(times, positions, velocities=None, accelerations=None) -> List[TrajectoryPoint]:
    """TrajectoryPoints (tuples of floats) from arrays of shape (N,) and (N, joints)."""
    # tolist() makes plain floats in one C loop: a goal of 100 points is built in a fraction of a millisecond.
    times = numpy.asarray(times, dtype=float).tolist()
    if not times:
        return []

    def rows(values):
        if values is None:
            return [None] * len(times)
        return [tuple(row) for row in numpy.asarray(values, dtype=float).reshape(len(times), -1).tolist()]
    return [TrajectoryPoint(*point) for point in zip(times, rows(positions), rows(velocities), rows(accelerations))]
