"""How close Pepper's arms come to its body: in a recording, along a motion style's plan, and anywhere in the bands
of a configuration (doc/figure.md, README: "See Pepper move").

The solids are `body_model`'s. `band_clearance` samples each moving joint of the configuration at its band's ends
and middle (every combination, the leg at its corners too): a hand's closest approach to the body in its band.
`close_hand_warnings` turns that into one line naming the configuration key when it is under `HAND_MARGIN`.
Pure numpy: no ROS import.
"""
import functools
import itertools
from typing import Dict, List, Mapping, NamedTuple, Optional, Sequence, Tuple

import numpy

from cssr_system.figure.body_model import Closest, arm_clearances, closest, closest_per_arm
from cssr_system.figure.kinematics import link_frames
from cssr_system.motion.waypoints import animated_parts
from cssr_system.pepper.joint_table import PARTS

HAND_MARGIN = 0.03  # m: a hand nearer the body than this anywhere in its band is warned about
ARM_KEYS = {"RArm": "armMaximumRange", "LArm": "armMaximumRange", "Leg": "legMaximumRange"}


class BandClearance(NamedTuple):
    closest: Closest  # index: the row of `poses`
    poses: Dict[str, numpy.ndarray]  # joint -> (P,) the sampled angles


# Turning about the forearm's own axis, the wrist moves no capsule: one level is enough.
STILL_SOLIDS = ("LWristYaw", "RWristYaw")


def _levels(name: str, lower: float, upper: float, moving: bool) -> Tuple[float, ...]:
    if moving and upper > lower and name not in STILL_SOLIDS:
        return lower, (lower + upper) / 2, upper
    return ((lower + upper) / 2,)


@functools.lru_cache(maxsize=32)
def _band_clearance(arm: str, bands: Tuple[Tuple[str, float, float, bool], ...]) -> BandClearance:
    """`arm`'s hand against the body over every combination of the bands' sampled angles."""
    names = [name for name, _, _, _ in bands]
    grid = numpy.array(list(itertools.product(*[_levels(*band) for band in bands])))
    poses = {name: grid[:, column] for column, name in enumerate(names)}
    pairs = arm_clearances(link_frames(poses, count=len(grid)), ("hand",), with_other_arm=False, arms=(arm,))
    return BandClearance(closest(pairs), poses)


def band_clearance(config, leg_held: bool = False) -> Optional[BandClearance]:
    """The hands' closest approach to the body at the configuration's bands (its intensity: use 1 for the widest),
    over the sampled poses of each arm with the leg's (`leg_held`: the leg at its rest centre); None when no arm
    moves. The other arm stays at rest: only the body counts here."""
    motions = {motion.part: motion for motion in animated_parts(config, tuple(PARTS))}
    leg = motions.get("Leg") if not leg_held else None
    found = []
    for key, arm in (("LArm", "left"), ("RArm", "right")):
        if key not in motions:
            continue
        bands = tuple((bounds.name, bounds.lower, bounds.upper, moving) for motion in (motions[key], leg)
                      if motion is not None for bounds, moving in zip(motion.bounds, motion.moving))
        found.append(_band_clearance(arm, bands))
    return min(found, key=lambda band: band.closest.distance) if found else None


def close_hand_warnings(config, margin: float = HAND_MARGIN) -> List[str]:
    """One line naming the key whose bands bring a hand within `margin` of the body (at intensity 1), else none: the
    arms' bands of the idle and listening modes (`armMaximumRange`; listening's are narrower), then speaking's
    (`speakingArmRange`, README "Modes")."""
    widest = config._replace(intensity=1.0)
    for arm_key, bands in (("armMaximumRange", widest),
                           ("speakingArmRange", widest._replace(arm_maximum_range=widest.speaking_arm_range))):
        band = band_clearance(bands)
        if band is None or band.closest.distance >= margin:
            continue
        found = band.closest
        key = arm_key if band_clearance(bands, leg_held=True).closest.distance < margin else "legMaximumRange"
        return ["%s (with selectedRange %g) brings the %s within %.1f cm of the %s in its band (margin %.0f cm): "
                "lower it, or selectedRange" % (key, config.selected_range, found.solid,
                                                100 * max(found.distance, 0.0), found.other, 100 * margin)]
    return []


def recorded_clearances(names: Sequence[str], positions: numpy.ndarray,
                        headings: Optional[numpy.ndarray] = None) -> Dict[str, Closest]:
    """Each arm's smallest clearance (and between the arms) over recorded rows of joint angles (NaN: at rest)."""
    angles = {}
    for column, name in enumerate(names):
        values = positions[:, column]
        if numpy.all(numpy.isnan(values)):
            continue
        angles[name] = filled(values)
    return closest_per_arm(arm_clearances(link_frames(angles, headings, count=len(positions))))


def filled(values: numpy.ndarray) -> numpy.ndarray:
    """NaN samples replaced by the last measured one before them (the first measured one at the start)."""
    values = numpy.array(values, dtype=float)
    valid = numpy.flatnonzero(~numpy.isnan(values))
    index = numpy.maximum.accumulate(numpy.where(~numpy.isnan(values), numpy.arange(len(values)), -1))
    index[index < 0] = valid[0]
    return values[index]


def format_closest(found: Closest, times: Optional[Sequence[float]] = None) -> str:
    when = " at %.2f s" % times[found.index] if times is not None else ""
    return "%.1f cm, %s - %s%s" % (100 * found.distance, found.solid, found.other, when)


def per_arm_lines(found: Mapping[str, Closest], times: Optional[Sequence[float]] = None) -> List[str]:
    labels = {"left": "left arm to body", "right": "right arm to body", "both": "arm to arm"}
    return ["%-18s %s" % (labels[arm], format_closest(value, times)) for arm, value in found.items()]


def largest_quiet_selected_range(config, margin: float = HAND_MARGIN, precision: float = 0.01) -> float:
    """The largest selectedRange (with the configuration's other ranges, at intensity 1) that gives no warning of
    `close_hand_warnings`, to `precision`; 0 when even the smallest warns."""
    widest = config._replace(intensity=1.0)
    if not close_hand_warnings(widest._replace(selected_range=1.0), margin):
        return 1.0
    low, high = 0.0, 1.0
    while high - low > precision:
        middle = (low + high) / 2
        if close_hand_warnings(widest._replace(selected_range=middle), margin):
            high = middle
        else:
            low = middle
    return float("%.3f" % low)
