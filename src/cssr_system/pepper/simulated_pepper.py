"""A kinematic Pepper: controller semantics and base kinematics, with no ROS communication.

scripts/simulatedPepper.py serves this model on the ROS interfaces of the robot (naoqi_dcm_driver,
``pepper_dcm``) or of the Gazebo simulator (``pepper``), in its own namespace.  Every method takes the current time
explicitly (seconds, any fixed origin), so the model is stepped and tested without a clock.

Joint controllers (`SimulatedController`) mirror ros_controllers' joint_trajectory_controller; each lists its
joints in the robot's controller order (joint_table.CONTROLLER_JOINTS), which its states and feedback follow:

- a goal must name exactly the controller's joints, in any order (else INVALID_JOINTS); every point
  carries one position per joint, velocities and accelerations are empty or one per joint, times
  strictly increase and every value is finite (else INVALID_GOAL);
- an empty trajectory (that names the joints) stops: hold the current position, accept, succeed at the
  next update;
- the trajectory starts at its stamp, or now when the stamp is None (a zero header stamp); points
  at or before the start are dropped, and a goal left with no point is rejected (INVALID_GOAL);
- the first segment starts from the current desired state (position, velocity, acceleration), so a
  new goal is spliced smoothly onto the running motion; it preempts the active goal at once, and
  with a future stamp the old motion continues until the new one starts;
- cancel holds the current position with zero velocity (instant stop);
- Joint limits: positions beyond the URDF limits are clamped (points at acceptance, and the sampled
  state, where a clamped joint has zero velocity and acceleration); each point value beyond a limit
  is reported as a `LimitViolation` and counted in `limit_violation_count`.

The control loop.  A controller updates at `control_rate` Hz, at whole periods from its creation; only
there does it judge its goal.  Each update reads the hardware, compares it with the desired state at that
time (error = desired - reported) and writes the desired position.  The hardware follows the command
exactly, so the position it reports at an update is the one written at the update before; the velocity
it reports is, by `velocity_report`:
  MEASURED   that position minus the one reported at the update before, over one period (as Gazebo does)
  ZERO       always 0 (the physical robot's driver never fills in velocities)
  COMMANDED  no tracking at all: position and velocity are exactly the desired state at the update (the
             model's behaviour before it had a control loop; every goal then succeeds at its end).
Events (goals, commands, cancels) first run the updates due before them.

Verdicts, for goals only (a command-topic trajectory is never judged).  Tolerances per joint (position,
velocity, acceleration; 0 = not checked, else |error| > tolerance is a violation; the acceleration error is
always 0, the hardware reports no acceleration): on the path none by default, at the goal the velocity
`stopped_velocity_tolerance`; the goal's path_tolerance and goal_tolerance override them per joint (> 0
sets, < 0 unchecks, 0 keeps), its goal_time_tolerance overrides `goal_time` the same way (< 0 gives 0).
- an update before the trajectory's end (from the goal's acceptance on) checks the path tolerances: a
  violation aborts the goal with PATH_TOLERANCE_VIOLATED, "<joint> path error <position error>";
- an update at or after the end checks the goal tolerances: a joint inside is marked done; when every joint
  is done the goal succeeds; a joint outside at or after end + goal time aborts it with
  GOAL_TOLERANCE_VIOLATED, "<joint> goal error <position error>" (six decimals, as the controller prints it).
Past its end the desired state holds the last point with zero velocity, while the velocity MEASURED at the
end is that of the last period before it: even a motion that ends at rest can fail the stopped velocity
check, unless the goal time leaves a period or two to settle.  A verdict does not change the motion.

Base (`MoveToBase`, `VelocityBase`): see their docstrings.  The heading is unwrapped (radians,
counter-clockwise positive) and the base never translates.

Drivers (`SimulatedPepper`'s `driver`): what moves the joints.  IDEAL: the controllers' hardware as above;
NAOQI_DCM: the physical robot's naoqi_dcm_driver executing the controllers' commands (`NaoqiDcmDriver`);
NAOQI_DRIVER: the robot's other driver, naoqi_driver, executing ``/joint_angles`` messages
(naoqi_bridge_msgs/JointAnglesWithSpeed) as ALMotion setAngles does (`NaoqiDriver`).
"""
import math
from collections import OrderedDict
from typing import Any, Dict, List, Mapping, NamedTuple, Optional, Sequence, Tuple

import numpy

from cssr_system.pepper.joint_table import (DRIVER_JOINT_PRECISION, DRIVER_RATE, DRIVER_SPEED_FRACTION,
                                            ACTION_NAME, RELATIVE, wheels_command_kind,
                                            BASE_MAX_ANGULAR_ACCELERATION, BASE_MAX_ANGULAR_VELOCITY,
                                            BASE_MOVETO_ANGULAR_VELOCITY, BASE_MOVETO_SETTLE_TIME,
                                            BASE_VELOCITY_COMMAND_TIMEOUT, CONTROLLER_JOINTS, CONTROLLER_NAMES,
                                            HEAD_PART, JOINTS, PARTS, WHEEL_JOINTS, Part)
from cssr_system.pepper.trajectory_interpolation import (JointTrajectorySpline, TrajectoryError,
                                                         TrajectoryPoint)

# control_msgs/FollowJointTrajectoryResult error codes.
SUCCESSFUL = 0
INVALID_GOAL = -1
INVALID_JOINTS = -2
PATH_TOLERANCE_VIOLATED = -4
GOAL_TOLERANCE_VIOLATED = -5

# What the hardware reports as a joint's velocity (module docstring).
MEASURED, COMMANDED, ZERO = "measured", "commanded", "zero"
VELOCITY_REPORTS = (MEASURED, COMMANDED, ZERO)
# The controllers' defaults: the rate of their control loop, and the constraints Pepper's configuration leaves
# at the controller's own defaults.
CONTROL_RATE = 50.0  # Hz (the robot's driver runs its controllers at DRIVER_RATE)
GOAL_TIME = 0.0  # s after a trajectory's end allowed to get inside the goal tolerances
STOPPED_VELOCITY_TOLERANCE = 0.01  # rad/s: the goal's velocity tolerance of every joint
_DUE_MARGIN = 1e-9  # s: an update a rounding error after `now` is still due at `now`

# Base command kinds.


class Platform(NamedTuple):
    """The ROS interface served: namespace, controllers (part keys) and the base topic."""

    name: str
    namespace: str
    controller_keys: Tuple[str, ...]  # keys of PARTS, or HEAD_PART.key
    base_topic: str  # relative to the namespace; its name says how commands are meant

    @property
    def base_kind(self) -> str:
        """RELATIVE or VELOCITY, decided from the topic name as the node decides it."""
        return wheels_command_kind(self.base_topic)


PLATFORMS: Dict[str, Platform] = OrderedDict(
    (platform.name, platform)
    for platform in (
        Platform("robot", "pepper_dcm", ("RArm", "LArm", "RHand", "LHand", "Leg", HEAD_PART.key),
                 "cmd_moveto"),
        Platform("simulator", "pepper", ("RArm", "LArm", "Leg", HEAD_PART.key), "cmd_vel"),
    )
)

POSTURES = ("rest", "zero")


def part(key: str) -> Part:
    """The part of a controller key (PARTS, or the head)."""
    return HEAD_PART if key == HEAD_PART.key else PARTS[key]


def action_namespace(platform: Platform, key: str) -> str:
    """The FollowJointTrajectory action namespace of a controller on a platform."""
    return "{}/{}/{}".format(platform.namespace, CONTROLLER_NAMES[key], ACTION_NAME)


def base_topic(platform: Platform) -> str:
    return "{}/{}".format(platform.namespace, platform.base_topic)


def odometry_topic(platform: Platform) -> str:
    return "{}/odom".format(platform.namespace)


def posture(key: str, name: str = "rest") -> Tuple[float, ...]:
    """Initial positions of a part (joint_table.PARTS order): its centre ("rest") or the URDF zero clamped into
    the limits."""
    if name == "rest":
        return tuple(part(key).centre)
    if name == "zero":
        return tuple(min(max(0.0, JOINTS[joint].lower), JOINTS[joint].upper) for joint in part(key).joints)
    raise ValueError("unknown posture {!r} (expected one of: {})".format(name, ", ".join(POSTURES)))


def controller_posture(key: str, name: str = "rest",
                       initial_positions: Optional[Mapping[str, float]] = None) -> Tuple[float, ...]:
    """`posture` in the order of the controller's joints (joint_table.CONTROLLER_JOINTS), with the joints that
    `initial_positions` names there instead (the controller clamps them into the limits)."""
    by_name = dict(zip(part(key).joints, posture(key, name)))
    by_name.update((joint, value) for joint, value in (initial_positions or {}).items() if joint in by_name)
    return tuple(by_name[joint] for joint in CONTROLLER_JOINTS[key])


def parse_initial_positions(text: str) -> Dict[str, float]:
    """`initial_positions` from "Joint=value, Joint=value" (a joint a controller drives, a finite number; "" none);
    ValueError naming what is wrong. Lets a test start the robot as another node left it, off the centres."""
    positions: Dict[str, float] = {}
    for item in (piece.strip() for piece in text.split(",")):
        if not item:
            continue
        joint, _, value = (piece.strip() for piece in item.partition("="))
        if joint not in JOINTS:
            raise ValueError("initial_positions: unknown joint {!r} (expected Joint=value, ...)".format(joint))
        try:
            number = float(value)
        except ValueError:
            number = float("nan")
        if not math.isfinite(number):
            raise ValueError("initial_positions: {} needs a finite number (got {!r})".format(joint, value))
        positions[joint] = number
    return positions


class JointTrajectoryState(NamedTuple):
    """Positions, velocities and accelerations of a controller's joints, in the controller's order."""

    positions: numpy.ndarray
    velocities: numpy.ndarray
    accelerations: numpy.ndarray


class GoalPoint(NamedTuple):
    """One point of a goal: time from the trajectory start; velocities/accelerations (and effort) may be empty."""

    time_from_start: float
    positions: Sequence[float]
    velocities: Sequence[float] = ()
    accelerations: Sequence[float] = ()
    effort: Sequence[float] = ()  # checked by ROS 2's rules only (ros2_trajectory_validation)


class JointTolerance(NamedTuple):
    """One joint's tolerances asked by a goal, as control_msgs/JointTolerance: a value > 0 sets that tolerance,
    < 0 leaves it unchecked, 0 keeps the controller's."""

    name: str
    position: float = 0.0
    velocity: float = 0.0
    acceleration: float = 0.0


class GoalTolerances(NamedTuple):
    """The tolerances a goal carries: path_tolerance and goal_tolerance (JointTolerance, or anything with the same
    fields; joints the controller lacks are ignored) and goal_time_tolerance (s: > 0 sets it, < 0 makes it 0,
    0 keeps the controller's goal_time)."""

    path: Sequence[Any] = ()
    goal: Sequence[Any] = ()
    goal_time: float = 0.0


class LimitViolation(NamedTuple):
    joint: str
    value: float  # the position asked for
    limit: float  # the limit it crossed (the position executed)
    point_index: int  # index of the point in the goal


MAX_VIOLATIONS_DESCRIBED = 4  # per goal, so one bad goal makes one readable warning


def describe_violations(violations: Sequence[LimitViolation]) -> str:
    """One line naming a goal's first values beyond the joint limits, and how many more there are."""
    described = ["point {} {} = {:.5g} beyond its limit {:.5g}".format(
        violation.point_index, violation.joint, violation.value, violation.limit)
        for violation in violations[:MAX_VIOLATIONS_DESCRIBED]]
    if len(violations) > MAX_VIOLATIONS_DESCRIBED:
        described.append("and {} more".format(len(violations) - MAX_VIOLATIONS_DESCRIBED))
    return "; ".join(described)


class Acceptance(NamedTuple):
    """The answer to a goal. When rejected, nothing changed."""

    accepted: bool
    error_code: int
    error_string: str
    preempted_goal: Any = None  # the goal that was active and is now preempted, or None
    limit_violations: Tuple[LimitViolation, ...] = ()


class GoalOutcome(NamedTuple):
    """A goal that ended by itself: SUCCESSFUL, or aborted (PATH_ or GOAL_TOLERANCE_VIOLATED)."""

    goal: Any
    error_code: int
    error_string: str
    time: float = 0.0  # the update that decided it


class ControllerUpdate(NamedTuple):
    """One update of the control loop: its time, the desired state and what the hardware reported (which has
    no accelerations: zeros)."""

    time: float
    desired: JointTrajectoryState
    actual: JointTrajectoryState

    @property
    def error(self) -> JointTrajectoryState:
        """desired - actual; the acceleration error is 0, as nothing measures accelerations."""
        return JointTrajectoryState(self.desired.positions - self.actual.positions,
                                    self.desired.velocities - self.actual.velocities,
                                    numpy.zeros(len(self.desired.positions)))

    def feedback_points(self) -> Dict[str, Dict[str, List[float]]]:
        """The action feedback's `desired`, `actual` and `error` points of this update (each a JointTrajectoryPoint's
        fields, in the controller's joint order), as joint_trajectory_controller fills them: nothing measures
        accelerations, so only the desired state has them."""
        desired, actual, error = self.desired, self.actual, self.error
        return {"desired": dict(positions=desired.positions.tolist(), velocities=desired.velocities.tolist(),
                                accelerations=desired.accelerations.tolist()),
                "actual": dict(positions=actual.positions.tolist(), velocities=actual.velocities.tolist()),
                "error": dict(positions=error.positions.tolist(), velocities=error.velocities.tolist())}

    def state_points(self) -> Dict[str, Dict[str, List[float]]]:
        """The ``reference``, ``feedback``, ``error`` and ``output`` points of ROS 2's controller_state message
        (control_msgs/msg/JointTrajectoryControllerState) for this update, as ros2_controllers'
        joint_trajectory_controller fills them: the output is the position it writes, the desired one."""
        points = self.feedback_points()
        return {"reference": points["desired"], "feedback": points["actual"], "error": points["error"],
                "output": dict(positions=self.desired.positions.tolist())}


class _Constraints(NamedTuple):
    """The tolerances one goal is judged by: (joints, 3) arrays of position, velocity and acceleration
    tolerances, 0 where unchecked, and the goal time (s)."""

    path: numpy.ndarray
    goal: numpy.ndarray
    goal_time: float


def _override(current: float, requested: float) -> float:
    """A tolerance after a goal's request: > 0 replaces it, < 0 unchecks it (0), 0 keeps it."""
    if requested > 0.0:
        return float(requested)
    if requested < 0.0:
        return 0.0
    return current


def _override_rows(table: numpy.ndarray, index: Dict[str, int], requests: Sequence[Any]) -> None:
    for request in requests:
        row = index.get(request.name)
        if row is None:
            continue
        for column, value in enumerate((request.position, request.velocity, request.acceleration)):
            table[row, column] = _override(table[row, column], value)


def _violated(tolerances: numpy.ndarray, error: JointTrajectoryState) -> numpy.ndarray:
    """Per joint: whether some checked tolerance (> 0) is smaller than its |error|."""
    errors = numpy.column_stack((error.positions, error.velocities, error.accelerations))
    return numpy.any((tolerances > 0.0) & (numpy.abs(errors) > tolerances), axis=1)


def check_loop_settings(control_rate: float, velocity_report: str, goal_time: float,
                        stopped_velocity_tolerance: float) -> None:
    """ValueError naming the first setting of a controller's loop that is out of range."""
    for name, value, lowest, inclusive in (("control_rate", control_rate, 0.0, False),
                                           ("goal_time", goal_time, 0.0, True),
                                           ("stopped_velocity_tolerance", stopped_velocity_tolerance, 0.0, True)):
        number = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        if not number or value < lowest or (value == lowest and not inclusive):
            raise ValueError("{} must be a finite number {} {:g} (got {!r})".format(
                name, ">=" if inclusive else ">", lowest, value))
    if velocity_report not in VELOCITY_REPORTS:
        raise ValueError("velocity_report must be one of {} (got {!r})".format(", ".join(VELOCITY_REPORTS),
                                                                               velocity_report))


class _Hold:
    """Stand still at `positions` (zero velocity, zero acceleration) from start_time on."""

    def __init__(self, positions: numpy.ndarray, start_time: float) -> None:
        self._state = (numpy.array(positions, dtype=float), numpy.zeros(len(positions)),
                       numpy.zeros(len(positions)))
        self.end_time = start_time

    def sample(self, t: float):
        return self._state


def _reordered(values: Sequence[float], order: Sequence[int]) -> Optional[List[float]]:
    """`values` in the controller's joint order; None when the point carries none."""
    return [values[i] for i in order] if len(values or ()) else None


class SimulatedController:
    """One FollowJointTrajectory controller and its control loop (module docstring); goals are opaque tokens
    compared by ==. Time only runs forward: each event's `now` is no earlier than the previous one's."""

    def __init__(self, name: str, joint_names: Sequence[str], initial_positions: Sequence[float],
                 now: float = 0.0, control_rate: float = CONTROL_RATE, velocity_report: str = MEASURED,
                 goal_time: float = GOAL_TIME,
                 stopped_velocity_tolerance: float = STOPPED_VELOCITY_TOLERANCE) -> None:
        if len(joint_names) != len(initial_positions):
            raise ValueError("{}: {} joints but {} initial positions".format(
                name, len(joint_names), len(initial_positions)))
        check_loop_settings(control_rate, velocity_report, goal_time, stopped_velocity_tolerance)
        self.name = name
        self.joint_names: Tuple[str, ...] = tuple(joint_names)
        self._index = {joint: index for index, joint in enumerate(self.joint_names)}
        self._lower = numpy.array([JOINTS[joint].lower for joint in self.joint_names])
        self._upper = numpy.array([JOINTS[joint].upper for joint in self.joint_names])
        start = numpy.clip(numpy.array(initial_positions, dtype=float), self._lower, self._upper)
        # The desired motion: (switch time, sampler) pieces, the last piece whose time has come rules.
        self._pieces: List[Tuple[float, Any]] = [(now, _Hold(start, now))]
        self.active_goal: Any = None
        self._goal_end_time = now
        self.limit_violation_count = 0
        self.control_rate = float(control_rate)
        self.velocity_report = velocity_report
        self.goal_time = float(goal_time)
        self.stopped_velocity_tolerance = float(stopped_velocity_tolerance)
        # The loop: updates at _origin + k / control_rate; the hardware starts at rest where the motion starts.
        self._origin = now
        self._updates = 0
        at_rest = JointTrajectoryState(start.copy(), numpy.zeros(len(start)), numpy.zeros(len(start)))
        self._last = ControllerUpdate(now, at_rest, at_rest)
        self._written = start.copy()  # the position command of the last update
        self._constraints: Optional[_Constraints] = None
        self._done = numpy.zeros(len(start), dtype=bool)  # joints found inside the goal tolerances
        self._outcomes: List[GoalOutcome] = []  # decided, not yet returned by update()

    # -- state -------------------------------------------------------------------------------
    def state(self, now: float) -> JointTrajectoryState:
        """The desired state at `now`, clamped into the joint limits (a clamped joint is still)."""
        sampler = self._pieces[0][1]
        for switch_time, candidate in self._pieces:
            if switch_time <= now:
                sampler = candidate
        positions, velocities, accelerations = sampler.sample(now)
        positions = numpy.array(positions, dtype=float)
        velocities = numpy.zeros(len(positions)) if velocities is None else numpy.array(velocities, dtype=float)
        accelerations = (numpy.zeros(len(positions)) if accelerations is None
                         else numpy.array(accelerations, dtype=float))
        clamped = (positions < self._lower) | (positions > self._upper)
        if clamped.any():
            positions = numpy.clip(positions, self._lower, self._upper)
            velocities[clamped] = 0.0
            accelerations[clamped] = 0.0
        return JointTrajectoryState(positions, velocities, accelerations)

    def reported_state(self, now: float) -> JointTrajectoryState:
        """What the hardware reports at `now`: with COMMANDED the desired state at `now`; otherwise what the last
        update due by `now` read (positions, velocities; accelerations are zeros)."""
        self._catch_up(now)
        if self.velocity_report == COMMANDED:
            return self.state(now)
        return self._last.actual

    @property
    def control_period(self) -> float:
        return 1.0 / self.control_rate

    @property
    def last_update(self) -> ControllerUpdate:
        """The latest update run (its time may be the creation time: none yet)."""
        return self._last

    @property
    def goal_end_time(self) -> Optional[float]:
        """When the active goal's trajectory ends, or None without an active goal."""
        return self._goal_end_time if self.active_goal is not None else None

    # -- goals ---------------------------------------------------------------------------------
    def validate(self, joint_names: Sequence[str], points: Sequence[GoalPoint]) -> Tuple[int, str]:
        """(SUCCESSFUL, "") or the error code and text that reject this trajectory."""
        names = list(joint_names)
        if len(names) != len(self.joint_names) or set(names) != set(self.joint_names):
            return INVALID_JOINTS, self._joint_problems(names)
        previous_time = None
        for index, point in enumerate(points):
            problem = self._point_problem(index, point, previous_time)
            if problem:
                return INVALID_GOAL, problem
            previous_time = point.time_from_start
        return SUCCESSFUL, ""

    def _joint_problems(self, names: List[str]) -> str:
        missing = [joint for joint in self.joint_names if joint not in names]
        extra = sorted(set(joint for joint in names if joint not in self._index))
        duplicated = sorted(set(joint for joint in names if names.count(joint) > 1))
        problems = ["{} {}".format(word, ", ".join(joints))
                    for word, joints in (("missing", missing), ("unknown", extra), ("repeated", duplicated))
                    if joints]
        return "{}: joints must be exactly {} ({})".format(self.name, ", ".join(self.joint_names), "; ".join(problems))

    def _point_problem(self, index: int, point: GoalPoint, previous_time: Optional[float]) -> str:
        """Why point `index` is invalid, or ""."""
        size = len(self.joint_names)
        if len(point.positions) != size:
            return "{}: point {} has {} positions, expected {}".format(self.name, index, len(point.positions), size)
        for field in ("velocities", "accelerations"):
            values = getattr(point, field) or ()
            if len(values) not in (0, size):
                return "{}: point {} has {} {}, expected 0 or {}".format(self.name, index, len(values), field, size)
        values = list(point.positions) + list(point.velocities or ()) + list(point.accelerations or ())
        if not all(math.isfinite(value) for value in values + [point.time_from_start]):
            return "{}: point {} holds a value that is not finite".format(self.name, index)
        if previous_time is not None and not point.time_from_start > previous_time:
            return ("{}: time_from_start must increase strictly: point {} at {:.6g} s follows {:.6g} s").format(
                self.name, index, point.time_from_start, previous_time)
        return ""

    def submit(self, goal: Any, joint_names: Sequence[str], points: Sequence[GoalPoint], now: float,
               stamp: Optional[float] = None, tolerances: Optional[GoalTolerances] = None) -> Acceptance:
        """Accept `goal` (it becomes the active goal, preempting the previous one) or reject it. The updates due
        by `now` run first. `tolerances`: what the goal asks of its verdict (None: the controller's defaults)."""
        self._catch_up(now)
        error_code, error_string = self.validate(joint_names, points)
        if error_code != SUCCESSFUL:
            return Acceptance(False, error_code, error_string)
        start_time = now if stamp is None else max(stamp, now)
        if not points:  # the controller's "stop" command: its hold checks nothing, so it succeeds at once
            self._replace_from(now, _Hold(self.state(now).positions, now))
            unchecked = numpy.zeros((len(self.joint_names), 3))
            return self._activate(goal, now, (), _Constraints(unchecked, unchecked, 0.0))
        trajectory_start = now if stamp is None else stamp
        kept = [(index, point) for index, point in enumerate(points)
                if trajectory_start + point.time_from_start > start_time]
        if not kept:
            return Acceptance(False, INVALID_GOAL, (
                "{}: all {} point(s) are at or before the start time (last point {:.3f} s before it)").format(
                self.name, len(points),
                start_time - trajectory_start - points[-1].time_from_start))
        # The spline counts time from start_time, which may be later than the trajectory's start.
        spline_points, violations = self._spline_points(joint_names, kept, trajectory_start - start_time)
        start = self.state(start_time)
        try:
            spline = JointTrajectorySpline(start.positions, start.velocities, start.accelerations, spline_points,
                                           start_time=start_time)
        except TrajectoryError as error:  # not expected after validate(); still the controller's answer
            return Acceptance(False, INVALID_GOAL, "{}: {}".format(self.name, error))
        self._replace_from(start_time, spline, now)
        self.limit_violation_count += len(violations)
        return self._activate(goal, spline.end_time, tuple(violations), self._constraints_for(tolerances))

    def _spline_points(self, joint_names: Sequence[str], kept: Sequence[Tuple[int, GoalPoint]],
                       offset: float) -> Tuple[List[TrajectoryPoint], List[LimitViolation]]:
        """The kept points in the controller's joint order, clamped into the limits, at time_from_start + offset;
        and the values that were beyond a limit."""
        order = [list(joint_names).index(joint) for joint in self.joint_names]
        # Every point at once (validate() has checked each point's sizes): a goal of 100 points in one conversion.
        positions = numpy.array([point.positions for _, point in kept], dtype=float).reshape(len(kept), -1)[:, order]
        beyond_lower, beyond_upper = positions < self._lower, positions > self._upper
        violations = [LimitViolation(self.joint_names[joint], float(positions[row, joint]),
                                     float(self._lower[joint] if beyond_lower[row, joint] else self._upper[joint]),
                                     kept[row][0])
                      for row, joint in zip(*numpy.nonzero(beyond_lower | beyond_upper))]  # point by point
        clipped = numpy.clip(positions, self._lower, self._upper)
        spline_points = [TrajectoryPoint(point.time_from_start + offset, row, _reordered(point.velocities, order),
                                         _reordered(point.accelerations, order))
                         for (_, point), row in zip(kept, clipped)]
        return spline_points, violations

    def _constraints_for(self, tolerances: Optional[GoalTolerances]) -> _Constraints:
        """The controller's default tolerances, overridden by what the goal asks."""
        path = numpy.zeros((len(self.joint_names), 3))
        goal = numpy.zeros((len(self.joint_names), 3))
        goal[:, 1] = self.stopped_velocity_tolerance
        if tolerances is None:
            return _Constraints(path, goal, self.goal_time)
        _override_rows(path, self._index, tolerances.path)
        _override_rows(goal, self._index, tolerances.goal)
        return _Constraints(path, goal, _override(self.goal_time, tolerances.goal_time))

    def command(self, joint_names: Sequence[str], points: Sequence[GoalPoint], now: float,
                stamp: Optional[float] = None) -> Acceptance:
        """A trajectory on the controller's command topic: obeyed like a goal, but it has no goal handle, no
        result, no status and no verdict. It preempts the active goal (`Acceptance.preempted_goal`) and is spliced
        the same way."""
        return self.submit(None, joint_names, points, now, stamp)

    def cancel(self, goal: Any, now: float) -> bool:
        """Stop at once if `goal` is the active goal (True); anything else changes nothing (False). The updates
        due by `now` run first, so a goal they ended is no longer active."""
        self._catch_up(now)
        if self.active_goal is None or not self.active_goal == goal:
            return False
        self._replace_from(now, _Hold(self.state(now).positions, now))
        self.active_goal, self._constraints = None, None
        return True

    def update(self, now: float) -> List[GoalOutcome]:
        """Run the control updates due by `now`: the goals that ended since the last call, in order."""
        self._catch_up(now)
        self._prune(now)
        outcomes, self._outcomes = self._outcomes, []
        return outcomes

    def _activate(self, goal: Any, end_time: float, violations: Tuple[LimitViolation, ...],
                  constraints: _Constraints) -> Acceptance:
        preempted, self.active_goal, self._goal_end_time = self.active_goal, goal, end_time
        self._constraints = constraints if goal is not None else None
        self._done = numpy.zeros(len(self.joint_names), dtype=bool)
        return Acceptance(True, SUCCESSFUL, "", preempted, violations)

    # -- the control loop ------------------------------------------------------------------------
    def _update_time(self, count: int) -> float:
        return self._origin + count / self.control_rate

    def _catch_up(self, now: float) -> None:
        """Run every update due by `now` that has not run yet."""
        while self._update_time(self._updates + 1) <= now + _DUE_MARGIN:
            if self._idle():
                self._skip_to(now)
                return
            self._updates += 1
            self._run_update(self._update_time(self._updates))

    def _run_update(self, time: float) -> None:
        """Read the hardware, judge the active goal, write the desired position."""
        desired = self.state(time)
        self._last = ControllerUpdate(time, desired, self._read(desired))
        self._judge(self._last)
        self._written = desired.positions
        self._prune(time)

    def _read(self, desired: JointTrajectoryState) -> JointTrajectoryState:
        """What the hardware reports at an update whose desired state is `desired`."""
        zeros = numpy.zeros(len(self.joint_names))
        if self.velocity_report == COMMANDED:
            return JointTrajectoryState(desired.positions.copy(), desired.velocities.copy(), zeros)
        positions = self._written.copy()  # the joints went exactly where the last update sent them
        if self.velocity_report == MEASURED:
            return JointTrajectoryState(positions, (positions - self._last.actual.positions) / self.control_period,
                                        zeros)
        return JointTrajectoryState(positions, zeros.copy(), zeros)

    def _judge(self, update: ControllerUpdate) -> None:
        """The active goal's verdict at this update, if it has one (module docstring)."""
        if self.active_goal is None or self._constraints is None:
            return
        error = update.error
        if update.time < self._goal_end_time:
            violated = _violated(self._constraints.path, error)
            if violated.any():
                self._finish(PATH_TOLERANCE_VIOLATED, "path", int(numpy.argmax(violated)), error, update.time)
            return
        outside = _violated(self._constraints.goal, error)
        self._done |= ~outside
        if outside.any() and update.time >= self._goal_end_time + self._constraints.goal_time:
            self._finish(GOAL_TOLERANCE_VIOLATED, "goal", int(numpy.argmax(outside)), error, update.time)
        elif self._done.all():
            self._finish(SUCCESSFUL, "", 0, error, update.time)

    def _finish(self, error_code: int, kind: str, joint_index: int, error: JointTrajectoryState,
                time: float) -> None:
        error_string = "" if error_code == SUCCESSFUL else "{} {} error {:f}".format(
            self.joint_names[joint_index], kind, error.positions[joint_index])  # printed as the controller does
        self._outcomes.append(GoalOutcome(self.active_goal, error_code, error_string, time))
        self.active_goal, self._constraints = None, None

    def _idle(self) -> bool:
        """Whether further updates would change nothing: no goal, nothing planned but a hold that began by the
        last update, and the hardware reading it at rest."""
        if self.active_goal is not None or len(self._pieces) != 1 or self._pieces[0][0] > self._last.time:
            return False
        desired, actual = self._last.desired, self._last.actual
        return (isinstance(self._pieces[0][1], _Hold) and numpy.array_equal(actual.positions, desired.positions)
                and numpy.array_equal(self._written, desired.positions)
                and not actual.velocities.any() and not desired.velocities.any())

    def _skip_to(self, now: float) -> None:
        """Idle: count the updates due by `now` as run, without running them."""
        count = int(math.floor((now - self._origin) * self.control_rate + 1e-6))
        if self._update_time(count) > now + _DUE_MARGIN:
            count -= 1
        self._updates = max(self._updates, count)
        self._last = self._last._replace(time=self._update_time(self._updates))

    def _replace_from(self, switch_time: float, sampler: Any, now: Optional[float] = None) -> None:
        """Run `sampler` from switch_time on, dropping whatever was planned from then."""
        self._pieces = [piece for piece in self._pieces if piece[0] < switch_time] + [(switch_time, sampler)]
        self._prune(switch_time if now is None else now)

    def _prune(self, now: float) -> None:
        """Forget pieces that can never rule again (all but the latest one already started)."""
        started = [index for index, piece in enumerate(self._pieces) if piece[0] <= now]
        if len(started) > 1:
            del self._pieces[:started[-1]]
        switch_time, sampler = self._pieces[0]
        if started and not isinstance(sampler, _Hold) and now > sampler.end_time:
            # Past its end a spline holds its last positions: the same, without sampling it every tick.
            self._pieces[0] = (switch_time, _Hold(sampler.sample(now)[0], sampler.end_time))


class BaseState(NamedTuple):
    heading: float  # rad, unwrapped, counter-clockwise positive
    angular_velocity: float  # rad/s


class MoveToBase:
    """The robot's ``cmd_moveto``: each command is a RELATIVE turn by `theta` radians.

    naoqi_dcm_driver calls the blocking ALMotion moveTo, then sleeps: the turn runs at
    `angular_velocity` (constant speed, instant start and stop), so it lasts |theta| / angular_velocity,
    then the base is busy for `settle_time` more.  Commands arriving while busy are dropped (the
    default), or, with keep_latest, the latest of them waits and starts when the settle time ends (what a
    roscpp subscriber queue of one does when its callback blocks).  A command with theta 0 is a no-op and
    does not make the base busy.  linear.x and linear.y are not simulated (the base never translates).
    """

    def __init__(self, heading: float = 0.0, now: float = 0.0,
                 angular_velocity: float = BASE_MOVETO_ANGULAR_VELOCITY,
                 settle_time: float = BASE_MOVETO_SETTLE_TIME, keep_latest: bool = False) -> None:
        self.angular_velocity = angular_velocity
        self.settle_time = settle_time
        self.keep_latest = keep_latest
        self._start_heading = heading
        self._turn_start = now
        self._angle = 0.0
        self._pending: Optional[float] = None
        self._busy_until = now
        self.executed = 0  # turns started
        self.dropped = 0  # commands dropped because the base was busy (or replaced while pending)

    @property
    def _turn_duration(self) -> float:
        return abs(self._angle) / self.angular_velocity

    @property
    def busy_until(self) -> float:
        """End of the current turn and its settle time (in the past when idle)."""
        return self._busy_until

    def command(self, x: float, y: float, theta: float, now: float) -> str:
        """Handle one Twist: "turning", "queued", "dropped", "no-op" or "invalid" (not finite)."""
        if not all(math.isfinite(value) for value in (x, y, theta)):
            return "invalid"
        self._advance(now)
        if theta == 0.0:
            return "no-op"
        if now < self.busy_until:
            if not self.keep_latest:
                self.dropped += 1
                return "dropped"
            if self._pending is not None:
                self.dropped += 1
            self._pending = theta
            return "queued"
        self._start_turn(theta, now)
        return "turning"

    def state(self, now: float) -> BaseState:
        self._advance(now)
        elapsed = now - self._turn_start
        if elapsed < 0.0:
            return BaseState(self._start_heading, 0.0)
        if elapsed < self._turn_duration:
            speed = math.copysign(self.angular_velocity, self._angle)
            return BaseState(self._start_heading + speed * elapsed, speed)
        return BaseState(self._start_heading + self._angle, 0.0)

    def _start_turn(self, theta: float, start: float) -> None:
        self._start_heading += self._angle
        self._turn_start, self._angle = start, theta
        self._busy_until = start + self._turn_duration + self.settle_time
        self.executed += 1

    def _advance(self, now: float) -> None:
        """Start the pending turn if the base became free by `now` (at the exact moment it did)."""
        if self._pending is not None and now >= self.busy_until:
            theta, self._pending = self._pending, None
            self._start_turn(theta, self.busy_until)


class VelocityBase:
    """The simulator's ``cmd_vel``: angular.z is a target angular velocity (Gazebo's plugin).

    The target is clipped to +-max_velocity; the velocity moves toward it at no more than
    max_acceleration; BASE_VELOCITY_COMMAND_TIMEOUT after the last command the target becomes zero, and
    the base decelerates at max_acceleration (the plugin zeroes the target, the limit still applies).
    The heading is integrated exactly between calls.  linear.x/y are not simulated.
    """

    def __init__(self, heading: float = 0.0, now: float = 0.0,
                 max_velocity: float = BASE_MAX_ANGULAR_VELOCITY,
                 max_acceleration: float = BASE_MAX_ANGULAR_ACCELERATION,
                 timeout: float = BASE_VELOCITY_COMMAND_TIMEOUT) -> None:
        self.max_velocity = max_velocity
        self.max_acceleration = max_acceleration
        self.timeout = timeout
        self._heading = heading
        self._velocity = 0.0
        self._time = now
        self._target = 0.0
        self._last_command: Optional[float] = None

    def command(self, x: float, y: float, angular_z: float, now: float) -> str:
        """Handle one Twist: "velocity" (target set, clipped) or "invalid" (not finite, ignored)."""
        if not all(math.isfinite(value) for value in (x, y, angular_z)):
            return "invalid"
        self._advance(now)
        self._target = min(max(angular_z, -self.max_velocity), self.max_velocity)
        self._last_command = max(now, self._time)
        return "velocity"

    @property
    def target(self) -> float:
        return self._target

    def state(self, now: float) -> BaseState:
        self._advance(now)
        return BaseState(self._heading, self._velocity)

    def _advance(self, now: float) -> None:
        while self._time < now:
            deadline = None if self._last_command is None else self._last_command + self.timeout
            if deadline is not None and self._time < deadline:
                target, end = self._target, min(now, deadline)
            else:
                target, end = 0.0, now
            self._velocity, turned = _ramp(self._velocity, target, self.max_acceleration, end - self._time)
            self._heading += turned
            self._time = end


def _ramp(velocity: float, target: float, acceleration: float, duration: float) -> Tuple[float, float]:
    """(velocity, angle turned) after `duration` moving from velocity toward target at `acceleration`."""
    difference = target - velocity
    ramp_time = abs(difference) / acceleration if acceleration > 0.0 else math.inf
    if ramp_time >= duration:
        final = velocity + math.copysign(acceleration * duration, difference)
        return final, 0.5 * (velocity + final) * duration
    return target, 0.5 * (velocity + target) * ramp_time + target * (duration - ramp_time)


class JointStateSample(NamedTuple):
    names: Tuple[str, ...]
    positions: List[float]
    velocities: List[float]


IDEAL, NAOQI_DCM, NAOQI_DRIVER = "ideal", "naoqi_dcm", "naoqi_driver"
DRIVERS = (IDEAL, NAOQI_DCM, NAOQI_DRIVER)

# Why naoqi_driver would refuse a /joint_angles message (`joint_angles_problem`), one kind each.
LENGTHS_DIFFER = "joint_names and joint_angles differ in length"
UNKNOWN_JOINT = "unknown joint"
NOT_FINITE = "a value is not finite"
SPEED_OUT_OF_RANGE = "speed outside (0, 1]"


class NaoqiDcmDriver:
    """What the physical robot's driver makes of the controllers' commands (joint_table's DRIVER_* facts): every
    1 / DRIVER_RATE s, when some joint's command differs from its measured angle by more than
    DRIVER_JOINT_PRECISION, it sends all joints' commands at once (ALMotion.setAngles at DRIVER_SPEED_FRACTION of
    their maximum speed); each joint then moves toward its last sent command at that speed and stops there."""

    def __init__(self, joint_names: Sequence[str], positions: Sequence[float], now: float) -> None:
        self.joint_names = tuple(joint_names)
        self.positions = numpy.array(positions, dtype=float)
        self.velocities = numpy.zeros(len(self.joint_names))
        self.sent = self.positions.copy()
        self.speeds = numpy.array([JOINTS[name].max_velocity * DRIVER_SPEED_FRACTION for name in self.joint_names])
        self.writes = 0
        self._time = now
        self._next_write = now

    def update(self, commanded: Sequence[float], now: float) -> Tuple[numpy.ndarray, numpy.ndarray]:
        """The executed positions and velocities at `now`, given what the controllers command now."""
        commanded = numpy.asarray(commanded, dtype=float)
        while self._next_write <= now:
            self._advance(self._next_write)
            if numpy.any(numpy.abs(commanded - self.positions) > DRIVER_JOINT_PRECISION):
                self.sent = commanded.copy()
                self.writes += 1
            self._next_write += 1.0 / DRIVER_RATE
        self._advance(now)
        return self.positions.copy(), self.velocities.copy()

    def _advance(self, t: float) -> None:
        elapsed = t - self._time
        if elapsed <= 0.0:
            return
        step = numpy.clip(self.sent - self.positions, -self.speeds * elapsed, self.speeds * elapsed)
        self.positions += step
        self.velocities = step / elapsed
        self._time = t


def joint_angles_problem(names: Sequence[str], angles: Sequence[float], speed: float,
                         known: Any = JOINTS) -> Optional[str]:
    """Why a setAngles call (names, angles, speed) is invalid (LENGTHS_DIFFER, UNKNOWN_JOINT, NOT_FINITE,
    SPEED_OUT_OF_RANGE), or None when it is valid; `known` holds the joint names the driver moves."""
    if len(names) != len(angles):
        return LENGTHS_DIFFER
    if any(name not in known for name in names):
        return UNKNOWN_JOINT
    if not all(math.isfinite(value) for value in list(angles) + [speed]):
        return NOT_FINITE
    if not 0.0 < speed <= 1.0:
        return SPEED_OUT_OF_RANGE
    return None


class NaoqiDriver:
    """naoqi_driver on ``/joint_angles``: each message is one ALMotion setAngles call, executed at once.

    setAngles is non-blocking: each named joint moves from where it is toward its target (clamped into the joint
    limits; with `relative`, the angle is added to where the joint is) at `speed` times its maximum velocity, and
    stops there.  A later call takes over the joints it names at once; the others keep their own targets.  The
    kinematics are exact (constant speed, then still) and evaluated in closed form at any time, so `state` changes
    nothing.  Time only runs forward: each call's `now` is no earlier than the previous one's."""

    def __init__(self, joint_names: Sequence[str], positions: Sequence[float], now: float) -> None:
        self.joint_names = tuple(joint_names)
        self._index = {name: index for index, name in enumerate(self.joint_names)}
        self._lower = numpy.array([JOINTS[name].lower for name in self.joint_names])
        self._upper = numpy.array([JOINTS[name].upper for name in self.joint_names])
        self._max_velocity = numpy.array([JOINTS[name].max_velocity for name in self.joint_names])
        # Per joint: where its last call found it, when, its target and its speed (rad/s).
        self._origins = numpy.clip(numpy.array(positions, dtype=float), self._lower, self._upper)
        self._since = numpy.full(len(self.joint_names), float(now))
        self._targets = self._origins.copy()
        self._speeds = numpy.zeros(len(self.joint_names))
        self.calls = 0  # setAngles calls executed

    def set_angles(self, names: Sequence[str], angles: Sequence[float], speed: float, now: float,
                   relative: bool = False) -> None:
        """One setAngles call at `now`; ValueError (naming the problem's kind) for an invalid one."""
        problem = joint_angles_problem(names, angles, speed, self._index)
        if problem is not None:
            raise ValueError(problem)
        index = numpy.array([self._index[name] for name in names], dtype=int)
        current = self.state(now)[0][index]
        targets = numpy.array(angles, dtype=float) + (current if relative else 0.0)
        self._origins[index] = current
        self._since[index] = now
        self._targets[index] = numpy.clip(targets, self._lower[index], self._upper[index])
        self._speeds[index] = speed * self._max_velocity[index]
        self.calls += 1

    @property
    def targets(self) -> numpy.ndarray:
        """Every joint's target (joint_names order): where its latest call sends it (where it started: none)."""
        return self._targets.copy()

    def state(self, now: float) -> Tuple[numpy.ndarray, numpy.ndarray]:
        """Positions and velocities of every joint (joint_names order) at `now`."""
        offsets = self._targets - self._origins
        travel = self._speeds * numpy.maximum(now - self._since, 0.0)
        moving = travel < numpy.abs(offsets)
        direction = numpy.sign(offsets)
        # A joint that arrived is exactly at its target, not a rounding error away from it.
        positions = numpy.where(moving, self._origins + direction * travel, self._targets)
        velocities = numpy.where(moving, direction * self._speeds, 0.0)
        return positions, velocities


class SimulatedPepper:
    """All controllers of a platform, the fixed joints, and the base; with `driver` NAOQI_DCM, the joints move as
    the physical robot's driver moves them (`NaoqiDcmDriver`); with NAOQI_DRIVER, as naoqi_driver executes the
    `joint_angles` calls (`NaoqiDriver`); otherwise (IDEAL) as the controllers' hardware reports them
    (`velocity_report`). `control_rate`, `velocity_report`, `goal_time` and `stopped_velocity_tolerance` apply to
    every controller (`SimulatedController`), which judges its goals on its own hardware, the driver or not. The
    joints start in `initial_posture`, except those `initial_positions` (joint name: position) names."""

    def __init__(self, platform: str = "robot", initial_posture: str = "rest", now: float = 0.0,
                 moveto_keep_latest: bool = False, driver: str = IDEAL, control_rate: float = CONTROL_RATE,
                 velocity_report: str = MEASURED, goal_time: float = GOAL_TIME,
                 stopped_velocity_tolerance: float = STOPPED_VELOCITY_TOLERANCE,
                 initial_positions: Optional[Mapping[str, float]] = None) -> None:
        if driver not in DRIVERS:
            raise ValueError("unknown driver {!r} (expected one of: {})".format(driver, ", ".join(DRIVERS)))
        if platform not in PLATFORMS:
            raise ValueError("unknown platform {!r} (expected one of: {})".format(platform, ", ".join(PLATFORMS)))
        self.platform = PLATFORMS[platform]
        self.controllers: Dict[str, SimulatedController] = OrderedDict(
            (key, SimulatedController(CONTROLLER_NAMES[key], CONTROLLER_JOINTS[key],
                                      controller_posture(key, initial_posture, initial_positions), now, control_rate,
                                      velocity_report, goal_time, stopped_velocity_tolerance))
            for key in self.platform.controller_keys)
        # Joints no controller drives (the simulator's hands) stay at their centre; wheels at 0.
        self._fixed = {joint: position
                       for key, part_ in list(PARTS.items()) + [(HEAD_PART.key, HEAD_PART)]
                       if key not in self.controllers
                       for joint, position in zip(part_.joints, part_.centre)}
        self.joint_names: Tuple[str, ...] = tuple(JOINTS) + WHEEL_JOINTS
        self.driver: Any = None  # None (IDEAL), a NaoqiDcmDriver or a NaoqiDriver; it moves the joints, not wheels
        start = self.commanded_state(now).positions[:len(JOINTS)]
        if driver == NAOQI_DCM:
            self.driver = NaoqiDcmDriver(tuple(JOINTS), start, now)
        elif driver == NAOQI_DRIVER:
            # The robot then runs naoqi_driver instead of pepper_dcm: the FollowJointTrajectory controllers still
            # accept and judge goals, but nothing writes their commands to the joints; /joint_angles moves them.
            self.driver = NaoqiDriver(tuple(JOINTS), start, now)
        if self.platform.base_kind == RELATIVE:
            self.base: Any = MoveToBase(now=now, keep_latest=moveto_keep_latest)
        else:
            self.base = VelocityBase(now=now)

    def update(self, now: float) -> List[Tuple[str, GoalOutcome]]:
        """Run every controller's updates due by `now`: the goals that ended, with their controller keys."""
        return [(key, outcome) for key, controller in self.controllers.items() for outcome in controller.update(now)]

    def joint_state(self, now: float) -> JointStateSample:
        """Position and velocity of every joint (JOINTS order, then the wheels): what the robot reports. With the
        robot's driver modelled, what it executes of the controllers' commands."""
        if self.driver is None:
            return self._sample(now, lambda controller: controller.reported_state(now))
        commanded = self.commanded_state(now)
        count = len(JOINTS)
        if isinstance(self.driver, NaoqiDriver):
            positions, velocities = self.driver.state(now)
        else:
            positions, velocities = self.driver.update(commanded.positions[:count], now)
        return JointStateSample(commanded.names, positions.tolist() + commanded.positions[count:],
                                velocities.tolist() + commanded.velocities[count:])

    def joint_angles(self, names: Sequence[str], angles: Sequence[float], speed: float, relative: int,
                     now: float) -> Optional[str]:
        """Execute one /joint_angles message (driver NAOQI_DRIVER only; a nonzero `relative` adds the angles to
        the current ones): None, or the kind of problem for which it was ignored (`joint_angles_problem`)."""
        if not isinstance(self.driver, NaoqiDriver):
            raise RuntimeError("joint_angles needs the {} driver".format(NAOQI_DRIVER))
        problem = joint_angles_problem(names, angles, speed)
        if problem is None:
            self.driver.set_angles(names, angles, speed, now, relative=bool(relative))
        return problem

    def reading_time(self, now: float) -> float:
        """When what `joint_state(now)` reports was read, for its stamp (a joint state broadcaster stamps each message
        with its control update's time): the controllers' last update, as they update together in one control loop;
        `now` where the state is taken at `now` (a driver modelled, or COMMANDED)."""
        controllers = list(self.controllers.values())
        if self.driver is not None or not controllers or controllers[0].velocity_report == COMMANDED:
            return now
        controllers[0].reported_state(now)  # runs the updates due by `now`, as joint_state(now) does
        return controllers[0].last_update.time

    def commanded_state(self, now: float) -> JointStateSample:
        """What the controllers command for every joint (JOINTS order, then the wheels): their desired state."""
        return self._sample(now, lambda controller: controller.state(now))

    def driver_commands(self, now: float) -> JointStateSample:
        """What the joints are commanded (JOINTS order, then the wheels): the controllers' desired state, or with
        NAOQI_DRIVER, whose joints the controllers do not move, each joint's latest setAngles target (with the
        velocity that call gives it)."""
        commanded = self.commanded_state(now)
        if not isinstance(self.driver, NaoqiDriver):
            return commanded
        count = len(JOINTS)
        _, velocities = self.driver.state(now)
        return JointStateSample(commanded.names, self.driver.targets.tolist() + commanded.positions[count:],
                                velocities.tolist() + commanded.velocities[count:])

    def _sample(self, now: float, state_of) -> JointStateSample:
        positions = dict((joint, 0.0) for joint in WHEEL_JOINTS)
        velocities = dict((joint, 0.0) for joint in self.joint_names)
        positions.update(self._fixed)
        for controller in self.controllers.values():
            state = state_of(controller)
            positions.update(zip(controller.joint_names, state.positions.tolist()))
            velocities.update(zip(controller.joint_names, state.velocities.tolist()))
        return JointStateSample(self.joint_names, [positions[joint] for joint in self.joint_names],
                                [velocities[joint] for joint in self.joint_names])

    def base_state(self, now: float) -> BaseState:
        return self.base.state(now)

    def base_command(self, x: float, y: float, angular_z: float, now: float) -> str:
        return self.base.command(x, y, angular_z, now)

    @property
    def limit_violation_count(self) -> int:
        return sum(controller.limit_violation_count for controller in self.controllers.values())


def yaw_quaternion(heading: float) -> Tuple[float, float, float, float]:
    """(x, y, z, w) of a rotation by `heading` about z."""
    return 0.0, 0.0, math.sin(heading / 2.0), math.cos(heading / 2.0)


def fill_state_messages(stamp, joints_stamp, joints: JointStateSample, base: BaseState, joint_state, odometry,
                        commanded: Optional[JointStateSample] = None, commanded_message=None) -> None:
    """Fills one control update's messages, of either ROS (their fields have the same names): `joint_state`
    (sensor_msgs JointState, its names set once), `odometry` (nav_msgs Odometry) and, where a driver is modelled,
    `commanded_message` (a JointState of what the driver commanded). `joints_stamp` dates `joint_state`: when its
    readings were taken (`SimulatedPepper.reading_time`); `stamp` the others."""
    joint_state.header.stamp = joints_stamp
    joint_state.position, joint_state.velocity = joints.positions, joints.velocities
    if commanded is not None:
        commanded_message.header.stamp = stamp
        commanded_message.position, commanded_message.velocity = commanded.positions, commanded.velocities
    odometry.header.stamp = stamp
    orientation = odometry.pose.pose.orientation
    orientation.x, orientation.y, orientation.z, orientation.w = yaw_quaternion(base.heading)
    odometry.twist.twist.angular.z = base.angular_velocity
