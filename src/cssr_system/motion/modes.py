"""What each mode of the conversation does to the motion (README: "Modes"; doc/modes.md).

- ``idle``: the configured behaviour and style, unchanged.
- ``listening``: calm and attentive. Each arm and hand joint moves within `listeningRange` of its idle band, about
  its centre, at LISTENING_TEMPO of the idle tempo; the leg keeps breathing (or its random positions), the hip in
  the forward half of its band (a slight lean towards the person); the base does not turn.
- ``speaking``: beats. The arms move within bands of their own (`speakingArmRange`, the band formula of
  `waypoints.joint_bounds`), the hands within their idle bands; both alternate between the two halves of each band at
  `beatsPerMinute` (`BeatPlanner`): a stroke and its return make a beat, the hands opening and closing with it. The
  leg keeps the style; the base does not turn.

Every band lies within the joint's limits, and every goal is timed by `trajectory_timing.time_trajectory` under the
speed cap, ending at rest, so a switch is one more goal that splices onto the motion (README: "Live settings").
Pure Python and numpy.
"""
from typing import Iterable, Tuple

import numpy

from cssr_system.animate_behaviour.configuration import MODES
from cssr_system.motion.planners import Planner
from cssr_system.motion.trajectory_timing import TimedTrajectory, time_trajectory
from cssr_system.motion.waypoints import ARM_PARTS, HAND_PARTS, LEG_PART, JointBounds, PartMotion, joint_bounds
from cssr_system.pepper.joint_table import HIP_PITCH_FORWARD, MIRRORED_JOINTS, short_name

IDLE, LISTENING, SPEAKING = MODES
LISTENING_TEMPO = 0.75  # the listening tempo, as a fraction of the idle one: slower, calmer
BEATS_PER_GOAL = 12  # a speaking part's goal: this many beats, then a rest (a pause in the gesturing)
BEAT_PARTS = ARM_PARTS + HAND_PARTS  # the parts that beat while speaking


def turns_base(mode: str) -> bool:
    """Whether the base may turn in `mode`: only while idle (listening and speaking, the robot faces the person)."""
    return mode == IDLE


def mode_config(config, mode: str):
    """The configuration the planners of `mode` read: listening slows the tempo."""
    if mode == LISTENING:
        return config._replace(breaths_per_minute=config.breaths_per_minute * LISTENING_TEMPO)
    return config


def _scaled(bounds: JointBounds, share: float) -> JointBounds:
    """The band scaled about its centre by `share` (still within the band, so within the limits)."""
    lower = bounds.centre - (bounds.centre - bounds.lower) * share
    upper = bounds.centre + (bounds.upper - bounds.centre) * share
    return bounds._replace(lower=lower, upper=upper)


def _leaning(bounds: JointBounds) -> JointBounds:
    """The forward half of a hip band, its middle the new centre."""
    middle = (bounds.lower + bounds.upper) / 2.0
    lower, upper = (bounds.lower, middle) if HIP_PITCH_FORWARD < 0 else (middle, bounds.upper)
    return JointBounds(bounds.name, (lower + upper) / 2.0, lower, upper)


def _shaped_bounds(motion: PartMotion, config, mode: str) -> Tuple[JointBounds, ...]:
    if mode == LISTENING and motion.part in BEAT_PARTS:
        return tuple(_scaled(bounds, config.listening_range) for bounds in motion.bounds)
    if mode == LISTENING and motion.part == LEG_PART:
        return tuple(_leaning(bounds) if short_name(bounds.name) == "HipPitch" and moving else bounds
                     for bounds, moving in zip(motion.bounds, motion.moving))
    if mode == SPEAKING and motion.part in ARM_PARTS:
        speaking = config._replace(arm_maximum_range=config.speaking_arm_range)
        return tuple(joint_bounds(speaking, bounds.name) if moving else bounds
                     for bounds, moving in zip(motion.bounds, motion.moving))
    return motion.bounds


def shaped_motions(motions: Iterable[PartMotion], config, mode: str) -> Tuple[PartMotion, ...]:
    """The parts' motions (`waypoints.animated_parts`) with the bands of `mode`."""
    return tuple(motion._replace(bounds=_shaped_bounds(motion, config, mode)) for motion in motions)


def beat_waypoints(motion: PartMotion, beats: int, rng: numpy.random.Generator) -> numpy.ndarray:
    """2 x `beats` positions (2 beats, J): a stroke into the upper half of each moving joint's band, its return into
    the lower half, and so on (mirrored on the right where the joint is, so that both sides beat alike); held joints
    at their centre."""
    lower = numpy.array([bounds.lower for bounds in motion.bounds])
    upper = numpy.array([bounds.upper for bounds in motion.bounds])
    middle = (lower + upper) / 2.0
    draws = rng.uniform(0.0, 1.0, size=(2 * beats, len(motion.joints)))
    flip = numpy.array([short_name(name) in MIRRORED_JOINTS and name.startswith("R") for name in motion.joints])
    up = (numpy.arange(2 * beats) % 2 == 0)[:, None] != flip[None, :]
    positions = numpy.where(up, middle + (upper - middle) * draws, lower + (middle - lower) * draws)
    held = ~numpy.array(motion.moving, dtype=bool)
    positions[:, held] = numpy.array([bounds.centre for bounds in motion.bounds])[held]
    return positions


class BeatPlanner(Planner):
    """A speaking part's goals: BEATS_PER_GOAL beats at `beatsPerMinute` (a half beat per point, stretched where
    the speed cap needs it), ending at rest."""

    def __init__(self, motion: PartMotion, config, rng: numpy.random.Generator) -> None:
        self._motion = motion
        self._half_beat = 30.0 / config.beats_per_minute
        self._rng = rng
        self._bounds = ([bounds.lower for bounds in motion.bounds], [bounds.upper for bounds in motion.bounds])

    def __call__(self, now, positions, velocities, accelerations) -> TimedTrajectory:
        return time_trajectory(beat_waypoints(self._motion, BEATS_PER_GOAL, self._rng), self._motion.joints,
                               positions, velocities, self._half_beat, start_accelerations=accelerations,
                               position_bounds=self._bounds)
