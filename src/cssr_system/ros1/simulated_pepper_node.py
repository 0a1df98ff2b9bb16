"""simulatedPepper: a kinematic Pepper on the ROS interfaces of the robot or of the Gazebo simulator.

The model (controllers, base) is cssr_system.pepper.simulated_pepper; this node only carries it over ROS.

Parameters (private):
  ~platform            "robot" (default: pepper_dcm, hand controllers, cmd_moveto) or "simulator"
                       (pepper, no hand controllers, cmd_vel)
  ~initial_posture     "rest" (default: every part at its centre, head 0) or "zero"
  ~initial_positions   "Joint=value, ..." (default ""): these joints start there instead, as another node may have
                       left them (clamped into their limits)
  ~moveto_keep_latest  false (default): cmd_moveto commands arriving while the base turns or settles are
                       dropped; true: the latest of them runs when the base is free (a queue of one)
  ~feedback_rate       Hz of action feedback for active goals (default 10; 0: none): the last control update's
                       desired and reported state and their difference, in the controller's joint order
  ~driver              "ideal" (default: the joints move exactly as the controllers command), "naoqi_dcm" (as the
                       physical robot's driver moves them: 12 Hz writes, 0.09 rad dead band, 20 % speed) or
                       "naoqi_driver" (the robot runs naoqi_driver: /joint_angles messages move the joints, each
                       executed at once as ALMotion setAngles; the controllers still accept and judge goals, but
                       their commands move nothing)
  ~control_rate        Hz of the controllers' control loop, whose updates judge the goals (default 50; the robot's
                       driver runs its controllers at 12)
  ~velocity_report     the joint velocity the controllers' hardware reports: "measured" (default: the change of the
                       reported position over one control period, as Gazebo), "zero" (as the robot's driver) or
                       "commanded" (position and velocity exactly as desired: no tracking error, every goal succeeds)
  ~goal_time           s after a trajectory's end allowed to get inside the goal tolerances (default 0.0), unless
                       the goal sets goal_time_tolerance
  ~stopped_velocity_tolerance  velocity tolerance of every joint at the end of a goal (default 0.01; 0: unchecked),
                       unless the goal sets its own goal_tolerance
  Goals are judged as joint_trajectory_controller judges them (cssr_system.pepper.simulated_pepper): they succeed,
  or abort with PATH_TOLERANCE_VIOLATED or GOAL_TOLERANCE_VIOLATED.
Serves (every name relative: the node's own namespace applies, README "Several robots"; <ns> is pepper_dcm
or pepper):
  <ns>/<Name>_controller/follow_joint_trajectory   control_msgs/FollowJointTrajectory (ActionServer)
  <ns>/<Name>_controller/command                   trajectory_msgs/JointTrajectory (subscribed, obeyed like a goal)
  <ns>/cmd_moveto or <ns>/cmd_vel                  geometry_msgs/Twist (subscribed)
  joint_angles         naoqi_bridge_msgs/JointAnglesWithSpeed (subscribed with ~driver naoqi_driver); a message
                       whose lengths differ, that names an unknown joint, has a speed outside (0, 1] or a value that
                       is not finite is ignored, with one warning for the first message of each kind
Publishes:
  joint_states         sensor_msgs/JointState, 50 Hz, every joint and the wheels, as the controllers' hardware reports
                       them at their latest update (~velocity_report; with "commanded", the desired state now;
                       with ~driver naoqi_dcm or naoqi_driver, what the driver executes)
  <ns>/odom            nav_msgs/Odometry, 50 Hz, base heading (frame odom, child base_footprint)
  ~limit_violations    std_msgs/UInt32, latched: goal point values beyond a joint limit so far
  ~commanded_joint_states  sensor_msgs/JointState, 50 Hz, with ~driver naoqi_dcm: what the controllers
                       command; with naoqi_driver: each joint's latest /joint_angles target
"""
import functools
import threading
from typing import Any, Dict, Optional

import actionlib
import rospy
from control_msgs.msg import (FollowJointTrajectoryAction, FollowJointTrajectoryFeedback,
                              FollowJointTrajectoryResult)
from geometry_msgs.msg import Twist
from naoqi_bridge_msgs.msg import JointAnglesWithSpeed
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from std_msgs.msg import UInt32
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from cssr_system.animate_behaviour.contract import JOINT_STATES_TOPIC
from cssr_system.pepper.joint_table import command_topic, JOINTS, WHEEL_JOINTS
from cssr_system.pepper.simulated_pepper import (CONTROL_RATE, GOAL_TIME, MEASURED, PLATFORMS, POSTURES,
                                                 STOPPED_VELOCITY_TOLERANCE, SUCCESSFUL, GoalPoint, GoalTolerances,
                                                 SimulatedPepper, action_namespace, base_topic,
                                                 check_loop_settings, describe_violations, fill_state_messages,
                                                 odometry_topic, parse_initial_positions, DRIVERS, IDEAL,
                                                 NAOQI_DRIVER)
from cssr_system.ros1.rospy_compat import quiet_at_shutdown

NODE_NAME = "simulatedPepper"
UPDATE_RATE = 50.0  # Hz: stepping the model (its control loop catches up), /joint_states and odometry
JOINT_ANGLES_TOPIC = "joint_angles"  # naoqi_driver's setAngles topic, in the namespace


class SimulatedPepperNode:
    def __init__(self, platform: str, initial_posture: str, moveto_keep_latest: bool, feedback_rate: float,
                 driver: str = IDEAL, control_rate: float = CONTROL_RATE, velocity_report: str = MEASURED,
                 goal_time: float = GOAL_TIME, stopped_velocity_tolerance: float = STOPPED_VELOCITY_TOLERANCE,
                 initial_positions: Optional[Dict[str, float]] = None):
        # The model's clock starts at 0 at start-up: small numbers keep the splines' arithmetic exact.
        self._epoch = rospy.get_time()
        # Guards the model. Lock order: an action server's own lock first (actionlib holds it around our
        # callbacks), then this one; never the reverse, so goal handles are used without this lock.
        self._lock = threading.Lock()
        self.model = SimulatedPepper(platform, initial_posture, self._now(), moveto_keep_latest, driver, control_rate,
                                     velocity_report, goal_time, stopped_velocity_tolerance, initial_positions)
        self.platform = self.model.platform
        self._feedback_period = 1.0 / feedback_rate if feedback_rate > 0 else None
        self._next_feedback = 0.0
        self._reported_violations = -1
        self._violation_lock = threading.Lock()

        self.joint_state_publisher = rospy.Publisher(JOINT_STATES_TOPIC, JointState, queue_size=10)
        # With the robot's driver modelled, /joint_states is what the driver executes; this is what was commanded.
        self.commanded_publisher = rospy.Publisher("~commanded_joint_states", JointState, queue_size=10)
        self._commanded = JointState(name=list(JOINTS) + list(WHEEL_JOINTS))
        self.odometry_publisher = rospy.Publisher(odometry_topic(self.platform), Odometry, queue_size=10)
        self.violation_publisher = rospy.Publisher("~limit_violations", UInt32, queue_size=1, latch=True)
        self._publish_violations()
        self.servers = {}
        for key in self.model.controllers:
            self.servers[key] = actionlib.ActionServer(
                action_namespace(self.platform, key), FollowJointTrajectoryAction,
                goal_cb=functools.partial(self.on_goal, key), cancel_cb=functools.partial(self.on_cancel, key),
                auto_start=False)
        for server in self.servers.values():
            # actionlib's status timer may fire while rospy closes the topics at shutdown: quiet, as on_tick is.
            server.publish_status_async = functools.partial(quiet_at_shutdown, server.publish_status_async)
            server.start()
        # Each controller also obeys trajectories on its command topic, as joint_trajectory_controller does.
        self.command_subscribers = [
            rospy.Subscriber(command_topic(action_namespace(self.platform, key)), JointTrajectory,
                             functools.partial(self.on_command, key), queue_size=10)
            for key in self.model.controllers]
        self.base_subscriber = rospy.Subscriber(base_topic(self.platform), Twist, self.on_twist, queue_size=10)
        self._joint_angle_problems = set()  # kinds of invalid /joint_angles messages already warned about
        self.joint_angles_subscriber = None
        if driver == NAOQI_DRIVER:
            self.joint_angles_subscriber = rospy.Subscriber(JOINT_ANGLES_TOPIC, JointAnglesWithSpeed,
                                                            self.on_joint_angles, queue_size=10)
        self._joint_state = JointState(name=list(self.model.joint_names))
        self._odometry = Odometry()
        self._odometry.header.frame_id = "odom"
        self._odometry.child_frame_id = "base_footprint"
        self.timer = rospy.Timer(rospy.Duration(1.0 / UPDATE_RATE), self.on_tick)
        rospy.loginfo("%s: platform %s, namespace %s, controllers %s, base %s (%s); control loop %g Hz, velocity "
                      "report %s, goal time %g s, stopped velocity tolerance %g", NODE_NAME, self.platform.name,
                      self.platform.namespace,
                      ", ".join(controller.name for controller in self.model.controllers.values()),
                      base_topic(self.platform), self.platform.base_kind, control_rate, velocity_report, goal_time,
                      stopped_velocity_tolerance)

    def _now(self) -> float:
        now = rospy.get_time()
        if self._epoch == 0.0 and now > 0.0:
            # A simulated clock that was silent at start-up (it reads 0) has started: the controllers' time counts
            # from now, as a controller's update loop counts its uptime, so goals accepted meanwhile start now.
            self._epoch = now
        return now - self._epoch if self._epoch else 0.0

    # -- actions -------------------------------------------------------------------------------
    def on_goal(self, key: str, goal_handle) -> None:
        controller = self.model.controllers[key]
        goal = goal_handle.get_goal()
        trajectory = goal.trajectory
        points = [GoalPoint(point.time_from_start.to_sec(), point.positions, point.velocities, point.accelerations)
                  for point in trajectory.points]
        stamp = None if trajectory.header.stamp.is_zero() else trajectory.header.stamp.to_sec() - self._epoch
        tolerances = GoalTolerances(goal.path_tolerance, goal.goal_tolerance, goal.goal_time_tolerance.to_sec())
        with self._lock:
            now = self._now()
            ended = controller.update(now)  # the control loop's updates due before this goal came
            acceptance = controller.submit(goal_handle, trajectory.joint_names, points, now, stamp, tolerances)
        self._deliver(controller.name, ended)
        if not acceptance.accepted:
            rospy.logwarn("%s: goal rejected (error code %d): %s", NODE_NAME, acceptance.error_code,
                          acceptance.error_string)
            goal_handle.set_rejected(FollowJointTrajectoryResult(error_code=acceptance.error_code,
                                                                 error_string=acceptance.error_string),
                                     acceptance.error_string)
            return
        if acceptance.preempted_goal is not None:  # as the controller does: preempt, then accept
            acceptance.preempted_goal.set_canceled(
                FollowJointTrajectoryResult(error_string="preempted by a new goal"), "preempted by a new goal")
        goal_handle.set_accepted()
        rospy.logdebug("%s: %s accepted a goal of %d point(s)%s", NODE_NAME, controller.name, len(points),
                       ", preempting the active one" if acceptance.preempted_goal is not None else "")
        if acceptance.limit_violations:
            self._report_violations(controller.name, acceptance.limit_violations)

    def on_command(self, key: str, trajectory: JointTrajectory) -> None:
        controller = self.model.controllers[key]
        points = [GoalPoint(point.time_from_start.to_sec(), point.positions, point.velocities, point.accelerations)
                  for point in trajectory.points]
        stamp = None if trajectory.header.stamp.is_zero() else trajectory.header.stamp.to_sec() - self._epoch
        with self.servers[key].lock:  # goals may end here, and their handles are used under their server's lock
            with self._lock:
                now = self._now()
                ended = controller.update(now)
                acceptance = controller.command(trajectory.joint_names, points, now, stamp)
            self._deliver(controller.name, ended)
            if acceptance.accepted and acceptance.preempted_goal is not None:
                acceptance.preempted_goal.set_canceled(
                    FollowJointTrajectoryResult(error_string="preempted by a command trajectory"),
                    "preempted by a command trajectory")
        if not acceptance.accepted:
            rospy.logwarn("%s: %s command rejected: %s", NODE_NAME, controller.name, acceptance.error_string)
            return
        rospy.logdebug("%s: %s follows a command trajectory of %d point(s)", NODE_NAME, controller.name, len(points))

    def on_cancel(self, key: str, goal_handle) -> None:
        controller = self.model.controllers[key]
        with self._lock:
            now = self._now()
            ended = controller.update(now)
            stopped = controller.cancel(goal_handle, now)
        self._deliver(controller.name, ended)
        if any(outcome.goal == goal_handle for outcome in ended):
            return  # it ended at an update before the cancel came: its result is sent
        goal_handle.set_canceled(FollowJointTrajectoryResult(error_string="canceled"), "canceled")
        rospy.logdebug("%s: %s goal canceled%s", NODE_NAME, controller.name, ", holding" if stopped else "")

    def _deliver(self, controller_name: str, outcomes) -> None:
        """Send the results of goals that ended (the caller holds the controller's server lock)."""
        for outcome in outcomes:
            result = FollowJointTrajectoryResult(error_code=outcome.error_code, error_string=outcome.error_string)
            if outcome.error_code == SUCCESSFUL:
                outcome.goal.set_succeeded(result)
                continue
            rospy.loginfo("%s: %s aborted a goal (error code %d): %s", NODE_NAME, controller_name, outcome.error_code,
                          outcome.error_string)
            outcome.goal.set_aborted(result, outcome.error_string)

    def _report_violations(self, controller_name: str, violations) -> None:
        rospy.logwarn("%s: %s goal beyond the joint limits, executed at the limits: %s", NODE_NAME,
                      controller_name, describe_violations(violations))
        self._publish_violations()

    def _publish_violations(self) -> None:
        with self._violation_lock:  # goals of different controllers arrive on different threads
            with self._lock:
                count = self.model.limit_violation_count
            if count != self._reported_violations:
                self._reported_violations = count
                self.violation_publisher.publish(UInt32(data=count))

    # -- base ----------------------------------------------------------------------------------
    def on_twist(self, message: Twist) -> None:
        with self._lock:
            reply = self.model.base_command(message.linear.x, message.linear.y, message.angular.z, self._now())
        if message.linear.x or message.linear.y:
            rospy.logwarn_once("%s: linear.x/y of %s are not simulated (the base only turns)", NODE_NAME,
                               base_topic(self.platform))
        if reply == "invalid":
            rospy.logwarn("%s: ignored a %s command that is not finite", NODE_NAME, base_topic(self.platform))
        else:
            rospy.logdebug("%s: %s angular.z %.4f: %s", NODE_NAME, base_topic(self.platform), message.angular.z,
                           reply)

    # -- naoqi_driver ---------------------------------------------------------------------------
    def on_joint_angles(self, message: JointAnglesWithSpeed) -> None:
        with self._lock:
            problem = self.model.joint_angles(message.joint_names, message.joint_angles, message.speed,
                                              message.relative, self._now())
        if problem is None:
            return
        # A sender streams at 10 Hz or more: one line per kind of problem, not one per message.
        if problem not in self._joint_angle_problems:
            self._joint_angle_problems.add(problem)
            rospy.logwarn("%s: ignored a %s message (%s): joints %s, angles %s, speed %s; further messages with "
                          "this problem are ignored silently", NODE_NAME, JOINT_ANGLES_TOPIC, problem,
                          list(message.joint_names), list(message.joint_angles), message.speed)

    # -- update loop ---------------------------------------------------------------------------
    def on_tick(self, event) -> None:
        quiet_at_shutdown(lambda _event: self._tick(), event)

    def _tick(self) -> None:
        for key, server in self.servers.items():
            controller = self.model.controllers[key]
            with server.lock:
                with self._lock:
                    ended = controller.update(self._now())
                self._deliver(controller.name, ended)
        with self._lock:
            now = self._now()
            joints = self.model.joint_state(now)
            read_at = self.model.reading_time(now)
            base = self.model.base_state(now)
            commanded = self.model.driver_commands(now) if self.model.driver is not None else None
        stamp = rospy.Time.from_sec(now + self._epoch)
        fill_state_messages(stamp, rospy.Time.from_sec(read_at + self._epoch), joints, base, self._joint_state,
                            self._odometry, commanded, self._commanded)
        self.joint_state_publisher.publish(self._joint_state)
        if commanded is not None:
            self.commanded_publisher.publish(self._commanded)
        self.odometry_publisher.publish(self._odometry)
        if self._feedback_period is not None and now >= self._next_feedback:
            self._next_feedback = now + self._feedback_period
            self._publish_feedback(stamp)

    def _publish_feedback(self, stamp) -> None:
        for key, server in self.servers.items():
            controller = self.model.controllers[key]
            with server.lock:
                with self._lock:
                    goal_handle = controller.active_goal
                    update = controller.last_update
                if goal_handle is None:
                    continue
                feedback = FollowJointTrajectoryFeedback(  # as the controller's: its last update
                    joint_names=list(controller.joint_names),
                    **{name: JointTrajectoryPoint(**point) for name, point in update.feedback_points().items()})
                feedback.header.stamp = rospy.Time.from_sec(update.time + self._epoch)
                goal_handle.publish_feedback(feedback)


def loop_parameters() -> Optional[Dict[str, Any]]:
    """The controllers' loop settings from the private parameters; None after a logfatal naming a bad one."""
    values = {name: rospy.get_param("~" + name, default)
              for name, default in (("control_rate", CONTROL_RATE), ("velocity_report", MEASURED),
                                    ("goal_time", GOAL_TIME),
                                    ("stopped_velocity_tolerance", STOPPED_VELOCITY_TOLERANCE))}
    try:
        check_loop_settings(**values)
    except ValueError as error:
        rospy.logfatal("%s: ~%s", NODE_NAME, error)
        return None
    return values


def main() -> int:
    rospy.init_node(NODE_NAME)
    platform = rospy.get_param("~platform", "robot")
    initial_posture = rospy.get_param("~initial_posture", "rest")
    if platform not in PLATFORMS or initial_posture not in POSTURES:
        rospy.logfatal("%s: ~platform must be one of %s (got %r) and ~initial_posture one of %s (got %r)", NODE_NAME,
                       ", ".join(PLATFORMS), platform, ", ".join(POSTURES), initial_posture)
        return 2
    driver = rospy.get_param("~driver", IDEAL)
    if driver not in DRIVERS:
        rospy.logfatal("%s: ~driver must be one of %s (got %r)", NODE_NAME, ", ".join(DRIVERS), driver)
        return 2
    loop = loop_parameters()
    try:
        initial_positions = parse_initial_positions(str(rospy.get_param("~initial_positions", "")))
    except ValueError as error:
        rospy.logfatal("%s: ~%s", NODE_NAME, error)
        return 2
    if loop is None:
        return 2
    SimulatedPepperNode(platform, initial_posture, bool(rospy.get_param("~moveto_keep_latest", False)),
                        float(rospy.get_param("~feedback_rate", 10.0)), driver, initial_positions=initial_positions,
                        **loop)
    rospy.spin()
    return 0
