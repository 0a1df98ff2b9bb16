"""simulatedPepper on ROS 2: the kinematic Pepper of cssr_system.pepper.simulated_pepper over rclpy.

The same model and behaviour as the ROS 1 node (cssr_system.ros1.simulated_pepper_node, doc/simulated-pepper.md),
on the interfaces ros2_control's joint_trajectory_controller and naoqi_driver2 serve.

  python3 -m cssr_system.ros2.simulated_pepper_node --ros-args -p platform:=simulator
  ros2 run cssr_system simulated_pepper --ros-args -p platform:=simulator

Parameters (declared with these defaults; any other is ignored):
  platform            "robot" (pepper_dcm, hand controllers, cmd_moveto) or "simulator" (pepper, no hands, cmd_vel)
  initial_posture     "rest" (every part at its centre) or "zero"
  initial_positions   "Joint=value, ..." (""): these joints start there instead, as another node may have left them
  moveto_keep_latest  false: cmd_moveto commands arriving while the base turns or settles are dropped; true: the
                      latest of them runs when the base is free
  feedback_rate       Hz of action feedback for active goals (10; 0: none)
  driver              "ideal", "naoqi_dcm" or "naoqi_driver" (/joint_angles moves the joints; goals are still judged)
  control_rate        Hz of the controllers' control loop, whose updates judge the goals (50)
  velocity_report     "measured", "zero" or "commanded": the joint velocity the controllers' hardware reports
  goal_time           s after a trajectory's end allowed to get inside the goal tolerances (0.0)
  stopped_velocity_tolerance  every joint's velocity tolerance at a goal's end (0.01; 0: unchecked)
  allow_nonzero_velocity_at_trajectory_end  joint_trajectory_controller's parameter: false (Jazzy's default) rejects
                      a trajectory whose last point still moves; true (Humble's default) takes it
  result_timeout      s a finished goal stays listed in a controller's status and its result is kept (10, Jazzy's rcl
                      default, which its controllers use; Humble's: 900)
  An invalid value: one line naming it and what was expected, exit status 1.
Serves (every name relative: the node's own namespace applies; <ns> is pepper_dcm or pepper):
  <ns>/<Name>_controller/follow_joint_trajectory  control_msgs/action/FollowJointTrajectory. As ros2_control's
                      joint_trajectory_controller (Jazzy and later): a goal that fails its checks
                      (pepper/ros2_trajectory_validation.py: its message is logged) or that the model would refuse
                      (joints, points) is rejected; an accepted one succeeds or aborts with the model's error code
                      and string; a new goal or a joint_trajectory message aborts the running goal (INVALID_GOAL,
                      "preempted"); a cancel stops the joints where they are and the goal ends canceled with an
                      empty result
  <ns>/<Name>_controller/joint_trajectory  trajectory_msgs/msg/JointTrajectory, obeyed like a goal, no result
  <ns>/cmd_moveto or <ns>/cmd_vel  geometry_msgs/msg/Twist
  joint_angles        naoqi_bridge_msgs/msg/JointAnglesWithSpeed (with driver naoqi_driver)
Publishes:
  joint_states        sensor_msgs/msg/JointState, 50 Hz, every joint and the wheels
  <ns>/odom           nav_msgs/msg/Odometry, 50 Hz, the base's heading (frame odom, child base_footprint)
  ~/limit_violations  std_msgs/msg/UInt32, transient local: goal point values beyond a joint limit so far
  ~/commanded_joint_states  sensor_msgs/msg/JointState, 50 Hz, with a driver other than ideal: what is commanded
  <ns>/<Name>_controller/controller_state  control_msgs/msg/JointTrajectoryControllerState, 50 Hz while someone
                      subscribes: each controller's latest update, its desired state as `reference`
Stamps and the controllers' time follow the node's clock (ROS time: /clock with use_sim_time).
SIGINT or SIGTERM: goals still running abort, the node ends with status 0.
"""
import functools
import math
import sys
import threading
import time
from typing import Any, Dict, List, NamedTuple, Optional, Sequence, Tuple

from control_msgs.action import FollowJointTrajectory
from control_msgs.msg import JointTrajectoryControllerState
from geometry_msgs.msg import Twist
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.time import Time
from sensor_msgs.msg import JointState
from std_msgs.msg import UInt32
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from cssr_system.animate_behaviour.contract import JOINT_STATES_TOPIC
from cssr_system.pepper.joint_table import ACTION_NAME, JOINTS, WHEEL_JOINTS
from cssr_system.pepper.ros2_trajectory_validation import JAZZY, trajectory_problem
from cssr_system.pepper.simulated_pepper import (CONTROL_RATE, DRIVERS, GOAL_TIME, IDEAL, INVALID_GOAL, MEASURED,
                                                 NAOQI_DRIVER, PLATFORMS, POSTURES, STOPPED_VELOCITY_TOLERANCE,
                                                 SUCCESSFUL, GoalOutcome, GoalPoint, GoalTolerances, SimulatedPepper,
                                                 action_namespace, base_topic, check_loop_settings, odometry_topic,
                                                 describe_violations, fill_state_messages, parse_initial_positions)
from cssr_system.ros2.program import on_signals, run_node

NODE_NAME = "simulatedPepper"
UPDATE_RATE = 50.0  # Hz: stepping the model (its control loop catches up), /joint_states and odometry
# s a finished goal stays in a controller's status and keeps its result: rcl's default from Iron on, which
# ros2_control's controllers use (rclpy's own server default on Jazzy is 900, Humble's rcl default).
RESULT_TIMEOUT = 10.0
JOINT_ANGLES_TOPIC = "joint_angles"  # naoqi_driver2's setAngles topic, in the namespace
TRAJECTORY_TOPIC_NAME = "joint_trajectory"  # ROS 2 joint_trajectory_controller's topic (ROS 1's is "command")
STATE_TOPIC_NAME = "controller_state"  # its state at each update (ROS 1's is "state", another message)
# What ros2_controllers' joint_trajectory_controller (Jazzy, Kilted, Rolling) gives a goal that a new goal replaces.
PREEMPTED_BY_GOAL = "Current goal preempted by new incoming action."
PREEMPTED_BY_TOPIC = "Current goal preempted by a trajectory on {}."
SHUT_DOWN = "the simulated Pepper shut down"
CANCEL_STATE_WAIT = 1.0  # s: the action server marks a goal canceling right after our cancel callback accepts

SUCCEEDED, ABORTED, CANCELED = "succeeded", "aborted", "canceled"

# name, default: every parameter, declared with dynamic typing so a wrong type gets our message, not rclpy's.
PARAMETERS: Tuple[Tuple[str, Any], ...] = (
    ("platform", "robot"), ("initial_posture", "rest"), ("moveto_keep_latest", False), ("feedback_rate", 10.0),
    ("driver", IDEAL), ("control_rate", CONTROL_RATE), ("velocity_report", MEASURED), ("goal_time", GOAL_TIME),
    ("stopped_velocity_tolerance", STOPPED_VELOCITY_TOLERANCE),
    ("allow_nonzero_velocity_at_trajectory_end", JAZZY.allow_nonzero_velocity_at_trajectory_end),
    ("result_timeout", RESULT_TIMEOUT), ("initial_positions", ""))
CHOICES = (("platform", tuple(PLATFORMS)), ("initial_posture", POSTURES), ("driver", DRIVERS))
LOOP_SETTINGS = ("control_rate", "velocity_report", "goal_time", "stopped_velocity_tolerance")


class Settings(NamedTuple):
    platform: str
    initial_posture: str
    moveto_keep_latest: bool
    feedback_rate: float
    driver: str
    control_rate: float
    velocity_report: str
    goal_time: float
    stopped_velocity_tolerance: float
    allow_nonzero_velocity_at_trajectory_end: bool
    result_timeout: float
    initial_positions: Dict[str, float]


def is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def check_settings(values: Dict[str, Any]) -> Settings:
    """The node's settings from its parameter values; ValueError naming the first bad one and what it must be."""
    for name, choices in CHOICES:
        if values[name] not in choices:
            raise ValueError("{} must be one of {} (got {!r})".format(name, ", ".join(choices), values[name]))
    for name in ("moveto_keep_latest", "allow_nonzero_velocity_at_trajectory_end"):
        if not isinstance(values[name], bool):
            raise ValueError("{} must be true or false (got {!r})".format(name, values[name]))
    if not is_number(values["feedback_rate"]) or values["feedback_rate"] < 0:
        raise ValueError("feedback_rate must be a finite number >= 0 (got {!r})".format(values["feedback_rate"]))
    if not is_number(values["result_timeout"]) or values["result_timeout"] <= 0:
        raise ValueError("result_timeout must be a finite number > 0 (got {!r})".format(values["result_timeout"]))
    check_loop_settings(**{name: values[name] for name in LOOP_SETTINGS})
    if not isinstance(values["initial_positions"], str):
        raise ValueError("initial_positions must be a string (got {!r})".format(values["initial_positions"]))
    converted = {name: float(value) if is_number(value) else value for name, value in values.items()}
    converted["initial_positions"] = parse_initial_positions(values["initial_positions"])
    return Settings(**converted)


def read_settings(node: Node) -> Settings:
    """Declare the node's parameters and check their values (ValueError: `check_settings`)."""
    dynamic = ParameterDescriptor(dynamic_typing=True)
    values = {name: node.declare_parameter(name, default, dynamic).value for name, default in PARAMETERS}
    return check_settings(values)


def trajectory_topic(platform, key: str) -> str:
    """`<ns>/<Name>_controller/joint_trajectory`: the controller that serves the action, its ROS 2 topic."""
    return action_namespace(platform, key)[:-len(ACTION_NAME)] + TRAJECTORY_TOPIC_NAME


def state_topic(platform, key: str) -> str:
    """`<ns>/<Name>_controller/controller_state`: the controller's state topic."""
    return action_namespace(platform, key)[:-len(ACTION_NAME)] + STATE_TOPIC_NAME


def seconds(duration) -> float:
    """A builtin_interfaces Duration (or Time) in seconds."""
    return duration.sec + duration.nanosec * 1e-9


def goal_points(trajectory: JointTrajectory) -> List[GoalPoint]:
    return [GoalPoint(seconds(point.time_from_start), list(point.positions), list(point.velocities),
                      list(point.accelerations), list(point.effort))
            for point in trajectory.points]


def goal_uuid(goal_handle) -> bytes:
    return bytes(goal_handle.goal_id.uuid)


class AcceptedGoal:
    """An accepted goal, the model's token for it: its handle, and its verdict once one is reached (the first one
    stands). The action server's execute callback waits for the verdict, then ends the goal with it."""

    def __init__(self, goal_handle) -> None:
        self.handle = goal_handle
        self.uuid = goal_uuid(goal_handle)
        self.status: Optional[str] = None
        self.result = FollowJointTrajectory.Result()
        self._decided = threading.Event()
        self._lock = threading.Lock()

    def decide(self, status: str, error_code: int = SUCCESSFUL, error_string: str = "") -> None:
        with self._lock:
            if self._decided.is_set():
                return
            self.status = status
            self.result = FollowJointTrajectory.Result(error_code=error_code, error_string=error_string)
            self._decided.set()

    def wait(self) -> Tuple[str, Any]:
        self._decided.wait()
        return self.status, self.result


class SimulatedPepperNode:
    """The model served on a node: action servers, topics, and a 50 Hz update of the model and the states."""

    def __init__(self, node: Node, settings: Settings) -> None:
        self.node = node
        self.logger = node.get_logger()
        self._clock = node.get_clock()
        # The model's clock counts from start-up: small numbers keep the splines' arithmetic exact.
        self._epoch_ns = self._clock.now().nanoseconds
        self._lock = threading.Lock()  # guards the model, the goals and _epoch_ns; goal handles are used outside it
        self.model = SimulatedPepper(settings.platform, settings.initial_posture, self._now(),
                                     settings.moveto_keep_latest, settings.driver, settings.control_rate,
                                     settings.velocity_report, settings.goal_time, settings.stopped_velocity_tolerance,
                                     settings.initial_positions)
        self.platform = self.model.platform
        self.rules = JAZZY._replace(
            allow_nonzero_velocity_at_trajectory_end=settings.allow_nonzero_velocity_at_trajectory_end)
        self._feedback_period = 1.0 / settings.feedback_rate if settings.feedback_rate > 0 else None
        self._result_timeout = settings.result_timeout
        self._next_feedback = 0.0
        self._goals: Dict[bytes, AcceptedGoal] = {}  # accepted, not yet ended, by goal id
        self._canceled_early: set = set()  # ids of goals canceled before the model got them
        self._closing = False
        self._reported_violations = -1
        self._violation_lock = threading.Lock()
        self._joint_angle_problems: set = set()  # kinds of invalid /joint_angles messages already warned about
        self._create_publishers()
        self._publish_violations()
        # Each controller takes its goals, cancels and command trajectories one at a time, in the order they came, as
        # a controller does: side by side, a later goal could be accepted first and then be replaced by the earlier
        # one. Controllers run beside each other; each execute callback waits for its goal's verdict on a thread of
        # its own (rclpy runs it as a task, outside the groups); the update timer has its own group.
        groups = {key: MutuallyExclusiveCallbackGroup() for key in self.model.controllers}
        self.servers = {key: self._action_server(key, groups[key]) for key in self.model.controllers}
        self.subscriptions = [
            node.create_subscription(JointTrajectory, trajectory_topic(self.platform, key),
                                     functools.partial(self.on_trajectory, key), 10, callback_group=groups[key])
            for key in self.model.controllers]
        self.subscriptions.append(node.create_subscription(Twist, base_topic(self.platform), self.on_twist, 10,
                                                           callback_group=MutuallyExclusiveCallbackGroup()))
        if settings.driver == NAOQI_DRIVER:
            self.subscriptions.append(node.create_subscription(JointAnglesWithSpeed, JOINT_ANGLES_TOPIC,
                                                               self.on_joint_angles, 10,
                                                               callback_group=MutuallyExclusiveCallbackGroup()))
        self.timer = node.create_timer(1.0 / UPDATE_RATE, self.on_tick,
                                       callback_group=MutuallyExclusiveCallbackGroup())
        self.logger.info("platform {}, namespace {}, controllers {}, base {} ({}); control loop {:g} Hz, velocity "
                         "report {}, goal time {:g} s, stopped velocity tolerance {:g}, driver {}, "
                         "allow_nonzero_velocity_at_trajectory_end {}, result timeout {:g} s".format(
                             self.platform.name, self.platform.namespace,
                             ", ".join(controller.name for controller in self.model.controllers.values()),
                             base_topic(self.platform), self.platform.base_kind, settings.control_rate,
                             settings.velocity_report, settings.goal_time, settings.stopped_velocity_tolerance,
                             settings.driver, str(settings.allow_nonzero_velocity_at_trajectory_end).lower(),
                             settings.result_timeout))

    def _create_publishers(self) -> None:
        node = self.node
        self.joint_state_publisher = node.create_publisher(JointState, JOINT_STATES_TOPIC, 10)
        # With the robot's driver modelled, /joint_states is what the driver executes; this is what was commanded.
        self.commanded_publisher = node.create_publisher(JointState, "~/commanded_joint_states", 10)
        self.odometry_publisher = node.create_publisher(Odometry, odometry_topic(self.platform), 10)
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)  # ROS 2's latching
        self.violation_publisher = node.create_publisher(UInt32, "~/limit_violations", latched)
        self._joint_state = JointState(name=list(self.model.joint_names))
        self._commanded = JointState(name=list(JOINTS) + list(WHEEL_JOINTS))
        self._odometry = Odometry()
        self._odometry.header.frame_id = "odom"
        self._odometry.child_frame_id = "base_footprint"
        self.state_publishers = {key: node.create_publisher(JointTrajectoryControllerState,
                                                            state_topic(self.platform, key), 10)
                                 for key in self.model.controllers}

    def _action_server(self, key: str, callback_group) -> ActionServer:
        # Resolved as the node resolves its controllers' names, remapping included: Jazzy's rcl leaves a remapping
        # of a whole action name unapplied to an action server (Kilted's applies it), and this moves it on both.
        name = self.node.resolve_topic_name(action_namespace(self.platform, key))
        return ActionServer(self.node, FollowJointTrajectory, name,
                            execute_callback=self.execute,
                            goal_callback=functools.partial(self.on_goal_request, key),
                            handle_accepted_callback=functools.partial(self.on_accepted, key),
                            cancel_callback=functools.partial(self.on_cancel, key),
                            callback_group=callback_group, result_timeout=self._result_timeout)

    # -- time (the caller holds self._lock) ------------------------------------------------------
    def _now(self) -> float:
        now = self._clock.now().nanoseconds
        if self._epoch_ns == 0 and now > 0:
            # A simulated clock that was silent at start-up (it reads 0) has started: the controllers' time counts
            # from now, as a controller's update loop counts its uptime, so goals accepted meanwhile start now.
            self._epoch_ns = now
        return (now - self._epoch_ns) * 1e-9 if self._epoch_ns else 0.0

    def _stamp(self, model_time: float):
        """A message stamp for a time of the model."""
        return Time(nanoseconds=self._epoch_ns + int(round(model_time * 1e9)),
                    clock_type=self._clock.clock_type).to_msg()

    def _model_stamp(self, stamp) -> Optional[float]:
        """A trajectory's header stamp on the model's clock; None for a zero stamp (start now)."""
        if stamp.sec == 0 and stamp.nanosec == 0:
            return None
        return (stamp.sec * 1000000000 + stamp.nanosec - self._epoch_ns) * 1e-9

    # -- actions -------------------------------------------------------------------------------
    def _controller_problem(self, controller, trajectory: JointTrajectory, points) -> str:
        """joint_trajectory_controller's line for a trajectory it refuses, or "" (call with the lock held)."""
        return trajectory_problem(self.rules, controller.joint_names, trajectory.joint_names, points,
                                  self._model_stamp(trajectory.header.stamp), self._now())

    def on_goal_request(self, key: str, goal) -> GoalResponse:
        """As joint_trajectory_controller: a trajectory it cannot follow is rejected (no result)."""
        controller = self.model.controllers[key]
        points = goal_points(goal.trajectory)
        with self._lock:
            problem = self._controller_problem(controller, goal.trajectory, points)
            error_code, error_string = controller.validate(goal.trajectory.joint_names, points)
            closing = self._closing
        if problem:
            self.logger.error("{} rejected a goal: {}".format(controller.name, problem))
            return GoalResponse.REJECT
        if error_code == SUCCESSFUL and not closing:
            return GoalResponse.ACCEPT
        self.logger.warning("{} rejected a goal (error code {}): {}".format(
            controller.name, error_code, error_string or SHUT_DOWN))
        return GoalResponse.REJECT

    def on_accepted(self, key: str, goal_handle) -> None:
        """Give the model the goal (it replaces the running one), then start its execute callback."""
        controller = self.model.controllers[key]
        goal = AcceptedGoal(goal_handle)
        request = goal_handle.request
        trajectory = request.trajectory
        tolerances = GoalTolerances(request.path_tolerance, request.goal_tolerance,
                                    seconds(request.goal_time_tolerance))
        acceptance, ended = None, []
        with self._lock:
            self._goals[goal.uuid] = goal
            if goal.uuid in self._canceled_early:
                self._canceled_early.discard(goal.uuid)
                goal.decide(CANCELED)
            elif self._closing:
                goal.decide(ABORTED, INVALID_GOAL, SHUT_DOWN)
            else:
                now = self._now()
                ended = controller.update(now)  # the control loop's updates due before this goal came
                acceptance = controller.submit(goal, trajectory.joint_names, goal_points(trajectory), now,
                                               self._model_stamp(trajectory.header.stamp), tolerances)
        self._deliver(controller.name, ended)
        if acceptance is not None:
            self._settle_acceptance(controller.name, goal, acceptance)
        goal_handle.execute()

    def _settle_acceptance(self, controller_name: str, goal: AcceptedGoal, acceptance) -> None:
        if not acceptance.accepted:
            # Valid when requested, stale by now (its points lie before the start): it ends at once.
            self.logger.warning("{} aborted a goal (error code {}): {}".format(
                controller_name, acceptance.error_code, acceptance.error_string))
            goal.decide(ABORTED, acceptance.error_code, acceptance.error_string)
            return
        if acceptance.preempted_goal is not None:
            acceptance.preempted_goal.decide(ABORTED, INVALID_GOAL, PREEMPTED_BY_GOAL)
        self.logger.debug("{} accepted a goal{}".format(
            controller_name, ", preempting the active one" if acceptance.preempted_goal is not None else ""))
        if acceptance.limit_violations:
            self._report_violations(controller_name, acceptance.limit_violations)

    def execute(self, goal_handle):
        """The goal's execute callback: wait for its verdict, end the goal with it, return its result."""
        goal = self._goals[goal_uuid(goal_handle)]  # registered by on_accepted before it called execute()
        status, result = goal.wait()
        try:
            if status == CANCELED and not wait_until_canceling(goal_handle):
                status = ABORTED  # not expected: the server never marked it canceling
            {SUCCEEDED: goal_handle.succeed, ABORTED: goal_handle.abort, CANCELED: goal_handle.canceled}[status]()
        finally:
            with self._lock:
                self._goals.pop(goal.uuid, None)
        return result

    def on_cancel(self, key: str, goal_handle) -> CancelResponse:
        """As joint_trajectory_controller: the running goal stops where it is and ends canceled."""
        controller = self.model.controllers[key]
        uuid = goal_uuid(goal_handle)
        with self._lock:
            goal = self._goals.get(uuid)
            if goal is None and not goal_handle.is_active:
                return CancelResponse.REJECT  # it has just ended
            if goal is None:  # accepted, not yet given to the model: on_accepted ends it canceled
                self._canceled_early.add(uuid)
                return CancelResponse.ACCEPT
            now = self._now()
            ended = controller.update(now)
            stopped = controller.cancel(goal, now)
        self._deliver(controller.name, ended)
        if not stopped:
            return CancelResponse.REJECT  # it ended before the cancel came: its verdict stands
        goal.decide(CANCELED)
        self.logger.debug("{} goal canceled, holding".format(controller.name))
        return CancelResponse.ACCEPT

    def _deliver(self, controller_name: str, outcomes: Sequence[GoalOutcome]) -> None:
        """The verdicts of goals that ended at the control loop's updates."""
        for outcome in outcomes:
            if outcome.error_code == SUCCESSFUL:
                outcome.goal.decide(SUCCEEDED, SUCCESSFUL, outcome.error_string)
                continue
            self.logger.info("{} aborted a goal (error code {}): {}".format(controller_name, outcome.error_code,
                                                                            outcome.error_string))
            outcome.goal.decide(ABORTED, outcome.error_code, outcome.error_string)

    def _report_violations(self, controller_name: str, violations) -> None:
        self.logger.warning("{} goal beyond the joint limits, executed at the limits: {}".format(
            controller_name, describe_violations(violations)))
        self._publish_violations()

    def _publish_violations(self) -> None:
        with self._violation_lock:  # goals of different controllers arrive on different threads
            with self._lock:
                count = self.model.limit_violation_count
            if count != self._reported_violations:
                self._reported_violations = count
                self.violation_publisher.publish(UInt32(data=count))

    # -- topics ----------------------------------------------------------------------------------
    def on_trajectory(self, key: str, trajectory: JointTrajectory) -> None:
        """A controller's joint_trajectory topic: obeyed like a goal, without a result."""
        controller = self.model.controllers[key]
        points = goal_points(trajectory)
        with self._lock:
            problem = self._controller_problem(controller, trajectory, points)
            now = self._now()
            ended = controller.update(now)
            acceptance = None if problem else controller.command(trajectory.joint_names, points, now,
                                                                 self._model_stamp(trajectory.header.stamp))
        self._deliver(controller.name, ended)
        if problem:
            self.logger.error("{} ignored a {} message: {}".format(controller.name, TRAJECTORY_TOPIC_NAME, problem))
            return
        if not acceptance.accepted:
            self.logger.warning("{} ignored a {} message: {}".format(controller.name, TRAJECTORY_TOPIC_NAME,
                                                                     acceptance.error_string))
            return
        if acceptance.preempted_goal is not None:
            acceptance.preempted_goal.decide(ABORTED, INVALID_GOAL,
                                             PREEMPTED_BY_TOPIC.format(trajectory_topic(self.platform, key)))
        if acceptance.limit_violations:
            self._report_violations(controller.name, acceptance.limit_violations)

    def on_twist(self, message: Twist) -> None:
        with self._lock:
            reply = self.model.base_command(message.linear.x, message.linear.y, message.angular.z, self._now())
        if message.linear.x or message.linear.y:
            self.logger.warning("linear.x/y of {} are not simulated (the base only turns)".format(
                base_topic(self.platform)), once=True)
        if reply == "invalid":
            self.logger.warning("ignored a {} command that is not finite".format(base_topic(self.platform)))
        else:
            self.logger.debug("{} angular.z {:.4f}: {}".format(base_topic(self.platform), message.angular.z, reply))

    def on_joint_angles(self, message: JointAnglesWithSpeed) -> None:
        with self._lock:
            problem = self.model.joint_angles(list(message.joint_names), list(message.joint_angles), message.speed,
                                              message.relative, self._now())
        # A sender streams at 10 Hz or more: one line per kind of problem, not one per message.
        if problem is None or problem in self._joint_angle_problems:
            return
        self._joint_angle_problems.add(problem)
        self.logger.warning("ignored a {} message ({}): joints {}, angles {}, speed {}; further messages with this "
                            "problem are ignored silently".format(JOINT_ANGLES_TOPIC, problem,
                                                                  list(message.joint_names),
                                                                  list(message.joint_angles), message.speed))

    # -- update loop -----------------------------------------------------------------------------
    def on_tick(self) -> None:
        with self._lock:
            if self._closing:
                return  # closed: no more updates
            now = self._now()
            ended = self.model.update(now)
            joints = self.model.joint_state(now)
            read_at = self.model.reading_time(now)
            base = self.model.base_state(now)
            commanded = self.model.driver_commands(now) if self.model.driver is not None else None
            stamp = self._stamp(now)
        for key, outcome in ended:
            self._deliver(self.model.controllers[key].name, [outcome])
        fill_state_messages(stamp, self._stamp(read_at), joints, base, self._joint_state, self._odometry, commanded,
                            self._commanded)
        self.joint_state_publisher.publish(self._joint_state)
        if commanded is not None:
            self.commanded_publisher.publish(self._commanded)
        self.odometry_publisher.publish(self._odometry)
        self._publish_controller_states()
        if self._feedback_period is not None and now >= self._next_feedback:
            self._next_feedback = now + self._feedback_period
            self._publish_feedback()

    def _publish_controller_states(self) -> None:
        """Each controller's last update, as joint_trajectory_controller publishes it at each of its updates; only
        while someone listens (a recorder), so the other runs pay nothing for it."""
        for key, controller in self.model.controllers.items():
            publisher = self.state_publishers[key]
            if publisher.get_subscription_count() == 0:
                continue
            with self._lock:
                update = controller.last_update
                stamp = self._stamp(update.time)
            message = JointTrajectoryControllerState(
                joint_names=list(controller.joint_names), speed_scaling_factor=1.0,
                **{name: JointTrajectoryPoint(**point) for name, point in update.state_points().items()})
            message.header.stamp = stamp
            publisher.publish(message)

    def _publish_feedback(self) -> None:
        for controller in self.model.controllers.values():
            with self._lock:
                goal, update = controller.active_goal, controller.last_update
                stamp = self._stamp(update.time)
            if goal is None:
                continue
            feedback = FollowJointTrajectory.Feedback(  # as the controller's: its last update
                joint_names=list(controller.joint_names),
                **{name: JointTrajectoryPoint(**point) for name, point in update.feedback_points().items()})
            feedback.header.stamp = stamp
            goal.handle.publish_feedback(feedback)

    def close(self) -> None:
        """Stop updating and end every goal still running (aborted), so no execute callback keeps waiting. The update
        timer is not cancelled: cancelled from this thread while the executor takes it, rcl's timer call fails in the
        executor ("timer is canceled", a traceback at SIGINT); once closed, each update returns at once."""
        with self._lock:
            self._closing = True
            goals = list(self._goals.values())
        for goal in goals:
            goal.decide(ABORTED, INVALID_GOAL, SHUT_DOWN)

    def wait_for_goals(self, timeout: float) -> bool:
        """Whether every goal's execute callback ended (within `timeout`)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self._lock:
                if not self._goals:
                    return True
            time.sleep(0.01)
        return False


def wait_until_canceling(goal_handle, timeout: float = CANCEL_STATE_WAIT) -> bool:
    """Whether the goal is (or within `timeout` becomes) canceling, the only state a goal may end canceled from."""
    deadline = time.monotonic() + timeout
    while not goal_handle.is_cancel_requested:
        if time.monotonic() > deadline or not goal_handle.is_active:
            return False
        time.sleep(0.001)
    return True


def serve(node: Node, stop: threading.Event) -> int:
    """Run the simulated Pepper on `node` until `stop` is set: 0, or 1 after a line naming a bad parameter."""
    try:
        settings = read_settings(node)
    except ValueError as error:
        node.get_logger().fatal("parameter {}".format(error))
        return 1
    pepper = SimulatedPepperNode(node, settings)
    # A thread per controller for its waiting execute callback, and as many for everything else.
    executor = MultiThreadedExecutor(num_threads=2 * len(pepper.model.controllers) + 2)
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, name="executor", daemon=True)
    spinner.start()
    while spinner.is_alive() and not stop.wait(0.2):
        pass
    failed = not spinner.is_alive()
    pepper.close()
    pepper.wait_for_goals(timeout=2.0)
    time.sleep(0.1)  # the executor still answers the clients waiting for those goals' results
    executor.shutdown(timeout_sec=5.0)
    spinner.join(timeout=5.0)
    return 1 if failed else 0


def main(args: Optional[List[str]] = None) -> int:
    stop = threading.Event()
    on_signals(lambda _name: stop.set())  # the goals still running end before the context goes away
    return run_node(NODE_NAME, args, lambda node: serve(node, stop))


if __name__ == "__main__":
    sys.exit(main())
