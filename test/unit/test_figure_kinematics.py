"""Pepper's figure: forward kinematics against the URDF's frames, and the body model's distances."""
import math

import numpy
import pytest

from cssr_system.figure.body_model import BODY, Box, Capsule, arm_clearances, box_corners, clearance, closest_per_arm
from cssr_system.figure.kinematics import CHAIN, CHAIN_JOINTS, link_frames, rest_angle
from cssr_system.pepper.joint_table import JOINTS

ZERO = {name: 0.0 for name in CHAIN_JOINTS}
TORSO_HEIGHT = 0.334 + 0.268 + 0.079  # base_footprint -> Tibia -> Hip -> torso, at zero


def origin(angles, link, heading=None):
    return link_frames({name: [value] for name, value in angles.items()}, heading).origins[link][0]


def test_at_zero_every_frame_is_the_sum_of_the_urdf_origins_above_it():
    # At zero angles only the elbow's fixed pitch turns a frame: the arm beyond it is along that pitch.
    assert origin(ZERO, "torso") == pytest.approx([-0.00002, 0, TORSO_HEIGHT])
    assert origin(ZERO, "Neck") == pytest.approx([-0.03802, 0, TORSO_HEIGHT + 0.3089])
    assert origin(ZERO, "LShoulder") == pytest.approx([-0.05702, 0.14974, TORSO_HEIGHT + 0.22582])
    assert origin(ZERO, "RElbow") == pytest.approx([-0.05702 + 0.1812, -0.14974 - 0.015, TORSO_HEIGHT + 0.22595])
    pitch = 0.157079  # the elbow frame's rpy pitch of -0.157079 lifts its x axis
    hand = origin(ZERO, "LElbow") + 0.175 * numpy.array([math.cos(pitch), 0, math.sin(pitch)])
    assert origin(ZERO, "l_hand") == pytest.approx(hand)
    assert origin(ZERO, "Tablet_frame") == pytest.approx([0.0839 - 0.00002, 0, TORSO_HEIGHT + 0.2015])


def test_the_arms_are_mirror_images_at_mirrored_angles():
    angles = dict(ZERO, LShoulderPitch=0.4, LShoulderRoll=0.3, LElbowYaw=-0.7, LElbowRoll=-0.9, LWristYaw=0.5)
    angles.update(RShoulderPitch=0.4, RShoulderRoll=-0.3, RElbowYaw=0.7, RElbowRoll=0.9, RWristYaw=-0.5)
    for left, right in (("LElbow", "RElbow"), ("l_wrist", "r_wrist"), ("l_hand", "r_hand")):
        assert origin(angles, right) == pytest.approx(origin(angles, left) * [1, -1, 1])


@pytest.mark.parametrize("limit", ["lower", "upper"])
def test_the_shoulder_pitch_at_its_limits_swings_the_arm_about_the_shoulder_in_the_sagittal_plane(limit):
    angle = getattr(JOINTS["LShoulderPitch"], limit)
    angles = dict(ZERO, LShoulderPitch=angle)
    shoulder, elbow = origin(angles, "LShoulder"), origin(angles, "LElbow")
    # Axis y: x turns towards -z for a positive angle (the arm hangs down at the rest centre of about 1.56).
    assert elbow - shoulder == pytest.approx([0.1812 * math.cos(angle) + 0.00013 * math.sin(angle), 0.015,
                                              -0.1812 * math.sin(angle) + 0.00013 * math.cos(angle)])


@pytest.mark.parametrize("limit", ["lower", "upper"])
def test_the_shoulder_roll_at_its_limits_opens_the_arm_outwards(limit):
    for side, sign in (("L", 1), ("R", -1)):
        name = side + "ShoulderRoll"
        angle = getattr(JOINTS[name], limit)
        shoulder, elbow = (origin(dict(ZERO, **{name: angle}), side + link) for link in ("Shoulder", "Elbow"))
        assert elbow - shoulder == pytest.approx([0.1812 * math.cos(angle) - sign * 0.015 * math.sin(angle),
                                                  0.1812 * math.sin(angle) + sign * 0.015 * math.cos(angle), 0.00013])
        assert sign * (elbow - shoulder)[1] > 0  # outwards on both sides, within the limits


@pytest.mark.parametrize("joint,limit", [(joint, limit) for joint in ("HipPitch", "KneePitch", "HipRoll")
                                         for limit in ("lower", "upper")])
def test_the_leg_at_its_limits_tilts_the_body_about_its_axis(joint, limit):
    angle = getattr(JOINTS[joint], limit)
    frames = link_frames({joint: [angle]}, count=1)
    pivot = {"KneePitch": "Pelvis", "HipPitch": "Hip", "HipRoll": "torso"}[joint]
    rest = link_frames({joint: [0.0]}, count=1)
    above = frames.origins["Neck"][0] - frames.origins[pivot][0]
    above_at_zero = rest.origins["Neck"][0] - rest.origins[pivot][0]
    assert numpy.linalg.norm(above) == pytest.approx(numpy.linalg.norm(above_at_zero))  # a rotation about the pivot
    if joint == "HipRoll":  # axis -x: a positive roll leans the torso to its left (+y)
        assert numpy.sign(above[1] - above_at_zero[1]) == numpy.sign(angle)
    else:  # axis -y: a negative pitch leans forward (+x)
        assert numpy.sign(above[0] - above_at_zero[0]) == -numpy.sign(angle)


def test_the_heading_turns_the_whole_robot_about_the_vertical():
    turned, straight = origin({}, "l_hand", [math.pi / 2]), origin({}, "l_hand", [0.0])
    assert turned == pytest.approx([-straight[1], straight[0], straight[2]])


def test_a_joint_not_given_is_at_its_rest_centre_and_the_head_at_zero():
    assert rest_angle("LShoulderPitch") == 1.5625 and rest_angle("HeadYaw") == 0.0
    assert origin({}, "l_hand") == pytest.approx(origin({"LShoulderPitch": 1.5625}, "l_hand"))
    assert [link.joint for link in CHAIN if link.joint][:5] == ["KneePitch", "HipPitch", "HipRoll", "HeadYaw",
                                                                "HeadPitch"]


def test_the_figure_is_about_as_tall_as_pepper():
    frames = link_frames({}, count=1)
    head = next(solid for solid in BODY if solid.name == "head")
    top = frames.point("Head", head.end)[0][2] + head.radius
    assert 1.17 < top < 1.25  # Pepper is 1.21 m high


def _sampled_distance(capsule, other, frames, samples=2001):
    """Brute force: points on the capsule's axis against the other solid, densely sampled."""
    start, end = frames.point(capsule.link, capsule.start)[0], frames.point(capsule.link, capsule.end)[0]
    points = start + numpy.linspace(0, 1, samples)[:, None] * (end - start)
    if isinstance(other, Capsule):
        other_start, other_end = frames.point(other.link, other.start)[0], frames.point(other.link, other.end)[0]
        inner = numpy.linspace(0, 1, samples)[:, None] * (other_end - other_start) + other_start
        distances = numpy.min(numpy.linalg.norm(points[:, None, :] - inner[None, :, :], axis=2), axis=1)
        return distances.min() - capsule.radius - other.radius
    centre = frames.point(other.link, other.centre)[0]
    local = (points - centre).dot(frames.rotations[other.link][0])
    return numpy.min(numpy.linalg.norm(numpy.maximum(numpy.abs(local) - other.half_size, 0), axis=1)) - capsule.radius


def test_the_distances_match_a_brute_force_sampling():
    angles = dict(LShoulderPitch=0.9, LShoulderRoll=0.2, LElbowYaw=-1.2, LElbowRoll=-1.4, HipRoll=0.3)
    frames = link_frames({name: [value] for name, value in angles.items()})
    hand = Capsule("left hand", "l_wrist", (0.025, 0, 0), (0.085, 0, 0), 0.035)
    for other in BODY:
        assert clearance(hand, other, frames)[0] == pytest.approx(_sampled_distance(hand, other, frames), abs=2e-4)


def test_a_capsule_against_a_box_and_a_capsule_in_known_places():
    frames = link_frames({}, count=1)
    base = Box("base", "base_footprint", (0, 0, 0.15), (0.2, 0.19, 0.15))
    above = Capsule("probe", "base_footprint", (-0.1, 0, 0.4), (0.1, 0, 0.4), 0.05)
    assert clearance(above, base, frames)[0] == pytest.approx(0.4 - 0.3 - 0.05)
    across = Capsule("probe", "base_footprint", (0.5, -1, 0.2), (0.5, 1, 0.2), 0.01)
    beside = Capsule("other", "base_footprint", (0.6, 0, -1), (0.6, 0, 1), 0.02)
    assert clearance(across, beside, frames)[0] == pytest.approx(0.1 - 0.03)
    assert box_corners(base, frames)[0].min(axis=0) == pytest.approx([-0.2, -0.19, 0.0])


def test_at_rest_the_arms_clear_the_body_and_each_other():
    found = closest_per_arm(arm_clearances(link_frames({}, count=1)))
    assert set(found) == {"left", "right", "both"}
    assert all(value.distance > 0.03 for value in found.values())
    # Arms reaching across the body touch: the clearance is negative.
    crossed = dict(LShoulderPitch=0.0, LShoulderRoll=0.00872665, LElbowYaw=0.0, LElbowRoll=-1.56207,
                   RShoulderPitch=0.0, RShoulderRoll=-0.00872665, RElbowYaw=0.0, RElbowRoll=1.56207)
    assert closest_per_arm(arm_clearances(link_frames({k: [v] for k, v in crossed.items()})))["both"].distance < 0
