"""Pepper's body as simple solids on the links of `kinematics`, and their smallest distances (doc/figure.md).

A capsule is a segment swept by a sphere; a box is a cuboid in its link's frame. The sizes are fitted to the
robot's published overall size (1.21 m high, 0.48 m wide, 0.425 m deep, a 10.1-inch tablet) around the URDF's
joint origins; the robot's meshes are not used. The arm's solids are capsules (upper arm, forearm, hand), so every
distance is between a segment and a convex core (a segment or a box): along the segment that distance is a convex
function, whose minimum a golden-section search finds for all instants at once. Solids that overlap give a
negative clearance: at most the sum of their radii, not a penetration depth. Pure numpy: no ROS import.
"""
from typing import Dict, List, NamedTuple, Sequence, Tuple

import numpy

from cssr_system.figure.kinematics import Frames

Vector = Tuple[float, float, float]


class Capsule(NamedTuple):
    name: str
    link: str
    start: Vector  # in the link's frame
    end: Vector
    radius: float


class Box(NamedTuple):
    name: str
    link: str
    centre: Vector  # in the link's frame; the box's edges are along the link's axes
    half_size: Vector


def _arm(side: str) -> Tuple[Capsule, ...]:
    sign = 1.0 if side == "L" else -1.0
    word = "left" if side == "L" else "right"
    wrist = side.lower() + "_wrist"
    return (Capsule(word + " upper arm", side + "Bicep", (0, 0, 0), (0.1812, sign * 0.015, 0.00013), 0.045),
            Capsule(word + " forearm", side + "ForeArm", (0, 0, 0), (0.15, 0, 0), 0.036),
            Capsule(word + " hand", wrist, (0.025, 0, 0), (0.085, 0, 0), 0.035))


BODY: Tuple[object, ...] = (
    Box("base", "base_footprint", (0.0, 0.0, 0.15), (0.2, 0.19, 0.15)),
    Capsule("leg", "Pelvis", (0, 0, 0.02), (0, 0, 0.24), 0.075),
    Capsule("hip", "Hip", (0, -0.035, 0.035), (0, 0.035, 0.035), 0.06),
    Box("torso", "torso", (-0.03, 0.0, 0.165), (0.08, 0.105, 0.145)),
    Box("tablet", "Tablet_frame", (-0.012, 0.0, 0.0), (0.012, 0.125, 0.085)),
    Capsule("head", "Head", (0.0, 0, 0.115), (0.0, 0, 0.115), 0.11),
)
LEFT_ARM = _arm("L")
RIGHT_ARM = _arm("R")
ARMS = {"left": LEFT_ARM, "right": RIGHT_ARM}
# An upper arm hangs from the torso at the shoulder joint: the two always touch there, so that pair says nothing.
ADJACENT = {("left upper arm", "torso"), ("right upper arm", "torso")}
GOLDEN = (5 ** 0.5 - 1) / 2
SEARCH_STEPS = 20  # golden-section steps: the parameter to 0.618^20 < 1e-4 (20 um on a 20 cm segment)


def segment_ends(capsule: Capsule, frames: Frames) -> Tuple[numpy.ndarray, numpy.ndarray]:
    """(N, 3) world positions of the capsule's two ends."""
    return frames.point(capsule.link, capsule.start), frames.point(capsule.link, capsule.end)


def box_corners(box: Box, frames: Frames) -> numpy.ndarray:
    """(N, 8, 3) world positions of the box's corners (bit 0: x, bit 1: y, bit 2: z; 0 the lower side)."""
    signs = numpy.array([[1 if corner & bit else -1 for bit in (1, 2, 4)] for corner in range(8)], dtype=float)
    offsets = numpy.asarray(box.centre) + signs * numpy.asarray(box.half_size)
    return frames.origins[box.link][:, None, :] + numpy.einsum("nij,cj->nci", frames.rotations[box.link], offsets)


def _distance_to_segment(points: numpy.ndarray, start: numpy.ndarray, end: numpy.ndarray) -> numpy.ndarray:
    direction = end - start
    length2 = numpy.maximum(numpy.einsum("ni,ni->n", direction, direction), 1e-18)
    along = numpy.clip(numpy.einsum("ni,ni->n", points - start, direction) / length2, 0.0, 1.0)
    return numpy.linalg.norm(points - start - along[:, None] * direction, axis=1)


def _distance_to_box(points: numpy.ndarray, centre: numpy.ndarray, rotation: numpy.ndarray,
                     half_size: numpy.ndarray) -> numpy.ndarray:
    local = numpy.einsum("nji,nj->ni", rotation, points - centre)  # rotation transposed: world -> box
    return numpy.linalg.norm(numpy.maximum(numpy.abs(local) - half_size, 0.0), axis=1)


def _core_distance(solid, frames: Frames):
    """A function (N, 3) points -> (N,) distances to the solid's core, and the solid's radius."""
    if isinstance(solid, Capsule):
        start, end = segment_ends(solid, frames)
        return (lambda points: _distance_to_segment(points, start, end)), solid.radius
    centre = frames.point(solid.link, solid.centre)
    rotation = frames.rotations[solid.link]
    half_size = numpy.asarray(solid.half_size, dtype=float)
    return (lambda points: _distance_to_box(points, centre, rotation, half_size)), 0.0


def clearance(capsule: Capsule, other, frames: Frames) -> numpy.ndarray:
    """(N,) smallest distance between the capsule's surface and the other solid's (m; < 0: they overlap)."""
    start, end = segment_ends(capsule, frames)
    distance_to, other_radius = _core_distance(other, frames)
    size = len(start)
    low, high = numpy.zeros(size), numpy.ones(size)

    def at(parameter):
        return distance_to(start + parameter[:, None] * (end - start))
    for _ in range(SEARCH_STEPS):  # the distance is convex in the parameter: keep the side of the smaller value
        left, right = high - GOLDEN * (high - low), low + GOLDEN * (high - low)
        keep_left = at(left) <= at(right)
        high = numpy.where(keep_left, right, high)
        low = numpy.where(keep_left, low, left)
    middle = (low + high) / 2
    ends = numpy.minimum(at(numpy.zeros(size)), at(numpy.ones(size)))
    return numpy.minimum(at(middle), ends) - capsule.radius - other_radius


class PairClearance(NamedTuple):
    arm: str  # "left" or "right"
    solid: str  # the arm's solid
    other: str  # a body solid, or one of the other arm
    values: numpy.ndarray  # (N,) m


def arm_clearances(frames: Frames, arm_solids: Sequence[str] = ("upper arm", "forearm", "hand"),
                   with_other_arm: bool = True, arms: Sequence[str] = ("left", "right")) -> List[PairClearance]:
    """Every pair of a solid of `arms` (those named in `arm_solids`) with a body solid, and with the other arm's."""
    pairs = []
    for arm in arms:
        solids = ARMS[arm]
        for solid in solids:
            if solid.name.split(" ", 1)[1] not in arm_solids:
                continue
            for other in BODY:
                if (solid.name, other.name) not in ADJACENT:
                    pairs.append(PairClearance(arm, solid.name, other.name, clearance(solid, other, frames)))
    if with_other_arm:
        for solid in LEFT_ARM:
            for other in RIGHT_ARM:
                pairs.append(PairClearance("both", solid.name, other.name, clearance(solid, other, frames)))
    return pairs


class Closest(NamedTuple):
    distance: float  # m
    solid: str
    other: str
    index: int  # the instant


def closest(pairs: Sequence[PairClearance]) -> Closest:
    """The pair and the instant of the smallest clearance."""
    best = min(pairs, key=lambda pair: float(numpy.min(pair.values)))
    index = int(numpy.argmin(best.values))
    return Closest(float(best.values[index]), best.solid, best.other, index)


def closest_per_arm(pairs: Sequence[PairClearance]) -> Dict[str, Closest]:
    """For each arm (and "both": between the arms), its smallest clearance."""
    return {arm: closest([pair for pair in pairs if pair.arm == arm]) for arm in ("left", "right", "both")
            if any(pair.arm == arm for pair in pairs)}
