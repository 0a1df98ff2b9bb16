"""The FollowJointTrajectory types this package uses must be wire-compatible with the robot's
controllers: their checksums must equal those of the real control_msgs package (ROS 1)."""
import pytest

control_msgs = pytest.importorskip("control_msgs.msg", reason="source the workspace (make test does)")

# `rosmsg md5` of the real control_msgs 1.3+ (reference/pepper-facts.md section 9).
REAL_CHECKSUMS = {
    "FollowJointTrajectoryAction": "bc4f9b743838566551c0390c65f1a248",
    "FollowJointTrajectoryActionGoal": "cff5c1d533bf2f82dd0138d57f4304bb",
    "FollowJointTrajectoryActionResult": "c4fb3b000dc9da4fd99699380efcc5d9",
    "FollowJointTrajectoryActionFeedback": "d8920dc4eae9fc107e00999cce4be641",
    "FollowJointTrajectoryGoal": "69636787b6ecbde4d61d711979bc7ecb",
    "FollowJointTrajectoryResult": "493383b18409bfb604b4e26c676401d2",
    "FollowJointTrajectoryFeedback": "10817c60c2486ef6b33e97dcd87f4474",
    "JointTolerance": "f544fe9c16cf04547e135dd6063ff5be",
}


@pytest.mark.parametrize("type_name", sorted(REAL_CHECKSUMS))
def test_checksum_equals_real_control_msgs(type_name):
    assert getattr(control_msgs, type_name)._md5sum == REAL_CHECKSUMS[type_name]


def test_result_error_codes_match_the_controllers():
    result = control_msgs.FollowJointTrajectoryResult
    assert (result.SUCCESSFUL, result.INVALID_GOAL, result.INVALID_JOINTS) == (0, -1, -2)
    assert (result.PATH_TOLERANCE_VIOLATED, result.GOAL_TOLERANCE_VIOLATED) == (-4, -5)
