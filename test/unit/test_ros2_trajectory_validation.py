"""Unit tests of joint_trajectory_controller's checks on ROS 2 (pepper/ros2_trajectory_validation.py): no ROS."""
from cssr_system.pepper.ros2_trajectory_validation import HUMBLE, JAZZY, trajectory_problem
from cssr_system.pepper.simulated_pepper import GoalPoint

JOINTS = ("HipRoll", "HipPitch", "KneePitch")
AT_REST = GoalPoint(2.0, [0.0, 0.1, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0])


def problem(points, names=JOINTS, rules=JAZZY, stamp=None, now=0.0):
    return trajectory_problem(rules, JOINTS, list(names), points, stamp, now)


def test_a_trajectory_ending_at_rest_passes_on_every_distribution():
    points = [GoalPoint(1.0, [0.0, 0.05, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.0]), AT_REST]
    assert problem(points) == "" and problem(points, rules=HUMBLE) == ""
    assert problem([GoalPoint(1.0, [0.0, 0.0, 0.0])]) == "", "velocities and accelerations may be left out"


def test_a_last_point_still_moving_is_refused_with_jazzys_default_and_taken_with_humbles():
    moving = [GoalPoint(1.0, [0.0, 0.1, 0.0], [0.0, -0.054, 0.0], [0.0, 0.0, 0.0])]
    assert problem(moving) == "Velocity of last trajectory point of joint HipPitch is not zero: -0.054000000000000"
    assert problem(moving, rules=HUMBLE) == ""
    almost = [GoalPoint(1.0, [0.0, 0.1, 0.0], [0.0, 1e-8, 0.0])]
    assert problem(almost) == "", "within float epsilon counts as zero"


def test_joints_points_and_times_are_checked_with_the_controllers_messages():
    assert problem([AT_REST], names=JOINTS[:2]) == "Joints on incoming trajectory don't match the controller joints."
    assert problem([]) == "Empty trajectory received."
    assert problem([AT_REST], names=("HipRoll", "HipPitch", "RElbowRoll")) == (
        "Incoming joint RElbowRoll doesn't match the controller's joints.")
    backwards = [AT_REST._replace(time_from_start=2.0), AT_REST._replace(time_from_start=1.5)]
    assert problem(backwards) == ("Time between points 0 and 1 is not strictly increasing, it is 2.000000 and "
                                  "1.500000 respectively")
    assert problem([AT_REST._replace(velocities=[0.0, 0.0])]) == (
        "Mismatch between joint_names size (3) and velocities (2) at point #0.")
    assert problem([AT_REST._replace(positions=[])]) == (
        "Mismatch between joint_names size (3) and positions (0) at point #0.")
    assert problem([AT_REST._replace(effort=[1.0, 1.0, 1.0])]).startswith("Trajectories with effort fields")
    assert problem([AT_REST], stamp=10.0, now=13.0) == (
        "Received trajectory with non-zero start time (10.000000) that ends in the past (12.000000)")
    assert problem([AT_REST], stamp=10.0, now=11.0) == ""
