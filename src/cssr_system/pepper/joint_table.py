"""Pepper's joints, limits, controllers and rest centres: the one place that holds these facts.

Numbers come from the Pepper URDF (limits, maximum velocities) and from the reference node's rest
posture (centres).  Everything else in the package reads them from here.
"""
import math
from collections import OrderedDict
from typing import Dict, NamedTuple, Tuple


class Joint(NamedTuple):
    """One revolute joint (or a hand, which is unitless: 0 closed .. 1 open)."""

    name: str
    lower: float
    upper: float
    max_velocity: float

    @property
    def full_range(self) -> float:
        return self.upper - self.lower


class Part(NamedTuple):
    """A group of joints driven by one FollowJointTrajectory controller."""

    key: str  # key of the part in the topic files
    label: str  # human-readable name, used in logs and reports
    joints: Tuple[str, ...]  # every joint of the controller, in the order of the configuration ranges
    centre: Tuple[float, ...]  # rest posture, the centre of the random motion, same order


JOINTS: Dict[str, Joint] = OrderedDict(
    (joint.name, joint)
    for joint in (
        Joint("LShoulderPitch", -2.08567, 2.08567, 7.33998),
        Joint("LShoulderRoll", 0.00872665, 1.56207, 9.22756),
        Joint("LElbowYaw", -2.08567, 2.08567, 7.33998),
        Joint("LElbowRoll", -1.56207, -0.00872665, 9.22756),
        Joint("LWristYaw", -1.82387, 1.82387, 17.3835),
        Joint("LHand", 0.02, 0.98, 12.56),
        Joint("RShoulderPitch", -2.08567, 2.08567, 7.33998),
        Joint("RShoulderRoll", -1.56207, -0.00872665, 9.22756),
        Joint("RElbowYaw", -2.08567, 2.08567, 7.33998),
        Joint("RElbowRoll", 0.00872665, 1.56207, 9.22756),
        Joint("RWristYaw", -1.82387, 1.82387, 17.3835),
        Joint("RHand", 0.02, 0.98, 12.56),
        Joint("HipRoll", -0.514872, 0.514872, 2.27032),
        Joint("HipPitch", -1.03847, 1.03847, 2.93276),
        Joint("KneePitch", -0.514872, 0.514872, 2.93276),
        # Not animated (owned by the attention subsystem), but served by the simulated Pepper.
        Joint("HeadYaw", -2.08567, 2.08567, 7.33998),
        Joint("HeadPitch", -0.706858, 0.637045, 9.22756),
    )
)

# Continuous wheel joints: published in /joint_states by the simulated Pepper, never commanded.
WHEEL_JOINTS: Tuple[str, ...] = ("WheelFL", "WheelFR", "WheelB")

PARTS: Dict[str, Part] = OrderedDict(
    (part.key, part)
    for part in (
        Part("RArm", "right arm",
             ("RShoulderPitch", "RShoulderRoll", "RElbowRoll", "RElbowYaw", "RWristYaw"),
             (1.5410, -0.09664, 0.30664, 1.6981, -0.05679)),
        Part("LArm", "left arm",
             ("LShoulderPitch", "LShoulderRoll", "LElbowRoll", "LElbowYaw", "LWristYaw"),
             (1.5625, 0.0997, -0.3434, -1.7150, 0.06592)),
        Part("RHand", "right hand", ("RHand",), (0.66608,)),
        Part("LHand", "left hand", ("LHand",), (0.6695,)),
        Part("Leg", "leg", ("HipPitch", "HipRoll", "KneePitch"), (-0.1107, -0.00766, 0.03221)),
    )
)

# The head's controller exists on both platforms; this package never drives it.
HEAD_PART = Part("Head", "head", ("HeadYaw", "HeadPitch"), (0.0, 0.0))

# Each controller's own joint order, as Pepper's controller configuration lists them (keys of PARTS, and the head's):
# the order of its feedback and state messages. PARTS keeps this package's order; goals are matched by joint name.
CONTROLLER_JOINTS: Dict[str, Tuple[str, ...]] = {
    "RArm": ("RShoulderPitch", "RShoulderRoll", "RElbowYaw", "RElbowRoll", "RWristYaw"),
    "LArm": ("LShoulderPitch", "LShoulderRoll", "LElbowYaw", "LElbowRoll", "LWristYaw"),
    "RHand": ("RHand",),
    "LHand": ("LHand",),
    "Leg": ("HipRoll", "HipPitch", "KneePitch"),
    "Head": ("HeadYaw", "HeadPitch"),
}

# Controller names on the robot and in Gazebo (<namespace>/<name>/follow_joint_trajectory).
CONTROLLER_NAMES: Dict[str, str] = {
    "RArm": "RightArm_controller",
    "LArm": "LeftArm_controller",
    "RHand": "RightHand_controller",
    "LHand": "LeftHand_controller",
    "Leg": "Pelvis_controller",
    "Head": "Head_controller",
}
ACTION_NAME = "follow_joint_trajectory"  # a controller's FollowJointTrajectory action, inside its namespace
COMMAND_TOPIC_NAME = "command"  # its trajectory_msgs/JointTrajectory topic, obeyed like a goal without a result


def command_topic(action_namespace: str) -> str:
    """The command topic of the controller that serves `action_namespace` (``<controller>/command``)."""
    controller = action_namespace.rstrip("/")
    if controller.endswith("/" + ACTION_NAME):
        controller = controller[:-len(ACTION_NAME) - 1]
    return controller + "/" + COMMAND_TOPIC_NAME


# Joint speeds are capped at this fraction of each joint's maximum (the robot's driver moves at 20 %).
SPEED_FRACTION = 0.2

# The physical robot's driver, naoqi_dcm_driver (pepper_dcm.yaml): it writes the controllers' commands to NAOqi at
# DRIVER_RATE, only when some joint's command differs from its measured angle by more than DRIVER_JOINT_PRECISION,
# with ALMotion.setAngles(names, angles, DRIVER_SPEED_FRACTION): all controlled joints at once.
DRIVER_RATE = 12.0  # Hz (ControllerFrequency)
DRIVER_JOINT_PRECISION = 0.09  # rad (JointPrecision)
DRIVER_SPEED_FRACTION = 0.2  # of each joint's maximum speed

# Base yaw (NAOqi move configuration): maximum angular velocity, and the default of moveTo.
BASE_MAX_ANGULAR_VELOCITY = 2.0  # rad/s; rotMaximumRange is a fraction of this
BASE_MOVETO_ANGULAR_VELOCITY = 1.0  # rad/s, the speed at which moveTo turns by default
BASE_MOVETO_SETTLE_TIME = 1.0  # s the robot's driver sleeps after each moveTo
BASE_MOVETO_LINEAR_VELOCITY = 0.35  # m/s, NAOqi's default walking speed, for the time a moveTo takes
# Gazebo's model-velocity plugin on /pepper/cmd_vel.
BASE_VELOCITY_COMMAND_TIMEOUT = 0.5  # s without a message before the plugin zeroes the velocity
BASE_MAX_ANGULAR_ACCELERATION = 2.4  # rad/s^2 the plugin allows


def joint(name: str) -> Joint:
    """The joint called `name`; a KeyError names unknown joints."""
    return JOINTS[name]


def part_of(joint_name: str) -> str:
    """Key of the animated part whose controller drives `joint_name`; KeyError for any other."""
    for key, part in PARTS.items():
        if joint_name in part.joints:
            return key
    raise KeyError("joint {!r} is not animated by this package".format(joint_name))


def centre_of(joint_name: str) -> float:
    """The rest position of an animated joint: the centre of its random motion."""
    part = PARTS[part_of(joint_name)]
    return part.centre[part.joints.index(joint_name)]


def short_name(joint_name: str) -> str:
    """A joint's name without its side letter: RShoulderPitch -> ShoulderPitch, HipRoll unchanged."""
    return joint_name[1:] if joint_name[0] in "LR" and joint_name[1].isupper() else joint_name


# The sign of a forward lean of the torso in HipPitch: its axis is -y (figure/kinematics.py), so a negative angle
# tilts the torso forward (the rest centre, -0.11, leans a little already).
HIP_PITCH_FORWARD = -1.0

# Arm joints (short names) that move as mirror images on the two sides: the right's motion is the left's negated.
MIRRORED_JOINTS = ("ShoulderRoll", "ElbowRoll", "ElbowYaw", "WristYaw")


def speed_limit(name: str) -> float:
    """The highest speed this package commands for a joint (rad/s, or unit/s for a hand)."""
    return JOINTS[name].max_velocity * SPEED_FRACTION


# What a Twist on the base's Wheels topic means (README: "Topics, actions and services").
RELATIVE, VELOCITY = "relative", "velocity"
KINDS: tuple = (RELATIVE, VELOCITY)

# Last name segment of the one relative Wheels topic; every other topic carries velocities.
RELATIVE_TOPIC_SEGMENT = "cmd_moveto"


def wheels_command_kind(topic: str) -> str:
    """RELATIVE when the last segment of the topic name is ``cmd_moveto``, otherwise VELOCITY.

    Namespaces and a leading ``~`` do not matter: ``/pepper_dcm/cmd_moveto``, ``cmd_moveto``,
    ``/robot1/pepper_dcm/cmd_moveto`` are relative; ``/pepper/cmd_vel`` is a velocity topic.
    """
    name = topic.strip().rstrip("/")
    if not name:
        raise ValueError("wheels topic name is empty")
    last_segment = name.rsplit("/", 1)[-1].lstrip("~")
    return RELATIVE if last_segment == RELATIVE_TOPIC_SEGMENT else VELOCITY


def base_busy_time(kind: str, x: float, y: float, angular_z: float) -> float:
    """How long the base is busy with one Twist on a Wheels topic of `kind` (s): on cmd_moveto the
    driver's moveTo (the turn at its default speed, a move at BASE_MOVETO_LINEAR_VELOCITY, then its
    settle time; a zero Twist is a no-op); on a velocity topic until the plugin's time-out."""
    if kind != RELATIVE:
        return BASE_VELOCITY_COMMAND_TIMEOUT
    if not (x or y or angular_z):
        return 0.0
    motion = max(abs(angular_z) / BASE_MOVETO_ANGULAR_VELOCITY, math.hypot(x, y) / BASE_MOVETO_LINEAR_VELOCITY)
    return motion + BASE_MOVETO_SETTLE_TIME
