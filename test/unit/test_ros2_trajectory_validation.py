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


def test_thirty_minutes_of_goals_switching_style_every_minute_pass_at_jazzys_defaults():
    """The node's goals (with their hold, as sent) over 30 minutes, the style switched every minute and each goal
    replaced as the node replaces it: none would be rejected by joint_trajectory_controller on Jazzy."""
    import numpy
    from conftest import default_configuration

    from cssr_system.motion.planners import settled
    from cssr_system.motion.styles import MotionStyle
    from cssr_system.motion.trajectory_timing import to_points
    from cssr_system.motion.waypoints import animated_parts, make_rng
    from cssr_system.pepper.joint_table import PARTS
    from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline

    configs = [default_configuration(motion_style=style, random_seed=3) for style in ("breathing", "random")]
    motions = {motion.part: motion for motion in animated_parts(configs[0], tuple(PARTS))}
    goals = 0
    for part in ("RArm", "RHand", "Leg"):
        joints = PARTS[part].joints
        state = (numpy.array(PARTS[part].centre), numpy.zeros(len(joints)), numpy.zeros(len(joints)))
        now = 0.0
        while now < 1800.0:
            minute = int(now // 60.0)
            plan = MotionStyle(configs[minute % 2], make_rng(minute)).planner(motions[part])
            while now < 60.0 * (minute + 1):
                timed = plan(now, *state)
                points = [GoalPoint(time, point.positions, point.velocities, point.accelerations)
                          for time, point in zip(settled(timed).times, to_points(settled(timed)))]
                assert trajectory_problem(JAZZY, joints, joints, points) == "", (part, now)
                goals += 1
                spline = JointTrajectorySpline(*state, to_points(timed), start_time=now)
                replaced_after = plan.replacement_time(timed)
                now = spline.end_time if replaced_after is None else now + replaced_after
                state = tuple(numpy.asarray(values, dtype=float) for values in spline.sample(now))
    assert goals > 100
