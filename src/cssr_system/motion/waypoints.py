"""Which joints move, within which bounds, and the random positions they visit.

Bounds follow the band formula of the README ("What moves, and how"), per joint j:
    FR  = max - min                      full range of the joint (URDF limits)
    MRO = FR * maxRange[j]               maximum range of oscillation
    SRO = MRO * selectedRange / 2 * intensity    half-width of the selected range (intensity: a live setting)
    UB  = min(centre + SRO, max),  LB = max(centre - SRO, min)
Each random position of a moving joint is uniform in [LB, UB]; a joint the behaviour does not move has
LB == UB == centre and stays exactly there.

The leg does not move at every point: the trajectory is cut into `legRepeatFactor` chunks of
floor(numPoints / legRepeatFactor) points; each chunk starts with `numPointsLeg` random positions and
is filled with the centre; points left over after the last chunk are the centre too.

Pure Python and numpy: no ROS import, so the node, the simulator and the tests share it.
"""
from typing import Iterable, List, NamedTuple, Optional, Sequence, Tuple

import numpy

from cssr_system.pepper.joint_table import JOINTS, PARTS, centre_of, part_of, short_name

ARM_PARTS: Tuple[str, ...] = ("RArm", "LArm")
HAND_PARTS: Tuple[str, ...] = ("RHand", "LHand")
LEG_PART = "Leg"
# Under the "hands" behaviour the arms only turn the forearm and wrist, which carry the hand.
HANDS_ARM_JOINTS: Tuple[str, ...] = ("ElbowRoll", "WristYaw")


class JointBounds(NamedTuple):
    """The interval a joint's random positions are drawn from (LB, UB of Table 1)."""

    name: str
    centre: float
    lower: float  # LB
    upper: float  # UB; lower == upper == centre for a joint held at its centre


class PartMotion(NamedTuple):
    """One controller's share of a behaviour: all its joints, and which of them move."""

    part: str  # key of PARTS and of the topic files
    joints: Tuple[str, ...]  # every joint of the controller (a goal must name them all)
    bounds: Tuple[JointBounds, ...]  # same order as joints
    moving: Tuple[bool, ...]  # same order; False: held exactly at the centre
    is_leg: bool  # positions follow leg_pattern


def maximum_range(config, joint_name: str) -> float:
    """The configuration's maximum-range fraction that applies to `joint_name`."""
    key = part_of(joint_name)
    index = PARTS[key].joints.index(joint_name)
    if key in ARM_PARTS:
        return float(config.arm_maximum_range[index])
    if key in HAND_PARTS:
        return float(config.hand_maximum_range)
    return float(config.leg_maximum_range[index])


def joint_bounds(config, joint_name: str) -> JointBounds:
    """LB and UB of a moving joint (module docstring formula)."""
    limits = JOINTS[joint_name]
    middle = centre_of(joint_name)
    full_range = limits.upper - limits.lower
    maximum_oscillation = full_range * maximum_range(config, joint_name)
    selected_half_range = maximum_oscillation * config.selected_range / 2.0 * config.intensity
    return JointBounds(
        joint_name,
        middle,
        max(middle - selected_half_range, limits.lower),
        min(middle + selected_half_range, limits.upper),
    )


def held_bounds(joint_name: str) -> JointBounds:
    """Bounds of a joint held at its centre."""
    middle = centre_of(joint_name)
    return JointBounds(joint_name, middle, middle, middle)


def _moving_joints(behaviour, part_key: str) -> Tuple[bool, ...]:
    """Which joints of a part the behaviour set moves (all False: the part is not animated)."""
    joints = PARTS[part_key].joints
    body = "body" in behaviour
    hands = "hands" in behaviour
    if part_key in ARM_PARTS:
        if body:
            return tuple(True for _ in joints)
        return tuple(hands and short_name(name) in HANDS_ARM_JOINTS for name in joints)
    if part_key in HAND_PARTS:
        return tuple(body or hands for _ in joints)
    return tuple(body for _ in joints)  # the leg


def part_switched_on(config, part_key: str) -> bool:
    """The live setting that lets a part move (moveArms, moveHands, moveLeg)."""
    if part_key in ARM_PARTS:
        return config.move_arms
    return config.move_hands if part_key in HAND_PARTS else config.move_leg


def animated_parts(config, available_parts: Iterable[str]) -> Tuple[PartMotion, ...]:
    """The parts the configured behaviour drives and the live settings let move, in PARTS order, each once.

    `available_parts` are the keys of the platform's topic file: a part without a controller there
    (the simulator's hands) is left out. "rotation" alone drives no joint.
    """
    available = {key for key in available_parts if key in PARTS and part_switched_on(config, key)}
    motions = []
    for key, part in PARTS.items():
        if key not in available:
            continue
        moving = _moving_joints(config.behaviour, key)
        if not any(moving):
            continue
        bounds = tuple(
            joint_bounds(config, name) if moves else held_bounds(name)
            for name, moves in zip(part.joints, moving)
        )
        motions.append(PartMotion(key, part.joints, bounds, moving, key == LEG_PART))
    return tuple(motions)


def leg_pattern(num_points: int, leg_repeat_factor: int, num_points_leg: int) -> Tuple[bool, ...]:
    """For each point of a trajectory, True if the leg takes a random position, False for the centre."""
    if not 1 <= leg_repeat_factor <= num_points:
        raise ValueError("need 1 <= leg_repeat_factor <= num_points")
    chunk = num_points // leg_repeat_factor
    if not 0 <= num_points_leg <= chunk:
        raise ValueError("need 0 <= num_points_leg <= chunk size {}".format(chunk))
    pattern = []
    for _ in range(leg_repeat_factor):
        pattern.extend([True] * num_points_leg + [False] * (chunk - num_points_leg))
    pattern.extend([False] * (num_points - len(pattern)))
    return tuple(pattern)


def random_waypoints(motion: PartMotion, config, rng: numpy.random.Generator) -> numpy.ndarray:
    """`config.num_points` random positions of a part, shape (num_points, len(motion.joints)).

    Moving joints are uniform in [LB, UB]; held joints are exactly the centre; the leg is at the centre
    where leg_pattern says so. The generator always draws the full matrix, so a seed fixes the result.
    """
    lower = numpy.array([bound.lower for bound in motion.bounds])
    upper = numpy.array([bound.upper for bound in motion.bounds])
    middle = numpy.array([bound.centre for bound in motion.bounds])
    size = (config.num_points, len(motion.joints))
    # Clip: lower + (upper - lower) * u can round one ulp past upper.
    positions = numpy.clip(rng.uniform(lower, upper, size=size), lower, upper)
    held = ~numpy.array(motion.moving, dtype=bool)
    positions[:, held] = middle[held]
    if motion.is_leg:
        pattern = numpy.array(
            leg_pattern(config.num_points, config.leg_repeat_factor, config.num_points_leg)
        )
        positions[~pattern, :] = middle
    return positions


def make_rng(seed: Optional[int]) -> numpy.random.Generator:
    """A random generator: reproducible with a seed, fresh entropy with None."""
    return numpy.random.default_rng(seed)


def narrow_bands(motions: Sequence[PartMotion], precision: float) -> List[str]:
    """One line per moving joint whose band is narrower than `precision` (the real robot's driver does not move
    a joint for a smaller change unless another joint's change makes it write: README: "Motion styles")."""
    lines = []
    for motion in motions:
        for bounds, moving in zip(motion.bounds, motion.moving):
            width = bounds.upper - bounds.lower
            if moving and width < precision:
                lines.append("%s moves within %.3f rad, less than the robot driver's %.2f rad dead band: on the "
                             "robot it moves only when another joint's motion makes the driver write"
                             % (bounds.name, width, precision))
    return lines
