"""The oracle: written from the README, deliberately apart from `motion.waypoints`, so that a bug there
is caught. It says which parts move per test and platform (README: "What moves, and how"), and each
joint's bounds from the band formula there (FR = max - min; MRO = FR x maxRange;
SRO = MRO x selectedRange / 2; LB = max(centre - SRO, min), UB = min(centre + SRO, max)), with the
URDF limits and rest centres of `pepper.joint_table` (facts, not logic).
"""
from collections import OrderedDict
from typing import Dict, NamedTuple, Tuple

from cssr_system.animate_behaviour.configuration import Configuration
from cssr_system.harness.settings import TESTS
from cssr_system.pepper.joint_table import JOINTS, PARTS, centre_of, part_of, short_name


ALL_JOINTS = "all"


# The README's behaviour table ("What moves, and how"), written out: per behaviour and platform,
# part -> the joints that move (names without
# the side letter, or ALL_JOINTS). Parts not listed do not move.
_ELBOW_AND_WRIST = ("ElbowRoll", "WristYaw")


EXPECTED_PARTS: Dict[str, Dict[str, Dict[str, object]]] = {
    "body": {"robot": {"RArm": ALL_JOINTS, "LArm": ALL_JOINTS, "RHand": ALL_JOINTS, "LHand": ALL_JOINTS,
                       "Leg": ALL_JOINTS},
             "simulator": {"RArm": ALL_JOINTS, "LArm": ALL_JOINTS, "Leg": ALL_JOINTS}},
    "hands": {"robot": {"RHand": ALL_JOINTS, "LHand": ALL_JOINTS, "RArm": _ELBOW_AND_WRIST,
                        "LArm": _ELBOW_AND_WRIST},
              "simulator": {"RArm": _ELBOW_AND_WRIST, "LArm": _ELBOW_AND_WRIST}},
    "rotation": {"robot": {}, "simulator": {}},
}


BASE_ROTATES = {"body": False, "hands": False, "rotation": True}


# The README's configuration table: the order of the values of armMaximumRange and legMaximumRange.
ARM_RANGE_ORDER = ("ShoulderPitch", "ShoulderRoll", "ElbowRoll", "ElbowYaw", "WristYaw")


LEG_RANGE_ORDER = ("HipPitch", "HipRoll", "KneePitch")


class JointBound(NamedTuple):
    name: str
    part: str
    centre: float
    lower: float  # LB; == centre for a held joint
    upper: float  # UB; == centre for a held joint
    moving: bool


class ExpectedMotion(NamedTuple):
    test: str
    platform: str
    parts: Tuple[str, ...]  # keys of PARTS the test drives, in PARTS order
    bounds: "OrderedDict[str, JointBound]"  # every joint of those parts
    base: bool  # the base turns


def maximum_range_fraction(config: Configuration, joint_name: str) -> float:
    """The configuration's maximum-range fraction of a joint (README: "Configuration file and parameters")."""
    key = part_of(joint_name)
    if key in ("RArm", "LArm"):
        return float(config.arm_maximum_range[ARM_RANGE_ORDER.index(short_name(joint_name))])
    if key in ("RHand", "LHand"):
        return float(config.hand_maximum_range)
    return float(config.leg_maximum_range[LEG_RANGE_ORDER.index(joint_name)])


def table1_bounds(config: Configuration, joint_name: str) -> Tuple[float, float]:
    """(LB, UB) of a moving joint: the README's band formula with the URDF limits."""
    limits = JOINTS[joint_name]
    centre = centre_of(joint_name)
    full_range = limits.upper - limits.lower
    maximum_range_offset = full_range * maximum_range_fraction(config, joint_name)
    selected_range_offset = maximum_range_offset * config.selected_range / 2.0 * config.intensity
    return max(centre - selected_range_offset, limits.lower), min(centre + selected_range_offset, limits.upper)


def expected_motion(test: str, platform: str, config: Configuration) -> ExpectedMotion:
    """What a test must move on a platform, and every bound, from the specification alone."""
    moving: Dict[str, set] = {}
    base = False
    for behaviour in TESTS[test].behaviours:
        base = base or BASE_ROTATES[behaviour]
        for key, joints in EXPECTED_PARTS[behaviour][platform].items():
            names = {short_name(name) for name in PARTS[key].joints} if joints == ALL_JOINTS else set(joints)
            moving.setdefault(key, set()).update(names)  # type: ignore[arg-type]
    bounds: "OrderedDict[str, JointBound]" = OrderedDict()
    parts = tuple(key for key in PARTS if key in moving)
    for key in parts:
        for name in PARTS[key].joints:
            centre = centre_of(name)
            if short_name(name) in moving[key]:
                lower, upper = table1_bounds(config, name)
                bounds[name] = JointBound(name, key, centre, lower, upper, True)
            else:
                bounds[name] = JointBound(name, key, centre, centre, centre, False)
    return ExpectedMotion(test, platform, parts, bounds, base)


def leg_slot_is_random(index: int, num_points: int, leg_repeat_factor: int, num_points_leg: int) -> bool:
    """Whether point `index` (0-based) of a leg trajectory is random (the leg's chunk pattern, README:
    "What moves, and how")."""
    chunk = num_points // leg_repeat_factor
    chunk_number, slot = divmod(index, chunk)
    return chunk_number < leg_repeat_factor and slot < num_points_leg
