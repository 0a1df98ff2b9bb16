"""The animateBehaviour node: the ROS adapter around the motion core.

It owns the ROS I/O (service, action clients, base publisher, /joint_states, log file, console) and
one state machine. A single supervisor thread owns every piece of motion state; the service
callback, actionlib's callbacks, the controller watcher and the signal handler only post events to
its queue. Each controller has its own `PartStream` (IDLE, ANIMATING, HOMING, WAITING) so that a
part can be paused or resumed on its own; the base has a `BaseStream`.
"""
import enum
import logging
import os
import queue
import signal
import sys
import threading
import time
import xml.etree.ElementTree as ElementTree
from collections import OrderedDict
from typing import Dict, List, NamedTuple, Optional

import actionlib
from actionlib.action_client import CommState
import numpy
import rospkg
import rospy
from actionlib_msgs.msg import GoalStatus
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from geometry_msgs.msg import Twist
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectoryPoint

from cssr_system import log_events
from cssr_system.log_events import PURPOSE_ANIMATE, PURPOSE_HOME, PURPOSE_RETURN
from cssr_system.activation import (ACCEPTED_STATES, ENABLED, NODE_NAME, REPLY_FAILURE,
                                    REPLY_SUCCESS, SERVICE_NAME, parse_activation_state)
from cssr_system.base_rotation import (VELOCITY, BaseRotationPlanner, heading_after_interruption,
                                       wheels_command_kind)
from cssr_system.configuration import (Configuration, ConfigurationError, configuration_items,
                                       load_configuration, shipped_configuration_path,
                                       topic_file_path)
from cssr_system.event_log import EventLog, default_log_path
from cssr_system.joint_table import PARTS
from cssr_system.motion_plan import PartMotion, animated_parts, make_rng, random_waypoints
from cssr_system.srv import setActivation, setActivationResponse
from cssr_system.topics import WHEELS_KEY, TopicFileError, load_topic_map
from cssr_system.trajectory_interpolation import JointTrajectorySpline
from cssr_system.trajectory_timing import TimedTrajectory, time_trajectory, to_points

PACKAGE_NAME = "cssr_system"
JOINT_STATES_TOPIC = "joint_states"
NODE_PARAMETERS = ("configFile", "logFile")  # private parameters that are not configuration keys

HEARTBEAT_PERIOD = 10.0  # s between "running." lines on the console
SERVICE_REPLY_TIMEOUT = 0.08  # s the service waits for the supervisor to apply a request
HOME_GESTURE_DURATION = 0.5  # s, the shortest return to the centre on disable (stretched as needed)
HOME_MAX_DURATION = 2.0  # s; longer returns are reported (the speed cap wins over this bound)
RETRY_DELAY = 2.0  # s before a part tries again after a rejected, aborted or foreign-preempted goal
JOINT_STATE_MAX_AGE = 1.0  # s; older /joint_states are not trusted as the current position
MAX_UNFINISHED_GOALS = 16  # handles kept for goals whose end has not been reported yet
LOST_RESULT_GRACE = 5.0  # s after a goal's end before a missing result counts as lost
WATCH_PERIOD = 0.5  # s between checks of controllers that are not connected yet
WAIT_REPORT_PERIOD = 10.0  # s between log lines about a controller that is still missing
SHUTDOWN_FLUSH_TIME = 0.3  # s left for the last messages to leave before the node exits


def package_dir() -> str:
    try:
        return rospkg.RosPack().get_path(PACKAGE_NAME)
    except rospkg.ResourceNotFound:
        return os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def package_version(directory: str) -> str:
    try:
        return ElementTree.parse(os.path.join(directory, "package.xml")).getroot().findtext("version")
    except (OSError, ElementTree.ParseError):
        return "unknown"


class JointStateCache:
    """The latest measured position of every joint, written by the /joint_states callback."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._positions: Dict[str, float] = {}
        self._received_at = 0.0

    def update(self, message: JointState) -> None:
        with self._lock:
            self._positions.update(zip(message.name, message.position))
            self._received_at = time.monotonic()

    def positions(self, joints) -> Optional[numpy.ndarray]:
        """Current positions of `joints`, or None when they are unknown or stale."""
        with self._lock:
            if time.monotonic() - self._received_at > JOINT_STATE_MAX_AGE:
                return None
            if not all(name in self._positions for name in joints):
                return None
            return numpy.array([self._positions[name] for name in joints], dtype=float)


# ----------------------------------------------------------------------------------------------
# Events posted to the supervisor.

class Enable(NamedTuple):
    config_file: str
    config: Configuration
    topics: Dict[str, str]
    done: threading.Event


class Disable(NamedTuple):
    reason: str
    done: threading.Event


class GoalDone(NamedTuple):
    part: str
    action: str
    goal_number: int
    state: int
    error_code: Optional[int]
    error_string: str


class ControllerConnected(NamedTuple):
    part: str
    action: str


class Shutdown(NamedTuple):
    reason: str
    done: threading.Event


class PartState(enum.Enum):
    IDLE = "idle"  # no goal of ours is running
    ANIMATING = "animating"  # random goals, one after the other
    HOMING = "homing"  # the return-to-centre goal after a disable
    WAITING = "waiting"  # animating, but waiting before the next goal (retry after a failure)


class SentGoal(NamedTuple):
    number: int
    purpose: str  # PURPOSE_ANIMATE or PURPOSE_HOME
    spline: JointTrajectorySpline  # what the controller executes, on the monotonic clock
    handle: object  # actionlib ClientGoalHandle


class PartStream:
    """One controller's goal stream. Only the supervisor thread calls its methods."""

    def __init__(self, part: str, action: str, post) -> None:
        self.part = part
        self.action = action
        # The goal-handle client, not SimpleActionClient: its transitions carry their handle, so
        # a result that arrives before send_goal returns is not lost.
        self.client = actionlib.ActionClient(action, FollowJointTrajectoryAction)
        self.connected = False
        self.state = PartState.IDLE
        self.motion: Optional[PartMotion] = None
        self.retry_at: Optional[float] = None
        self._post = post
        self._goal_number = 0
        self._sent: Optional[SentGoal] = None
        # Goals that have not reported their end, replaced and cancelled ones too: holding their
        # handles keeps their transitions coming, so every goal's final state reaches the log.
        self._unfinished: "OrderedDict[int, SentGoal]" = OrderedDict()

    # -- state estimates --------------------------------------------------------------------
    def current_state(self, joint_states: JointStateCache, now: float):
        """Positions and velocities to start the next goal from: what the controller is executing
        for us (it splices new goals onto that), else the measured joints, else the centre."""
        joints = PARTS[self.part].joints
        if self._sent is not None and now <= self._sent.spline.end_time:
            positions, velocities, accelerations = self._sent.spline.sample(now)
            return numpy.asarray(positions), numpy.asarray(velocities), numpy.asarray(accelerations)
        measured = joint_states.positions(joints)
        if measured is None and self._sent is not None:
            measured = numpy.asarray(self._sent.spline.sample(now)[0])
        if measured is None:
            measured = numpy.array(PARTS[self.part].centre, dtype=float)
        zeros = numpy.zeros(len(joints))
        return measured, zeros, zeros

    # -- commands -----------------------------------------------------------------------------
    def send(self, waypoints: numpy.ndarray, gesture_duration: float, purpose: str,
             joint_states: JointStateCache, log: EventLog) -> TimedTrajectory:
        now = time.monotonic()
        joints = PARTS[self.part].joints
        positions, velocities, accelerations = self.current_state(joint_states, now)
        bands = self.motion.bounds if self.motion is not None else ()
        lower, upper = [b.lower for b in bands], [b.upper for b in bands]
        # A return home from a moving joint brakes inside the band it was animated in.
        home_bounds = (lower, upper) if purpose == PURPOSE_HOME and bands else None
        timed = time_trajectory(waypoints, joints, positions, velocities, gesture_duration,
                                start_accelerations=accelerations, position_bounds=home_bounds)
        points = to_points(timed)
        goal = FollowJointTrajectoryGoal()
        goal.trajectory.joint_names = list(joints)
        goal.trajectory.header.stamp = rospy.Time(0)  # start now
        for point in points:
            goal.trajectory.points.append(JointTrajectoryPoint(
                positions=list(point.positions), velocities=list(point.velocities),
                accelerations=list(point.accelerations),
                time_from_start=rospy.Duration.from_sec(point.time)))
        self._goal_number += 1
        number = self._goal_number

        def transition(handle, part=self.part):
            if handle.get_comm_state() != CommState.DONE:
                return
            result = handle.get_result()
            self._post(GoalDone(part, self.action, number, handle.get_goal_status(),
                                None if result is None else result.error_code,
                                "" if result is None else result.error_string))

        handle = self.client.send_goal(goal, transition)
        self._sent = SentGoal(number, purpose,
                              JointTrajectorySpline(positions, velocities, accelerations, points,
                                                    start_time=now), handle)
        self._unfinished[number] = self._sent
        while len(self._unfinished) > MAX_UNFINISHED_GOALS:  # a controller that never answers
            self._unfinished.popitem(last=False)
        rospy.logdebug("%s: %s goal %d (%s) sent to %s: %d points over %.1f s.", NODE_NAME,
                       self.part, number, purpose, self.action, len(points), timed.times[-1])
        log.write(log_events.GOAL_SENT, part=self.part, label=PARTS[self.part].label,
                  action=self.action, purpose=purpose, goal=number, joints=joints,
                  centre=PARTS[self.part].centre,
                  lower=lower, upper=upper,
                  moving=self.motion.moving if self.motion is not None else (),
                  times=timed.times, positions=timed.positions)
        return timed

    def cancel(self) -> None:
        if self._sent is not None and self.connected:
            self._sent.handle.cancel()
        self._sent = None

    def overdue(self, now: float) -> bool:
        """True when our goal should long have ended but no result came (a lost result)."""
        return self._sent is not None and now > self._sent.spline.end_time + LOST_RESULT_GRACE

    def is_current(self, goal_number: int) -> bool:
        return self._sent is not None and self._sent.number == goal_number

    def finished(self, goal_number: int) -> Optional[SentGoal]:
        """The goal that reported its end, once; None for one already reported."""
        return self._unfinished.pop(goal_number, None)

    def forget_goal(self) -> None:
        self._sent = None

    @property
    def sent_purpose(self) -> Optional[str]:
        return None if self._sent is None else self._sent.purpose


class BaseState(enum.Enum):
    IDLE = "idle"
    ROTATING = "rotating"
    RETURNING = "returning"


class BaseStream:
    """The base's rotation commands on the Wheels topic. Only the supervisor thread calls it.

    A step is a turn (one relative command, or a streamed velocity bump) followed by a pause. The
    robot is busy for the step's busy_time; the pause is ours and is cut short on a new enable."""

    def __init__(self, topic: str) -> None:
        self.topic = topic
        self.kind = wheels_command_kind(topic)
        self.publisher = rospy.Publisher(topic, Twist, queue_size=10)
        self.state = BaseState.IDLE
        self.planner: Optional[BaseRotationPlanner] = None
        self._step = None
        self._step_purpose = ""
        self._step_started = 0.0
        self._step_ends_at = 0.0
        self._next_sample = 0  # index of the next velocity sample to publish

    def start(self, config: Configuration, rng, now: float, log: EventLog) -> None:
        # Keep the frame of a rotation or return still under way; otherwise start from heading 0.
        keep = self.planner is not None and (self.state != BaseState.IDLE or self._step is not None)
        heading = self.planner.heading if keep else 0.0
        self.planner = BaseRotationPlanner(self.kind, config.rot_maximum_range, config.heading_bound, rng)
        self.planner.set_heading(heading)
        self.state = BaseState.ROTATING
        if self._step is None:
            self._begin(self.planner.next_step(), now, PURPOSE_ANIMATE, log)
        else:
            self._drop_pause()

    def stop(self, return_home: bool, now: float, log: EventLog) -> None:
        """Stops at once (an explicit zero on a velocity topic); then, if asked, turns back to the
        heading the base had at enable, once a relative turn under way has ended."""
        if self.state == BaseState.IDLE:
            return
        if self.kind == VELOCITY and self._step is not None:
            self._publish(0.0)
            self.planner.set_heading(heading_after_interruption(self._step, self._next_sample))
            self._step = None
        elif self._step is not None:
            self._drop_pause()
        self.state = BaseState.IDLE
        if return_home and self.planner is not None:
            self.state = BaseState.RETURNING
            if self._step is None:
                self._begin(self.planner.return_step(), now, PURPOSE_RETURN, log)

    def _drop_pause(self) -> None:
        """The step under way ends when the robot is done with it: our pause after it is dropped."""
        self._step_ends_at = min(self._step_ends_at, self._step_started + self._step.busy_time)

    def next_deadline(self) -> Optional[float]:
        if self._step is None:
            return None
        if self.kind == VELOCITY and self._next_sample < len(self._step.velocities):
            return self._step_started + self._next_sample * self._step.period
        return self._step_ends_at

    def tick(self, now: float, log: EventLog) -> None:
        step = self._step
        if step is None:
            return
        if self.kind == VELOCITY:
            while (self._next_sample < len(step.velocities)
                   and now >= self._step_started + self._next_sample * step.period):
                self._publish(step.velocities[self._next_sample])
                self._next_sample += 1
        if now < self._step_ends_at:
            return
        ended = self._step_purpose
        self._step = None
        if self.state == BaseState.ROTATING:
            self._begin(self.planner.next_step(), now, PURPOSE_ANIMATE, log)
        elif self.state == BaseState.RETURNING and ended != PURPOSE_RETURN:
            self._begin(self.planner.return_step(), now, PURPOSE_RETURN, log)
        else:
            self.state = BaseState.IDLE

    def _begin(self, step, now: float, purpose: str, log: EventLog) -> None:
        self._step = step
        self._step_purpose = purpose
        self._step_started = now
        self._next_sample = 0
        if step is None:
            if self.state == BaseState.RETURNING:
                self.state = BaseState.IDLE
            return
        self._step_ends_at = now + step.duration
        rospy.logdebug("%s: base %s turn of %+.3f rad to heading %+.3f on %s.", NODE_NAME, purpose,
                       step.angle, step.target_heading, self.topic)
        log.write(log_events.BASE_COMMAND, topic=self.topic, kind=self.kind, purpose=purpose,
                  angle=step.angle, target_heading=step.target_heading, period=step.period,
                  velocities=step.velocities)
        if self.kind == VELOCITY:
            self.tick(now, log)
        else:
            self._publish(step.angle)

    def _publish(self, angular_z: float) -> None:
        twist = Twist()
        twist.angular.z = float(angular_z)
        self.publisher.publish(twist)


# ----------------------------------------------------------------------------------------------

class AnimateBehaviour:
    """The node: configuration, service, supervisor and the streams it drives."""

    def __init__(self) -> None:
        self.package_dir = package_dir()
        self.version = package_version(self.package_dir)
        self.default_config_file = shipped_configuration_path(self.package_dir)
        self.log = EventLog(rospy.get_param("~logFile", default_log_path(
            self.package_dir, os.environ.get("ROS_HOME"))))
        self.joint_states = JointStateCache()
        self.events: "queue.Queue" = queue.Queue()
        self.config: Optional[Configuration] = None
        self.enabled = False
        self.rng = None
        self.parts: Dict[str, PartStream] = {}  # by action namespace: one client each, kept for life
        self._parts_lock = threading.Lock()  # the watcher reads `parts` while the supervisor adds
        self.active_parts: Dict[str, PartStream] = {}  # by part key, while enabled or homing
        self.bases: Dict[str, BaseStream] = {}
        self.active_base: Optional[BaseStream] = None
        self._stopped = threading.Event()
        self._supervisor = threading.Thread(target=self._run, name="supervisor", daemon=True)
        self._watcher = threading.Thread(target=self._watch_controllers, name="watcher", daemon=True)

    # -- configuration ------------------------------------------------------------------------
    def parameter_overrides(self) -> Dict[str, object]:
        """Private parameters other than the node's own: overrides of configuration keys."""
        prefix = rospy.get_name() + "/"
        overrides = {}
        for name in rospy.get_param_names():
            if name.startswith(prefix) and "/" not in name[len(prefix):]:
                key = name[len(prefix):]
                if key not in NODE_PARAMETERS:
                    overrides[key] = rospy.get_param(name)
        return overrides

    def current_config_file(self) -> str:
        """~configFile as it is now: read again at every enable, so a harness can point the node
        at a configuration of its own. Relative paths are relative to the working directory."""
        return os.path.abspath(rospy.get_param("~configFile", self.default_config_file))

    def load(self):
        """(configuration file, configuration, topics of the selected platform);
        raises ConfigurationError."""
        config_file = self.current_config_file()
        data_dir = os.path.join(self.package_dir, "data")
        config = load_configuration(config_file, self.parameter_overrides(), data_dir=data_dir)
        try:  # validated by load_configuration; read again only if the file changed since
            topics = load_topic_map(topic_file_path(config, data_dir)).topics
        except TopicFileError as error:
            raise ConfigurationError(error.problems)
        return config_file, config, dict(topics)

    # -- start-up -----------------------------------------------------------------------------
    def start(self, config_file: str, config: Configuration, topics: Dict[str, str]) -> None:
        self.log.write(log_events.CONFIGURATION_LOADED, file=config_file,
                       items=configuration_items(config))
        # Clients and the base publisher connect while the node is still disabled, so the first
        # commands leave at once and none is lost to a connection not yet made.
        for key, name in topics.items():
            if key in PARTS:
                self._stream_for(key, name)
            elif key == WHEELS_KEY:
                self._base_for(name)
        self.apply_verbosity(config)
        for key, value in configuration_items(config).items():
            rospy.loginfo("%s: %-18s %s", NODE_NAME, key, value)
        rospy.Subscriber(JOINT_STATES_TOPIC, JointState, self.joint_states.update, queue_size=1)
        self._supervisor.start()
        self._watcher.start()
        rospy.Service(SERVICE_NAME, setActivation, self.handle_service)
        rospy.loginfo("%s: service %s ready (requests: %s).", NODE_NAME,
                      rospy.resolve_name(SERVICE_NAME), ", ".join(ACCEPTED_STATES))
        rospy.Timer(rospy.Duration(HEARTBEAT_PERIOD), self._heartbeat)

    @staticmethod
    def apply_verbosity(config: Configuration) -> None:
        logging.getLogger("rosout").setLevel(logging.DEBUG if config.verbose_mode else logging.INFO)

    def _heartbeat(self, _event) -> None:
        rospy.loginfo("%s: running.", NODE_NAME)

    # -- service (any thread): only requests transitions ----------------------------------------
    def handle_service(self, request) -> setActivationResponse:
        state = parse_activation_state(request.state)
        reply = REPLY_FAILURE
        if state is None:
            rospy.logwarn("%s: setActivation: unknown state %r; expected one of: %s.", NODE_NAME,
                          request.state, ", ".join(ACCEPTED_STATES))
        elif state == ENABLED:
            try:
                config_file, config, topics = self.load()
            except ConfigurationError as error:
                rospy.logerr("%s: not enabled: %s", NODE_NAME, error)
                self.log.write(log_events.CONFIGURATION_INVALID, file=self.current_config_file(),
                               problems=list(error.problems))
            else:
                reply = self._request(lambda done: Enable(config_file, config, topics, done))
        else:
            reply = self._request(lambda done: Disable("disabled", done))
        self.log.write(log_events.ACTIVATION_REQUEST, state=request.state, reply=reply)
        return setActivationResponse(reply)

    def _request(self, make_event) -> str:
        done = threading.Event()
        self.events.put(make_event(done))
        if not done.wait(SERVICE_REPLY_TIMEOUT):
            rospy.logwarn("%s: the request is taking longer than %.0f ms; it will still be applied.",
                          NODE_NAME, SERVICE_REPLY_TIMEOUT * 1000)
        return REPLY_SUCCESS

    def request_shutdown(self, reason: str) -> None:
        done = threading.Event()
        self.events.put(Shutdown(reason, done))
        done.wait(1.0)

    # -- supervisor thread: the only owner of the motion state -----------------------------------
    def _run(self) -> None:
        while not self._stopped.is_set():
            timeout = self._next_timeout()
            try:
                event = self.events.get(timeout=timeout)
            except queue.Empty:
                event = None
            try:
                if event is not None:
                    self._handle(event)
                self._tick()
            except Exception as error:  # the supervisor must survive anything a callback brings
                rospy.logerr("%s: %s: %s", NODE_NAME, type(error).__name__, error)
                self.log.write(log_events.ERROR, where="supervisor",
                               message="{}: {}".format(type(error).__name__, error))
            if isinstance(event, Shutdown):
                event.done.set()
                self._stopped.set()

    def _next_timeout(self) -> float:
        deadlines = [stream.retry_at for stream in self.active_parts.values()
                     if stream.retry_at is not None]
        for base in self.bases.values():
            deadline = base.next_deadline()
            if deadline is not None:
                deadlines.append(deadline)
        if not deadlines:
            return 0.5
        return min(0.5, max(0.0, min(deadlines) - time.monotonic()))

    def _handle(self, event) -> None:
        if isinstance(event, Enable):
            self._enable(event.config_file, event.config, event.topics)
            event.done.set()
        elif isinstance(event, Disable):
            self._disable(event.reason)
            event.done.set()
        elif isinstance(event, Shutdown):
            self._disable(event.reason)
        elif isinstance(event, GoalDone):
            self._goal_done(event)
        elif isinstance(event, ControllerConnected):
            self._connected(event)

    def _tick(self) -> None:
        now = time.monotonic()
        for stream in list(self.active_parts.values()):
            if stream.overdue(now):
                rospy.logwarn("%s: no result for the %s goal; sending the next one.", NODE_NAME,
                              stream.part)
                self.log.write(log_events.ERROR, where=stream.part, message="goal result lost")
                self._finish_goal(stream)
            if stream.retry_at is not None and now >= stream.retry_at:
                stream.retry_at = None
                if stream.state == PartState.WAITING and self.enabled:
                    stream.state = PartState.ANIMATING
                    self._send_random_goal(stream)
        for base in self.bases.values():
            base.tick(now, self.log)

    def _enable(self, config_file: str, config: Configuration, topics: Dict[str, str]) -> None:
        reconfigured = self.enabled
        if config.random_seed is not None or self.rng is None or reconfigured:
            self.rng = make_rng(config.random_seed)
        self.config = config
        self.apply_verbosity(config)
        self.log.write(log_events.CONFIGURATION_LOADED, file=config_file,
                       items=configuration_items(config))
        motions = {motion.part: motion for motion in animated_parts(
            config, [key for key in topics if key in PARTS])}
        # Parts that no longer move (new behaviour or platform) go home as on disable.
        for key, stream in list(self.active_parts.items()):
            if key not in motions or stream.action != topics.get(key):
                self._stop_part(stream, config.home_on_disable)
        for key, motion in motions.items():
            stream = self._stream_for(key, topics[key])
            stream.motion = motion
            self.active_parts[key] = stream
            stream.state = PartState.ANIMATING
            stream.retry_at = None
            if stream.connected:
                self._send_random_goal(stream)  # replaces a running goal smoothly (splice)
        wheels = topics.get(WHEELS_KEY) if "rotation" in config.behaviour else None
        if self.active_base is not None and self.active_base.topic != wheels:
            self.active_base.stop(config.home_on_disable, time.monotonic(), self.log)
            self.active_base = None
        if wheels is not None:
            self.active_base = self._base_for(wheels)
            self.active_base.start(config, self.rng, time.monotonic(), self.log)
        self.enabled = True
        self.log.write(log_events.BEHAVIOUR_STARTED, behaviour=sorted(config.behaviour),
                       platform=config.platform, parts=sorted(motions), wheels=wheels,
                       reconfigured=reconfigured)
        rospy.loginfo("%s: animating %s.", NODE_NAME, ", ".join(sorted(motions) + ([WHEELS_KEY] if wheels else [])))

    def _disable(self, reason: str) -> None:
        if not self.enabled:
            return
        home = self.config.home_on_disable
        now = time.monotonic()
        for stream in list(self.active_parts.values()):
            self._stop_part(stream, home)
        if self.active_base is not None:
            self.active_base.stop(home, now, self.log)
            self.active_base = None
        self.enabled = False
        self.log.write(log_events.BEHAVIOUR_ENDED, reason=reason, home=home)
        rospy.loginfo("%s: stopped (%s).", NODE_NAME, reason)

    def _stop_part(self, stream: PartStream, home: bool) -> None:
        stream.retry_at = None
        if stream.state in (PartState.ANIMATING, PartState.WAITING) and stream.sent_purpose == PURPOSE_ANIMATE:
            if home and stream.connected:
                centre = numpy.array([PARTS[stream.part].centre])
                timed = stream.send(centre, HOME_GESTURE_DURATION, PURPOSE_HOME, self.joint_states, self.log)
                if timed.times[-1] > HOME_MAX_DURATION:
                    rospy.logwarn("%s: %s returns to its centre in %.1f s (speed cap).", NODE_NAME,
                                  stream.part, timed.times[-1])
                stream.state = PartState.HOMING
                return
            stream.cancel()
        stream.state = PartState.IDLE
        self.active_parts.pop(stream.part, None)

    def _stream_for(self, part: str, action: str) -> PartStream:
        with self._parts_lock:
            if action not in self.parts:
                self.parts[action] = PartStream(part, action, self.events.put)
            return self.parts[action]

    def _base_for(self, topic: str) -> BaseStream:
        if topic not in self.bases:
            self.bases[topic] = BaseStream(topic)
        return self.bases[topic]

    def _send_random_goal(self, stream: PartStream) -> None:
        waypoints = random_waypoints(stream.motion, self.config, self.rng)
        stream.send(waypoints, self.config.gesture_duration, PURPOSE_ANIMATE, self.joint_states, self.log)

    def _goal_done(self, event: GoalDone) -> None:
        stream = self._stream_for(event.part, event.action)
        sent = stream.finished(event.goal_number)
        if sent is None:
            return
        self.log.write(log_events.GOAL_FINISHED, part=event.part, action=stream.action,
                       purpose=sent.purpose, goal=event.goal_number,
                       state=_goal_state_name(event.state), error_code=event.error_code,
                       error_string=event.error_string)
        if self.active_parts.get(event.part) is not stream or not stream.is_current(event.goal_number):
            return  # a goal we replaced or cancelled: its end changes nothing
        if event.state == GoalStatus.SUCCEEDED or stream.sent_purpose == PURPOSE_HOME:
            self._finish_goal(stream)
            return
        rospy.logwarn("%s: %s goal ended %s (%s); trying again in %.0f s.", NODE_NAME, event.part,
                      _goal_state_name(event.state), event.error_string or "no reason given", RETRY_DELAY)
        stream.state = PartState.WAITING
        stream.retry_at = time.monotonic() + RETRY_DELAY

    def _finish_goal(self, stream: PartStream) -> None:
        """A goal of ours ended as planned: a part going home is done, an animating one goes on."""
        purpose = stream.sent_purpose
        stream.forget_goal()
        if purpose == PURPOSE_HOME:
            stream.state = PartState.IDLE
            self.active_parts.pop(stream.part, None)
        elif self.enabled and stream.state == PartState.ANIMATING:
            self._send_random_goal(stream)

    def _connected(self, event: ControllerConnected) -> None:
        stream = self.parts.get(event.action)
        if stream is None or stream.connected:
            return
        stream.connected = True
        self.log.write(log_events.CONTROLLER_CONNECTED, part=event.part, action=event.action)
        rospy.loginfo("%s: controller %s connected.", NODE_NAME, event.action)
        if self.enabled and self.active_parts.get(stream.part) is stream and stream.state == PartState.ANIMATING:
            self._send_random_goal(stream)

    # -- watcher thread: finds controllers without blocking anyone -------------------------------
    def _watch_controllers(self) -> None:
        started: Dict[str, float] = {}  # when each missing controller was first looked for
        last_report: Dict[str, float] = {}
        while not self._stopped.is_set() and not rospy.is_shutdown():
            with self._parts_lock:
                streams = list(self.parts.items())
            for action, stream in streams:
                if stream.connected:
                    continue
                started.setdefault(action, time.monotonic())
                if stream.client.wait_for_server(rospy.Duration(0.05)):
                    self.events.put(ControllerConnected(stream.part, action))
                    continue
                waited = time.monotonic() - started[action]
                if (waited >= WAIT_REPORT_PERIOD
                        and time.monotonic() - last_report.get(action, 0.0) >= WAIT_REPORT_PERIOD):
                    last_report[action] = time.monotonic()
                    rospy.logwarn("%s: still waiting for controller %s (%.0f s); %s is skipped "
                                  "until it appears.", NODE_NAME, action, waited, stream.part)
                    self.log.write(log_events.CONTROLLER_WAITING, part=stream.part, action=action,
                                   seconds=round(waited, 1))
            self._stopped.wait(WATCH_PERIOD)


_GOAL_STATE_NAMES = {getattr(GoalStatus, name): name for name in (
    "PENDING", "ACTIVE", "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED", "PREEMPTING",
    "RECALLING", "RECALLED", "LOST")}


def _goal_state_name(state: int) -> str:
    return _GOAL_STATE_NAMES.get(state, str(state))


def print_banner(version: str) -> None:
    rospy.loginfo("%s %s: makes the Pepper robot look alive with small random movements.",
                  NODE_NAME, version)
    rospy.loginfo("%s: start-up.", NODE_NAME)


def main(argv: Optional[List[str]] = None) -> int:
    argv = rospy.myargv(sys.argv if argv is None else argv)
    # The node handles SIGINT and SIGTERM itself: it stops the robot before rospy shuts down.
    rospy.init_node(NODE_NAME, disable_signals=True)
    try:
        node = AnimateBehaviour()
    except OSError as error:
        rospy.logerr("%s: cannot open the log file: %s", NODE_NAME, error)
        return 1
    print_banner(node.version)
    node.log.write(log_events.NODE_STARTED, version=node.version, node=rospy.get_name(),
                   config_file=node.current_config_file(), log_file=node.log.path,
                   parameters={key: str(value) for key, value in node.parameter_overrides().items()},
                   arguments=argv[1:])
    try:
        config_file, config, topics = node.load()
    except ConfigurationError as error:
        print("{}: invalid configuration: {}".format(NODE_NAME, error), file=sys.stderr, flush=True)
        node.log.write(log_events.CONFIGURATION_INVALID, file=node.current_config_file(),
                       problems=list(error.problems))
        rospy.signal_shutdown("invalid configuration")
        return 1
    node.start(config_file, config, topics)

    stop_reason = []
    signal.signal(signal.SIGINT, lambda number, frame: stop_reason.append("SIGINT"))
    signal.signal(signal.SIGTERM, lambda number, frame: stop_reason.append("SIGTERM"))
    while not stop_reason and not rospy.is_shutdown():
        time.sleep(0.02)
    reason = stop_reason[0] if stop_reason else "ROS shutdown"
    node.request_shutdown(reason)
    time.sleep(SHUTDOWN_FLUSH_TIME)  # let the cancel, home goals and zero twist leave
    node.log.write(log_events.NODE_STOPPED, reason=reason)
    node.log.close()
    rospy.signal_shutdown(reason)
    return 0
