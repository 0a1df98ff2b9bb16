"""The animateBehaviour node's supervisor: configuration, service, and the one thread that owns the
motion state. The service callback, actionlib's callbacks, the controller watcher and the signal
handler only post events to its queue; it dispatches them to the part and base streams.
"""
import logging
import os
import queue
import threading
import time
from typing import Dict, Optional

import numpy
import rospy
from actionlib_msgs.msg import GoalStatus
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import (Configuration, ConfigurationError,
                                                         configuration_items, load_configuration,
                                                         shipped_configuration_path, topic_file_path)
from cssr_system.animate_behaviour.contract import (PURPOSE_ANIMATE, PURPOSE_HOME, ACCEPTED_STATES, ENABLED,
                                                    NODE_NAME, REPLY_FAILURE, REPLY_SUCCESS, SERVICE_NAME,
                                                    parse_activation_state, JOINT_STATES_TOPIC,
                                                    NODE_PARAMETERS)
from cssr_system.animate_behaviour.event_log import EventLog, default_log_path
from cssr_system.animate_behaviour.motion.waypoints import animated_parts, make_rng, random_waypoints
from cssr_system.animate_behaviour.node.base_stream import BaseStream
from cssr_system.animate_behaviour.node.events import ControllerConnected, Disable, Enable, GoalDone, Shutdown
from cssr_system.animate_behaviour.node.joint_states import JointStateCache
from cssr_system.animate_behaviour.node.part_stream import PartState, PartStream
from cssr_system.animate_behaviour.topics import WHEELS_KEY, TopicFileError, load_topic_map
from cssr_system.package_files import data_dir as data_dir_of_package, package_dir, package_version
from cssr_system.pepper.joint_table import PARTS
from cssr_system.srv import setActivation, setActivationResponse


HEARTBEAT_PERIOD = 10.0  # s between "running." lines on the console


SERVICE_REPLY_TIMEOUT = 0.08  # s the service waits for the supervisor to apply a request


HOME_GESTURE_DURATION = 0.5  # s, the shortest return to the centre on disable (stretched as needed)


HOME_MAX_DURATION = 2.0  # s; longer returns are reported (the speed cap wins over this bound)


RETRY_DELAY = 2.0  # s before a part tries again after a rejected, aborted or foreign-preempted goal


WATCH_PERIOD = 0.5  # s between checks of controllers that are not connected yet


WAIT_REPORT_PERIOD = 10.0  # s between log lines about a controller that is still missing


class AnimateBehaviour:
    """The node: configuration, service, supervisor and the streams it drives."""

    def __init__(self) -> None:
        self.package_dir = package_dir()
        self.version = package_version()
        self.default_config_file = shipped_configuration_path()
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
        data_dir = data_dir_of_package()
        config = load_configuration(config_file, self.parameter_overrides(), data_dir=data_dir)
        try:  # validated by load_configuration; read again only if the file changed since
            topics = load_topic_map(topic_file_path(config, data_dir)).topics
        except TopicFileError as error:
            raise ConfigurationError(error.problems)
        return config_file, config, dict(topics)

    # -- start-up -----------------------------------------------------------------------------
    def start(self, config_file: str, config: Configuration, topics: Dict[str, str]) -> None:
        self.log.write(contract.CONFIGURATION_LOADED, file=config_file,
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
                self.log.write(contract.CONFIGURATION_INVALID, file=self.current_config_file(),
                               problems=list(error.problems))
            else:
                reply = self._request(lambda done: Enable(config_file, config, topics, done))
        else:
            reply = self._request(lambda done: Disable("disabled", done))
        self.log.write(contract.ACTIVATION_REQUEST, state=request.state, reply=reply)
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
                self.log.write(contract.ERROR, where="supervisor",
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
                self.log.write(contract.ERROR, where=stream.part, message="goal result lost")
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
        self.log.write(contract.CONFIGURATION_LOADED, file=config_file,
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
        self.log.write(contract.BEHAVIOUR_STARTED, behaviour=sorted(config.behaviour),
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
        self.log.write(contract.BEHAVIOUR_ENDED, reason=reason, home=home)
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
        self.log.write(contract.GOAL_FINISHED, part=event.part, action=stream.action,
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
        self.log.write(contract.CONTROLLER_CONNECTED, part=event.part, action=event.action)
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
                    self.log.write(contract.CONTROLLER_WAITING, part=stream.part, action=action,
                                   seconds=round(waited, 1))
            self._stopped.wait(WATCH_PERIOD)


_GOAL_STATE_NAMES = {getattr(GoalStatus, name): name for name in (
    "PENDING", "ACTIVE", "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED", "PREEMPTING",
    "RECALLING", "RECALLED", "LOST")}


def _goal_state_name(state: int) -> str:
    return _GOAL_STATE_NAMES.get(state, str(state))
