"""The breathing motion style (README: "Motion styles"): a slow breathing rhythm with coherent variation.

Every moving joint j follows, at absolute time t, ``q_j(t) = m_j + h_j * k_j * s_j(t)``, where m_j and h_j are
the middle and half-width of its band (`waypoints.joint_bounds`: selectedRange and the *MaximumRange keys keep
their meaning), k_j <= breathingAmplitude its amplitude, and s_j(t), always within [-1, 1], the weighted sum of

- the breath: ``sin(2 pi f t - lag_j)`` with f = breathsPerMinute / 60; shoulders and hip lead, elbows, wrists
  and hands follow with a lag;
- coherent variation: three octaves of incommensurate sines between about 0.03 and 0.3 Hz with random phases,
  so the motion never repeats exactly;
- posture shifts (hip and hands only): at random intervals of 10-30 s a slow (4 s) C2 smooth step to a new
  random level: a weight shift, the hands opening or closing.

The same joint on both sides shares its phases and shifts: the two sides move together (roll and yaw joints
mirrored, as their limits are). Held joints stay exactly at their centre. Each joint's amplitude is lowered
where needed so that its speed stays under the cap (`trajectory_timing.speed_caps`) with a margin.

A goal samples q, q' and q'' exactly every POINT_SPACING seconds for GOAL_BREATHS breaths; its first point is
far enough from the part's current state (which may be anywhere after another node's gesture) for the
controller's quintic splice to stay under the cap and to accelerate no harder than the style itself ever does
(`BreathingMotion.peak_acceleration`) where that still brings every joint into its band within EASE_IN: the first
goal after an enable, a yield or a style switch eases in from the measured pose instead of twitching or dawdling.

Every goal ends at rest (README: "Controllers: what each goal carries"): after its last sample, one more segment
brings each joint to a stop (`ending`): velocity and acceleration 0 at its last point, as joint_trajectory_controller
on ROS 2 Jazzy and later requires by default, so that a goal the node can no longer replace (the node killed, the
connection lost) ends with the robot at rest instead of a jump in velocity. The segment is the controller's quintic
from the last sample to a rest point in the band; it lasts long enough to accelerate no more than the style does on
each joint and to stay under the speed cap. The node replaces each goal CONTINUATION_LEAD seconds before that ending
begins (`BreathingPlanner.replacement_time`), so while it runs the ending is never played: the motion is C2
continuous and never stops. Pure Python and numpy.
"""
import math
from typing import Dict, List, NamedTuple, Tuple

import numpy

from cssr_system.motion.planners import Planner
from cssr_system.motion.trajectory_timing import TimedTrajectory, speed_caps
from cssr_system.motion.waypoints import PartMotion
from cssr_system.pepper.joint_table import MIRRORED_JOINTS, short_name
from cssr_system.pepper.trajectory_interpolation import evaluate_polynomial, quintic_coefficients

POINT_SPACING = 0.2  # s between the points of a goal
GOAL_BREATHS = 3  # breaths per goal
CONTINUATION_LEAD = 1.5  # s before a goal's end when the next one replaces it
SPEED_MARGIN = 0.8  # fraction of the speed cap the style may use
BREATH_WEIGHT, VARIATION_WEIGHT, SHIFT_WEIGHT = 0.6, 0.3, 0.1  # shares of s_j for joints with posture shifts
VARIATION_FREQUENCIES = (0.031, 0.031 * 3.1416, 0.031 * 9.8696)  # Hz: octaves apart, incommensurate
VARIATION_SHARES = (0.57, 0.29, 0.14)
SHIFT_INTERVAL = (10.0, 30.0)  # s between posture shifts
SHIFT_DURATION = 4.0  # s a shift takes
# Phase lag (rad) and amplitude factor of each joint (short name): shoulders and hip lead, the rest follows.
LAG = {"ShoulderPitch": 0.0, "ShoulderRoll": 0.0, "HipPitch": 0.0, "HipRoll": 0.0, "KneePitch": 0.3,
       "ElbowRoll": 0.6, "ElbowYaw": 0.6, "WristYaw": 0.9, "Hand": 1.1}
AMPLITUDE = {"ShoulderPitch": 1.0, "ShoulderRoll": 0.8, "HipPitch": 1.0, "HipRoll": 0.6, "KneePitch": 1.0,
             "ElbowRoll": 0.9, "ElbowYaw": 0.7, "WristYaw": 0.6, "Hand": 0.8}
SHIFTING = ("HipPitch", "HipRoll", "Hand")  # joints with posture shifts
SMOOTHSTEP_PEAK_SLOPE = 1.875  # the peak of d/dx of 6x^5 - 15x^4 + 10x^3
SMOOTHSTEP_PEAK_CURVE = 10.0 / math.sqrt(3.0)  # the peak of |d2/dx2| of the same
# s after the start of a first goal by which every joint is in its band (README: "Motion styles"): the blend onto the
# function is lengthened to accelerate no more than the style only while it still brings every joint in by then.
EASE_IN = 2.5
LONGEST_BLEND = 8.0  # s: the first point is never later than this (a part whose style barely accelerates)
BLEND_SAMPLES = 33  # times at which a blend's acceleration and positions are evaluated
BAND_TOLERANCE = 1e-9  # rad: a held joint's band is its centre, which the blend reaches up to rounding
LONGEST_ENDING = 12.0  # s: the longest stop at a goal's end that is tried
ENDING_SAMPLES = 41  # times at which an ending's speed, acceleration and position are evaluated
ENDING_MARGIN = 0.98  # of the style's acceleration and the speed cap: room for what falls between the samples


def _smoothstep(x: float) -> Tuple[float, float, float]:
    """6x^5 - 15x^4 + 10x^3 on [0, 1] and its first two derivatives (C2 at both ends)."""
    if x <= 0.0:
        return 0.0, 0.0, 0.0
    if x >= 1.0:
        return 1.0, 0.0, 0.0
    return (x ** 3 * (10 - 15 * x + 6 * x * x), 30 * x * x * (1 - x) ** 2, 60 * x * (1 - x) * (1 - 2 * x))


class PostureShifts:
    """Random levels in [-1, 1] reached by smooth steps at random times: a function of time, made as time goes."""

    def __init__(self, rng: numpy.random.Generator) -> None:
        self._rng = rng
        self._starts: List[float] = [float(rng.uniform(*SHIFT_INTERVAL))]
        self._levels: List[float] = [0.0, float(rng.uniform(-1.0, 1.0))]  # before and after each shift

    def sample(self, t: float) -> Tuple[float, float, float]:
        while self._starts[-1] <= t:
            self._starts.append(self._starts[-1] + SHIFT_DURATION + float(self._rng.uniform(*SHIFT_INTERVAL)))
            self._levels.append(float(self._rng.uniform(-1.0, 1.0)))
        index = sum(1 for start in self._starts if start + SHIFT_DURATION <= t)  # shifts already complete
        start = self._starts[index]
        before, after = self._levels[index], self._levels[index + 1]
        value, slope, curve = _smoothstep((t - start) / SHIFT_DURATION)
        span = after - before
        return before + span * value, span * slope / SHIFT_DURATION, span * curve / SHIFT_DURATION ** 2


class BreathingMotion:
    """q, q', q'' of every joint of one part at absolute times: the breathing style's function of time."""

    def __init__(self, motion: PartMotion, breaths_per_minute: float, amplitude: float,
                 shared: Dict[str, object], rng: numpy.random.Generator) -> None:
        self.motion = motion
        self.frequency = breaths_per_minute / 60.0
        self._terms = []
        peaks = []
        caps = speed_caps(motion.joints)
        for index, (bounds, moving) in enumerate(zip(motion.bounds, motion.moving)):
            name = short_name(bounds.name)
            middle, half_width = (bounds.lower + bounds.upper) / 2.0, (bounds.upper - bounds.lower) / 2.0
            if not moving or half_width <= 0.0:
                self._terms.append((bounds.centre, 0.0, 0.0, 1.0, name))
                peaks.append(0.0)
                continue
            # Both sides share phases and shifts: drawn once per joint name, for whichever side comes first.
            if name not in shared:
                shared[name] = (rng.uniform(0.0, 2 * math.pi, len(VARIATION_FREQUENCIES)),
                                PostureShifts(rng) if name in SHIFTING else None)
            sign = -1.0 if name in MIRRORED_JOINTS and bounds.name.startswith("R") else 1.0
            weights = self._weights(name)
            peak_speed = half_width * (weights[0] * 2 * math.pi * self.frequency + weights[1] * sum(
                share * 2 * math.pi * f for share, f in zip(VARIATION_SHARES, VARIATION_FREQUENCIES)) +
                weights[2] * 2.0 * SMOOTHSTEP_PEAK_SLOPE / SHIFT_DURATION)
            scale = min(amplitude * AMPLITUDE.get(name, 1.0), SPEED_MARGIN * caps[index] / peak_speed)
            self._terms.append((middle, half_width * scale, LAG.get(name, 0.0), sign, name))
            peaks.append(half_width * scale * self._curvature_bound(weights))
        self._shared = shared
        # The most each joint accelerates in this style (0 for a held one): a bound of its terms' peaks.
        self.peak_accelerations = numpy.array(peaks)
        # The most any moving joint of the part accelerates in this style.
        self.peak_acceleration = max(peaks, default=0.0)

    def _curvature_bound(self, weights: Tuple[float, float, float]) -> float:
        """An upper bound of |s_j''| for a joint with these weights."""
        omega = 2 * math.pi * self.frequency
        variation = sum(share * (2 * math.pi * f) ** 2 for share, f in zip(VARIATION_SHARES, VARIATION_FREQUENCIES))
        return (weights[0] * omega ** 2 + weights[1] * variation
                + weights[2] * 2.0 * SMOOTHSTEP_PEAK_CURVE / SHIFT_DURATION ** 2)

    @staticmethod
    def _weights(name: str) -> Tuple[float, float, float]:
        if name in SHIFTING:
            return BREATH_WEIGHT, VARIATION_WEIGHT, SHIFT_WEIGHT
        total = BREATH_WEIGHT + VARIATION_WEIGHT
        return BREATH_WEIGHT / total, VARIATION_WEIGHT / total, 0.0

    def sample(self, t: float) -> Tuple[numpy.ndarray, numpy.ndarray, numpy.ndarray]:
        positions, velocities, accelerations = [], [], []
        omega = 2 * math.pi * self.frequency
        for middle, radius, lag, sign, name in self._terms:
            if radius == 0.0:
                positions.append(middle)
                velocities.append(0.0)
                accelerations.append(0.0)
                continue
            breath_weight, variation_weight, shift_weight = self._weights(name)
            phase = omega * t - lag
            s = breath_weight * math.sin(phase)
            ds = breath_weight * omega * math.cos(phase)
            dds = -breath_weight * omega * omega * math.sin(phase)
            phases, shifts = self._shared[name]
            for share, frequency, offset in zip(VARIATION_SHARES, VARIATION_FREQUENCIES, phases):
                w = 2 * math.pi * frequency
                s += variation_weight * share * math.sin(w * t + offset)
                ds += variation_weight * share * w * math.cos(w * t + offset)
                dds -= variation_weight * share * w * w * math.sin(w * t + offset)
            if shifts is not None:
                level, slope, curve = shifts.sample(t)
                s, ds, dds = s + shift_weight * level, ds + shift_weight * slope, dds + shift_weight * curve
            positions.append(middle + sign * radius * s)
            velocities.append(sign * radius * ds)
            accelerations.append(sign * radius * dds)
        return numpy.array(positions), numpy.array(velocities), numpy.array(accelerations)


def _blend_samples(start_state, target_state, duration: float):
    """Times (BLEND_SAMPLES, 1) and the positions and accelerations there (BLEND_SAMPLES, joints) of the controller's
    quintic from one (p, v, a) state to another in `duration`."""
    coefficients = quintic_coefficients(*start_state, *target_state, duration)
    tau = numpy.linspace(0.0, duration, BLEND_SAMPLES)[:, None]
    positions, _, accelerations = evaluate_polynomial(coefficients, tau)
    return tau, positions, accelerations


def blend_acceleration(start_state, target_state, duration: float) -> float:
    """The largest |acceleration| of the controller's quintic from one (p, v, a) state to another in `duration`."""
    return float(numpy.abs(_blend_samples(start_state, target_state, duration)[2]).max())


def blend_entry(start_state, target_state, duration: float, lower, upper) -> float:
    """When the controller's quintic from one (p, v, a) state to another in `duration` has brought every joint into
    [lower, upper] for good (to the sample after its last one outside): the target, a point of the function, is in."""
    tau, positions, _ = _blend_samples(start_state, target_state, duration)
    outside = ((positions < numpy.asarray(lower) - BAND_TOLERANCE)
               | (positions > numpy.asarray(upper) + BAND_TOLERANCE)).any(axis=1)
    late = numpy.flatnonzero(outside)
    return float(tau[min(late[-1] + 1, len(tau) - 1), 0]) if late.size else 0.0


def blend_time(start: numpy.ndarray, start_velocities: numpy.ndarray, target: numpy.ndarray,
               target_velocities: numpy.ndarray, caps: numpy.ndarray) -> float:
    """A duration for the controller's quintic from a state to a point of the function that keeps every joint
    under its cap: the rest-to-rest quintic peaks at 1.875 * distance / T; velocities at the ends add to it."""
    distance = numpy.abs(target - start)
    carried = numpy.maximum(numpy.abs(start_velocities), numpy.abs(target_velocities))
    room = numpy.maximum(SPEED_MARGIN * caps - carried, 0.25 * caps)
    return float(numpy.max(SMOOTHSTEP_PEAK_SLOPE * distance / room))


class Ending(NamedTuple):
    """How a goal comes to rest after its last sample: how long it takes and where each joint stops."""

    duration: float
    positions: numpy.ndarray


def ending(state, lower, upper, caps, accelerations) -> Ending:
    """The shortest stop (a multiple of POINT_SPACING) from `state` (p, v, a per joint) to rest, as the controller's
    quintic plays it, that keeps each joint's |acceleration| within `accelerations`, its speed under `caps` and its
    path inside [lower, upper]. Each joint stops where a cubic fall of its speed to zero takes it,
    p + v D / 2 + a D^2 / 12, or at the edge of its band when that lies beyond. None meeting it all (not expected
    from a state of the style): the one that exceeds least."""
    p0, v0, a0 = (numpy.asarray(values, dtype=float) for values in state)
    durations = POINT_SPACING * numpy.arange(1, int(round(LONGEST_ENDING / POINT_SPACING)) + 1)[:, None]
    rest = numpy.clip(p0 + v0 * durations / 2.0 + a0 * durations ** 2 / 12.0, lower, upper)
    coefficients = quintic_coefficients(p0, v0, a0, rest, 0.0, 0.0, durations)  # (durations, joints, 6)
    tau = durations[:, :, None] * numpy.linspace(0.0, 1.0, ENDING_SAMPLES)  # (durations, 1, samples)
    positions, velocities, accelerations_played = evaluate_polynomial(coefficients[:, :, None, :], tau)
    outside = numpy.maximum(numpy.maximum(lower - positions.min(axis=2), positions.max(axis=2) - upper), 0.0)
    excess = numpy.maximum.reduce([
        numpy.abs(accelerations_played).max(axis=2) / (ENDING_MARGIN * numpy.asarray(accelerations) + 1e-12),
        numpy.abs(velocities).max(axis=2) / (ENDING_MARGIN * numpy.asarray(caps)),
        numpy.where(outside > 1e-9, 2.0 + outside, 0.0),  # out of the band: worse than any excess within it
    ]).max(axis=1)
    met = numpy.flatnonzero(excess <= 1.0)
    index = int(met[0]) if met.size else int(numpy.argmin(excess))
    return Ending(float(durations[index, 0]), rest[index])


class BreathingPlanner(Planner):
    """The breathing style's `Planner` of one part: goals sampled from the function, each ending at rest."""

    def __init__(self, motion: PartMotion, config, shared: Dict[str, object], rng: numpy.random.Generator,
                 epoch: Dict[str, float]) -> None:
        self.function = BreathingMotion(motion, config.breaths_per_minute, config.breathing_amplitude, shared, rng)
        self.caps = speed_caps(motion.joints)
        self._lower = numpy.array([bounds.lower for bounds in motion.bounds])
        self._upper = numpy.array([bounds.upper for bounds in motion.bounds])
        self.goal_length = GOAL_BREATHS / self.function.frequency
        self._epoch = epoch  # shared by the parts of one enable: t = now - epoch keeps the numbers small

    def __call__(self, now: float, positions, velocities, accelerations) -> TimedTrajectory:
        origin = self._epoch.setdefault("t", now)
        start = tuple(numpy.asarray(values, dtype=float) for values in (positions, velocities, accelerations))
        first = self._first_point_time(now - origin, start)
        count = int(round(self.goal_length / POINT_SPACING))
        times = first + POINT_SPACING * numpy.arange(count)
        samples = [self.function.sample(now - origin + time) for time in times]
        stop = ending(samples[-1], self._lower, self._upper, self.caps, self.function.peak_accelerations)
        zeros = numpy.zeros((1, len(self.caps)))
        return TimedTrajectory(numpy.append(times, times[-1] + stop.duration),
                               numpy.vstack([[s[0] for s in samples], stop.positions[None, :]]),
                               numpy.vstack([[s[1] for s in samples], zeros]),
                               numpy.vstack([[s[2] for s in samples], zeros]))

    def replacement_time(self, timed: TimedTrajectory) -> float:
        """CONTINUATION_LEAD before the goal's ending (its last segment) begins."""
        return float(timed.times[-2]) - CONTINUATION_LEAD

    def ease_in(self, t: float, start, first: float) -> float:
        """When a goal from `start` (at style time t) whose first point is `first` s later has every joint in its
        band for good."""
        return blend_entry(start, self.function.sample(t + first), first, self._lower, self._upper)

    def _first_point_time(self, t: float, start) -> float:
        """When the goal reaches the function: soon enough to follow it, late enough for the quintic from `start`
        (at style time t) to stay under the cap, and to accelerate no more than the style does (or than the part
        already does) where that still brings every joint into its band within EASE_IN."""
        first = POINT_SPACING
        for _ in range(3):  # the target moves with the blend time: settle it
            target, target_velocities, _ = self.function.sample(t + first)
            needed = blend_time(start[0], start[1], target, target_velocities, self.caps)
            first = max(POINT_SPACING, math.ceil(needed / POINT_SPACING) * POINT_SPACING)
        # No harder than the style accelerates, or than the part already does (a live change of settings), unless
        # that would keep a joint out of its band past EASE_IN: a small band's style barely accelerates (the leg's
        # breath would take 4 to 5 s to reach from 0.2 rad away).
        limit = max(self.function.peak_acceleration, float(numpy.max(numpy.abs(start[2]), initial=0.0)))
        while blend_acceleration(start, self.function.sample(t + first), first) > limit:
            longer = first + POINT_SPACING
            if longer > LONGEST_BLEND or self.ease_in(t, start, longer) > EASE_IN:
                break
            first = longer
        return first
