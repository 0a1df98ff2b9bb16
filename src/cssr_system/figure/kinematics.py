"""Forward kinematics of Pepper's whole chain, vectorised over instants (doc/figure.md).

The joint origins and axes are those of Pepper's URDF (the table of `CHAIN`, in metres, each in its parent link's
frame at zero angles; x forward, y left, z up). `link_frames` gives every link's frame in the world for N instants
of joint angles and base heading: rotations (N, 3, 3) and origins (N, 3). The base turns about the vertical through
its footprint; a joint missing from the angles given is at its rest centre (`joint_table.PARTS`), the head at zero.
The hands' opening moves no frame. Pure numpy: no ROS import.
"""
from typing import Dict, Mapping, NamedTuple, Optional, Sequence, Tuple

import numpy

from cssr_system.pepper.joint_table import PARTS


class ChainJoint(NamedTuple):
    """One joint of the chain: the child link's frame is the parent's, moved by `origin`, turned by the joint."""

    child: str
    parent: str
    joint: Optional[str]  # None: a fixed joint
    origin: Tuple[float, float, float]
    rpy: Tuple[float, float, float]
    axis: Tuple[float, float, float]


def _arm(side: str) -> Tuple[ChainJoint, ...]:
    """The joints of one arm: `side` "L" or "R"; the right is the left mirrored in the sagittal plane."""
    sign = 1.0 if side == "L" else -1.0
    lower = side.lower()
    return (
        ChainJoint(side + "Shoulder", "torso", side + "ShoulderPitch", (-0.057, sign * 0.14974, 0.22582), (0, 0, 0),
                   (0, 1, 0)),
        ChainJoint(side + "Bicep", side + "Shoulder", side + "ShoulderRoll", (0, 0, 0), (0, 0, 0), (0, 0, 1)),
        ChainJoint(side + "Elbow", side + "Bicep", side + "ElbowYaw", (0.1812, sign * 0.015, 0.00013),
                   (0, -0.157079, 0), (1, 0, 0)),
        ChainJoint(side + "ForeArm", side + "Elbow", side + "ElbowRoll", (0, 0, 0), (0, 0, 0), (0, 0, 1)),
        ChainJoint(lower + "_wrist", side + "ForeArm", side + "WristYaw", (0.15, 0, 0), (0, 0, 0), (1, 0, 0)),
        ChainJoint(lower + "_hand", lower + "_wrist", None, (0.025, 0, 0), (0, 0, 0), (1, 0, 0)),
    )


# Parents before children. base_footprint is the world frame turned by the heading.
CHAIN: Tuple[ChainJoint, ...] = (
    ChainJoint("Tibia", "base_footprint", None, (0, 0, 0.334), (0, 0, 0), (0, 0, 1)),
    ChainJoint("Pelvis", "Tibia", "KneePitch", (0, 0, 0), (0, 0, 0), (0, -1, 0)),
    ChainJoint("Hip", "Pelvis", "HipPitch", (0, 0, 0.268), (0, 0, 0), (0, -1, 0)),
    ChainJoint("torso", "Hip", "HipRoll", (-0.00002, 0, 0.079), (0, 0, 0), (-1, 0, 0)),
    ChainJoint("Neck", "torso", "HeadYaw", (-0.038, 0, 0.3089), (0, 0, 0), (0, 0, 1)),
    ChainJoint("Head", "Neck", "HeadPitch", (0, 0, 0), (0, 0, 0), (0, 1, 0)),
    ChainJoint("Tablet_frame", "torso", None, (0.0839, 0, 0.2015), (0, -0.5236, 0), (1, 0, 0)),
) + _arm("L") + _arm("R")

CHAIN_JOINTS: Tuple[str, ...] = tuple(joint.joint for joint in CHAIN if joint.joint is not None)


class Frames(NamedTuple):
    """Every link's frame in the world at N instants."""

    rotations: Dict[str, numpy.ndarray]  # link -> (N, 3, 3): columns are the link's axes in the world
    origins: Dict[str, numpy.ndarray]  # link -> (N, 3)

    def point(self, link: str, offset: Sequence[float]) -> numpy.ndarray:
        """(N, 3): the point at `offset` in `link`'s frame, in the world."""
        return self.origins[link] + numpy.einsum("nij,j->ni", self.rotations[link], numpy.asarray(offset, float))


def axis_rotations(axis: Sequence[float], angles: numpy.ndarray) -> numpy.ndarray:
    """(N, 3, 3) rotations by `angles` about the unit vector `axis` (Rodrigues)."""
    x, y, z = axis
    cross = numpy.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    angles = numpy.asarray(angles, dtype=float).reshape(-1, 1, 1)
    return numpy.eye(3) + numpy.sin(angles) * cross + (1.0 - numpy.cos(angles)) * cross.dot(cross)


def rpy_rotation(rpy: Sequence[float]) -> numpy.ndarray:
    """The URDF's fixed-axis roll, pitch, yaw: Rz(yaw) Ry(pitch) Rx(roll)."""
    roll, pitch, yaw = rpy
    return (axis_rotations((0, 0, 1), [yaw])[0].dot(axis_rotations((0, 1, 0), [pitch])[0])
            .dot(axis_rotations((1, 0, 0), [roll])[0]))


def rest_angle(joint: str) -> float:
    """Where a joint is when a recording does not say: its part's rest centre; the head's joints at zero."""
    for part in PARTS.values():
        if joint in part.joints:
            return part.centre[part.joints.index(joint)]
    return 0.0


def link_frames(angles: Mapping[str, Sequence[float]], heading: Optional[Sequence[float]] = None,
                count: Optional[int] = None) -> Frames:
    """Every link's frame for N instants: `angles` maps joint names to (N,) angles (rad), `heading` is the base's
    yaw (N,) (rad; None: 0). N comes from the arrays, or `count` when none is given."""
    sizes = [numpy.size(values) for values in angles.values()] + ([numpy.size(heading)] if heading is not None else [])
    size = max(sizes) if sizes else (count or 1)
    yaw = numpy.zeros(size) if heading is None else numpy.broadcast_to(numpy.asarray(heading, float), (size,))
    rotations = {"base_footprint": axis_rotations((0, 0, 1), yaw)}
    origins = {"base_footprint": numpy.zeros((size, 3))}
    for link in CHAIN:
        parent_rotation = rotations[link.parent]
        origins[link.child] = origins[link.parent] + parent_rotation.dot(numpy.asarray(link.origin, float))
        rotation = parent_rotation.dot(rpy_rotation(link.rpy)) if any(link.rpy) else parent_rotation
        if link.joint is not None:
            values = angles.get(link.joint)
            values = numpy.full(size, rest_angle(link.joint)) if values is None else numpy.broadcast_to(
                numpy.asarray(values, float), (size,))
            rotation = numpy.matmul(rotation, axis_rotations(link.axis, values))
        rotations[link.child] = rotation
    return Frames(rotations, origins)
