"""Planning of the base's slight random rotations (no ROS communication here).

The base turns by small random amounts around the heading it had when animation was enabled
(heading 0 in the planner's frame, counter-clockwise positive as in ROS), never leaving
[-heading_bound, heading_bound]: every target heading is drawn inside that interval, so, unlike
a random walk, the heading cannot drift.  The planner is open loop: after each step its
heading estimate is the step's target, unless the node corrects it with `set_heading` (odometry).

The Wheels topic decides what a step is (`wheels_command_kind`, the one place that decides it):

RELATIVE (the robot's ``/pepper_dcm/cmd_moveto``)
    naoqi_dcm_driver executes each Twist as ALMotion ``moveTo(x, y, theta)``: ``angular.z`` is a
    relative angle (rad), turned at moveTo's own speed (BASE_MOVETO_ANGULAR_VELOCITY), after which
    the driver sleeps BASE_MOVETO_SETTLE_TIME and drops anything sent meanwhile.  A step is one
    non-zero turn (never smaller than MIN_TURN, or than the bound when the bound is smaller), and
    its duration is at least |angle| / BASE_MOVETO_ANGULAR_VELOCITY + BASE_MOVETO_SETTLE_TIME,
    plus a random pause so the motion looks calm.
    LIMITATION: moveTo's speed (1.0 rad/s) cannot be set from this topic and may exceed
    rot_maximum_range * BASE_MAX_ANGULAR_VELOCITY (0.6 rad/s by default).  The only lever is the
    size of each turn, so rot_maximum_range bounds the turn instead: |turn| <= the angle the
    allowed peak speed covers in MAX_TURN_TIME (0.3 rad by default), and never more than the bound.

VELOCITY (the simulator's ``/pepper/cmd_vel``)
    Gazebo's plugin takes ``angular.z`` as a velocity, zeroes it BASE_VELOCITY_COMMAND_TIMEOUT
    after the last message and limits acceleration to BASE_MAX_ANGULAR_ACCELERATION.  A step is a
    raised-cosine velocity bump  v(t) = (A / T) * (1 - cos(2 pi t / T)),  0 <= t <= T, sampled once
    per period (sample_rate >= MIN_SAMPLE_RATE Hz), starting and ending at zero speed with
    continuous velocity; its peak 2A/T is <= rot_maximum_range * BASE_MAX_ANGULAR_VELOCITY and
    its acceleration 2 pi A / T^2 is <= BASE_MAX_ANGULAR_ACCELERATION.  The samples are scaled so
    that sum(samples) * period equals the step's angle (to rounding), and the last sample is an
    explicit 0.0 that stops the base.  Between steps the node may stay silent (the base is still).

Turn sizes are the same for both kinds: uniform over the targets in [-bound, bound] that are at
least MIN_TURN and at most the maximum turn away from the current heading.
"""
import math
from typing import NamedTuple, Optional, Tuple

import numpy

from cssr_system.pepper.joint_table import (KINDS, RELATIVE, VELOCITY, BASE_MAX_ANGULAR_ACCELERATION,
                                            BASE_MAX_ANGULAR_VELOCITY, BASE_MOVETO_ANGULAR_VELOCITY,
                                            BASE_MOVETO_SETTLE_TIME, BASE_VELOCITY_COMMAND_TIMEOUT)


MIN_TURN = 0.02  # rad; smaller turns are invisible (and a zero moveTo is a no-op)
MAX_TURN_TIME = 0.5  # s; the largest turn is what the allowed peak speed covers in this time
MIN_MOTION_TIME = 1.0  # s; a velocity bump never takes less, so even small turns are gentle
MOTION_TIME_STRETCH = (1.0, 1.5)  # random stretch of the shortest allowed bump, for variety
PAUSE_RANGE = (1.0, 4.0)  # s of stillness after each random step: a calm rhythm (6-30 per minute)
MIN_SAMPLE_RATE = 10.0  # Hz (the plugin's time-out is BASE_VELOCITY_COMMAND_TIMEOUT)
DEFAULT_SAMPLE_RATE = 20.0  # Hz
RETURN_TOLERANCE = 1e-3  # rad; return_step does nothing closer to 0 than this
# s beyond the driver's turn and settle time before the next relative command: a command that
# arrives while the driver is still busy is dropped, and its timing is not exact.
RELATIVE_COMMAND_MARGIN = 0.3
# Plan slightly inside the speed and acceleration limits so rounding never crosses them.
_LIMIT_MARGIN = 1.0 - 1e-9


class RotationStep(NamedTuple):
    """One base command (RELATIVE) or one streamed rotation (VELOCITY)."""

    kind: str  # RELATIVE or VELOCITY
    angle: float  # rad, relative turn (VELOCITY: the total planned turn; samples integrate to it)
    velocities: Tuple[float, ...]  # VELOCITY: angular.z samples, one per period, last exactly 0.0
    period: float  # s between samples (VELOCITY); 0.0 for RELATIVE (one message, no samples)
    duration: float  # s the step occupies, including settle and pause, before the next may start
    target_heading: float  # rad, heading after the step in the planner's frame
    busy_time: float  # s the robot is executing the step (turn, settle); the rest is our pause


def raised_cosine_velocities(angle: float, sample_count: int, period: float) -> Tuple[float, ...]:
    """`sample_count` samples of a raised-cosine bump turning by `angle`; the last one is 0.0.

    Sample k (k = 1 .. n-1) is c * (1 - cos(2 pi k / n)); then 0.0.  c is chosen so that
    sum(samples) * period == angle to rounding, which also absorbs the discretisation.
    """
    if sample_count < 2:
        raise ValueError("a velocity bump needs at least 2 samples, got %d" % sample_count)
    phase = 2.0 * math.pi * numpy.arange(1, sample_count) / sample_count
    shape = 1.0 - numpy.cos(phase)
    scale = angle / (period * math.fsum(shape.tolist()))
    return tuple((shape * scale).tolist()) + (0.0,)


def heading_after_interruption(step: RotationStep, samples_sent: int) -> float:
    """Where a VELOCITY step cut short after `samples_sent` samples leaves the heading (planner
    frame): the turn the sent samples made, plus the base's braking from the last speed at its
    acceleration limit once the explicit zero arrives."""
    start = step.target_heading - step.angle
    turned = math.fsum(step.velocities[:samples_sent]) * step.period
    last = step.velocities[samples_sent - 1] if samples_sent else 0.0
    braking = math.copysign(last * last / (2.0 * BASE_MAX_ANGULAR_ACCELERATION), last)
    return start + turned + braking


class BaseRotationPlanner:
    """Random base turns inside [-heading_bound, heading_bound] (see the module docstring).

    State: the heading estimate (rad, relative to the heading at enable) and the random generator.
    """

    def __init__(self, kind: str, rot_maximum_range: float, heading_bound: float,
                 rng: numpy.random.Generator, sample_rate: float = DEFAULT_SAMPLE_RATE,
                 pause_range: Tuple[float, float] = PAUSE_RANGE) -> None:
        if kind not in KINDS:
            raise ValueError("wheels command kind must be one of %s, got %r" % (KINDS, kind))
        if not 0.0 <= rot_maximum_range <= 1.0:
            raise ValueError("rot_maximum_range must be in [0, 1], got %r" % (rot_maximum_range,))
        if not (math.isfinite(heading_bound) and heading_bound >= 0.0):
            raise ValueError("heading_bound must be a finite angle >= 0, got %r" % (heading_bound,))
        if not (math.isfinite(sample_rate) and sample_rate >= MIN_SAMPLE_RATE):
            raise ValueError("sample_rate must be >= %g Hz, got %r" % (MIN_SAMPLE_RATE, sample_rate))
        self.kind = kind
        self.rot_maximum_range = float(rot_maximum_range)
        self.heading_bound = float(heading_bound)
        self.period = 1.0 / float(sample_rate)
        self.pause_range = pause_range
        self._rng = rng
        self._heading = 0.0
        assert self.period < BASE_VELOCITY_COMMAND_TIMEOUT  # guaranteed by MIN_SAMPLE_RATE

    @property
    def heading(self) -> float:
        """The planner's heading estimate (rad) relative to the heading at enable."""
        return self._heading

    @property
    def peak_speed(self) -> float:
        """The largest angular speed this package may command (rad/s)."""
        return self.rot_maximum_range * BASE_MAX_ANGULAR_VELOCITY

    @property
    def min_turn(self) -> float:
        """The smallest random turn (rad): MIN_TURN, or the bound when the bound is smaller."""
        return min(MIN_TURN, self.heading_bound)

    @property
    def max_turn(self) -> float:
        """The largest random turn (rad): what the peak speed covers in MAX_TURN_TIME, <= bound."""
        return max(self.min_turn, min(self.heading_bound, self.peak_speed * MAX_TURN_TIME))

    def set_heading(self, heading: float) -> None:
        """Replace the open-loop estimate by a measured heading (rad, same frame)."""
        if not math.isfinite(heading):
            raise ValueError("heading must be finite, got %r" % (heading,))
        self._heading = float(heading)

    def next_step(self) -> Optional[RotationStep]:
        """A random turn to a new target inside [-bound, bound]; None when rotation is impossible."""
        if self.peak_speed <= 0.0 or self.heading_bound <= 0.0:
            return None
        target = self._draw_target()
        pause = float(self._rng.uniform(*self.pause_range))
        return self._step_to(target, pause, stretch=float(self._rng.uniform(*MOTION_TIME_STRETCH)))

    def return_step(self) -> Optional[RotationStep]:
        """A turn back to heading 0 (no pause); None when already within RETURN_TOLERANCE of it,
        or when rotation is disabled (rot_maximum_range 0)."""
        if self.peak_speed <= 0.0 or abs(self._heading) < RETURN_TOLERANCE:
            return None
        return self._step_to(0.0, pause=0.0, stretch=1.0)

    def _draw_target(self) -> float:
        """Uniform over the targets in [-bound, bound] at a distance in [min_turn, max_turn]."""
        bound, heading = self.heading_bound, self._heading
        low_turn, high_turn = self.min_turn, self.max_turn
        below = (max(-bound, heading - high_turn), min(bound, heading - low_turn))
        above = (max(-bound, heading + low_turn), min(bound, heading + high_turn))
        below_length = max(0.0, below[1] - below[0])
        above_length = max(0.0, above[1] - above[0])
        total = below_length + above_length
        if total <= 0.0:
            # Only possible when a measured heading lies beyond the bound by more than max_turn
            # (or exactly at a single admissible point): head for the nearest admissible heading.
            if below[0] <= below[1]:
                return below[0]
            if above[0] <= above[1]:
                return above[0]
            return min(bound, max(-bound, heading))
        draw = float(self._rng.uniform(0.0, total))
        target = below[0] + draw if draw < below_length else above[0] + (draw - below_length)
        return min(bound, max(-bound, target))  # rounding must never leave the interval

    def return_time(self, heading: float) -> float:
        """How long `return_step` keeps the base busy from `heading` (s; 0: no return)."""
        if self.peak_speed <= 0.0 or abs(heading) < RETURN_TOLERANCE:
            return 0.0
        if self.kind == RELATIVE:
            return self._relative_busy_time(heading)
        return max(2, int(math.ceil(self._shortest_motion_time(abs(heading)) / self.period - 1e-9))) * self.period

    @staticmethod
    def _relative_busy_time(angle: float) -> float:
        return abs(angle) / BASE_MOVETO_ANGULAR_VELOCITY + BASE_MOVETO_SETTLE_TIME + RELATIVE_COMMAND_MARGIN

    def _step_to(self, target: float, pause: float, stretch: float) -> RotationStep:
        angle = target - self._heading
        if self.kind == RELATIVE:
            busy_time = self._relative_busy_time(angle)
            step = RotationStep(RELATIVE, angle, (), 0.0, busy_time + pause, target, busy_time)
        else:
            motion_time = self._shortest_motion_time(abs(angle)) * stretch
            # One sample per period; the last (zero) sample ends the bump at n * period >= time.
            sample_count = max(2, int(math.ceil(motion_time / self.period - 1e-9)))
            velocities = raised_cosine_velocities(angle, sample_count, self.period)
            busy_time = sample_count * self.period
            step = RotationStep(VELOCITY, angle, velocities, self.period, busy_time + pause, target,
                                busy_time)
        self._heading = target
        return step

    def _shortest_motion_time(self, turn: float) -> float:
        """The shortest raised-cosine bump turning by `turn` within the speed and acceleration
        limits: peak 2 turn / T <= peak_speed, acceleration 2 pi turn / T^2 <= the plugin's."""
        by_speed = 2.0 * turn / (self.peak_speed * _LIMIT_MARGIN)
        by_acceleration = math.sqrt(2.0 * math.pi * turn / (BASE_MAX_ANGULAR_ACCELERATION * _LIMIT_MARGIN))
        return max(MIN_MOTION_TIME, by_speed, by_acceleration)
