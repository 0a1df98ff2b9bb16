"""The demo's gesture: a wave of one arm, from where it is up and back to its rest posture.

`gesture_points` gives the points of a FollowJointTrajectory goal for every joint of the arm's
controller (``joint_table.PARTS``), each point at rest (zero velocity and acceleration), so the
controller moves from pose to pose along quintic segments. The poses are written for the right arm;
the left arm's are mirrored (roll and yaw angles negated). Every pose is inside the URDF limits.
Pure Python: no ROS import.
"""
from typing import List

from cssr_system.pepper.joint_table import PARTS
from cssr_system.pepper.trajectory_interpolation import TrajectoryPoint

NODE_NAME = "animateBehaviourDemoGesture"
PLAY_TOPIC = NODE_NAME + "/play"  # std_msgs/Empty: play the gesture now (relative: in the demo's namespace)
GESTURE_PART = "RArm"
GESTURE_DURATION = 4.0  # s

# (fraction of the duration, right-arm pose: RShoulderPitch, RShoulderRoll, RElbowRoll, RElbowYaw,
# RWristYaw); the last point is the rest posture.
_RIGHT_ARM = ("RShoulderPitch", "RShoulderRoll", "RElbowRoll", "RElbowYaw", "RWristYaw")
_WAVE = ((0.30, (-0.30, -0.35, 1.20, 1.30, 0.0)),  # arm raised, forearm up
         (0.45, (-0.30, -0.55, 0.60, 1.30, 0.0)),  # forearm out
         (0.60, (-0.30, -0.35, 1.20, 1.30, 0.0)),  # in
         (0.75, (-0.30, -0.55, 0.60, 1.30, 0.0)))  # out
_MIRRORED = {"ShoulderPitch": 1.0, "ShoulderRoll": -1.0, "ElbowRoll": -1.0, "ElbowYaw": -1.0, "WristYaw": -1.0}


def gesture_points(part_key: str = GESTURE_PART, duration: float = GESTURE_DURATION) -> List[TrajectoryPoint]:
    """The goal's points (joints in ``PARTS[part_key].joints`` order) of a wave lasting `duration` s;
    ValueError for a part that is not an arm or a duration that is not positive."""
    if part_key not in ("RArm", "LArm"):
        raise ValueError("the gesture is for an arm (RArm or LArm), not %r" % part_key)
    if not duration > 0.0:
        raise ValueError("the gesture's duration must be positive, not %r" % duration)
    part = PARTS[part_key]
    points = []
    for fraction, pose in _WAVE:
        value_of = {}
        for name, value in zip(_RIGHT_ARM, pose):
            suffix = name[1:]
            value_of[part_key[0] + suffix] = value if part_key == "RArm" else _MIRRORED[suffix] * value
        points.append(TrajectoryPoint(fraction * duration, tuple(value_of[name] for name in part.joints),
                                      (0.0,) * len(part.joints), (0.0,) * len(part.joints)))
    points.append(TrajectoryPoint(duration, tuple(part.centre), (0.0,) * len(part.joints), (0.0,) * len(part.joints)))
    return points
