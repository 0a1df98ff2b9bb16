"""What ros2_control's joint_trajectory_controller checks of a trajectory before it takes it, with its messages.

The checks of `validate_trajectory_msg` in ros2_controllers' joint_trajectory_controller (jazzy branch): it runs
them on every FollowJointTrajectory goal (a goal that fails one is rejected, with no result) and on every
`joint_trajectory` message (ignored). One of its parameters changed its default between distributions:
`allow_nonzero_velocity_at_trajectory_end` is true on Humble, false from Jazzy on, where a trajectory whose last
point still moves is refused. The simulated Pepper on ROS 2 applies them before its own checks
(simulated_pepper.SimulatedController.validate: ROS 1's rules). Pure Python.
"""
from typing import NamedTuple, Optional, Sequence

FLOAT_EPSILON = 1.1920928955078125e-07  # std::numeric_limits<float>::epsilon(): the controller's "zero" velocity


class TrajectoryRules(NamedTuple):
    """The controller parameters the checks depend on; the defaults are Jazzy's."""

    allow_nonzero_velocity_at_trajectory_end: bool = False  # Humble's default: True
    allow_partial_joints_goal: bool = False
    allow_integration_in_goal_trajectories: bool = False
    has_effort_command_interface: bool = False  # Pepper's controllers command positions


JAZZY = TrajectoryRules()
HUMBLE = TrajectoryRules(allow_nonzero_velocity_at_trajectory_end=True)


def trajectory_problem(rules: TrajectoryRules, controller_joints: Sequence[str], joint_names: Sequence[str],
                       points: Sequence, stamp: Optional[float] = None, now: float = 0.0) -> str:
    """The controller's error line for the first check the trajectory fails, or "" when it passes them all.
    `points`: objects with time_from_start (s), positions, velocities, accelerations and effort (sequences);
    `stamp`: the header's start time on the clock of `now`, None for a zero stamp (start now)."""
    return (_joints_problem(rules, controller_joints, joint_names, points)
            or _end_velocity_problem(rules, joint_names, points)
            or _end_time_problem(points, stamp, now)
            or next(filter(None, (_point_problem(rules, len(joint_names), points, index)
                                  for index in range(len(points)))), ""))


def _joints_problem(rules: TrajectoryRules, controller_joints, joint_names, points) -> str:
    if not rules.allow_partial_joints_goal and len(joint_names) != len(controller_joints):
        return "Joints on incoming trajectory don't match the controller joints."
    if not joint_names:
        return "Empty joint names on incoming trajectory."
    if not points:
        return "Empty trajectory received."
    unknown = [name for name in joint_names if name not in controller_joints]
    if unknown:
        return "Incoming joint {} doesn't match the controller's joints.".format(unknown[0])
    return ""


def _end_velocity_problem(rules: TrajectoryRules, joint_names, points) -> str:
    if rules.allow_nonzero_velocity_at_trajectory_end:
        return ""
    for name, velocity in zip(joint_names, getattr(points[-1], "velocities", ()) or ()):
        if abs(velocity) > FLOAT_EPSILON:
            return "Velocity of last trajectory point of joint {} is not zero: {:.15f}".format(name, velocity)
    return ""


def _end_time_problem(points, stamp: Optional[float], now: float) -> str:
    if stamp is None:
        return ""
    end = stamp + points[-1].time_from_start
    if end < now:
        return "Received trajectory with non-zero start time ({:f}) that ends in the past ({:f})".format(stamp, end)
    return ""


def _point_problem(rules: TrajectoryRules, joint_count: int, points, index: int) -> str:
    point = points[index]
    if index > 0 and not point.time_from_start > points[index - 1].time_from_start:
        return ("Time between points {} and {} is not strictly increasing, it is {:f} and {:f} respectively").format(
            index - 1, index, points[index - 1].time_from_start, point.time_from_start)
    fields = [(name, list(getattr(point, name, ()) or ())) for name in ("positions", "velocities", "accelerations")]
    if rules.allow_integration_in_goal_trajectories:
        if not any(values for _, values in fields):
            return "The given trajectory has no position, velocity, or acceleration points."
        checked = [(name, values) for name, values in fields if values]
    else:
        checked = [fields[0]] + [(name, values) for name, values in fields[1:] if values]
    for name, values in checked:
        if len(values) != joint_count:
            return "Mismatch between joint_names size ({}) and {} ({}) at point #{}.".format(
                joint_count, name, len(values), index)
    if not rules.has_effort_command_interface and getattr(point, "effort", ()):
        return ("Trajectories with effort fields are only supported for controllers using the 'effort' command "
                "interface.")
    return ""
