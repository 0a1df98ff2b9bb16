"""The animateBehaviour node's supervisor: configuration, service, and the one thread that owns the
motion state. The service callback, actionlib's callbacks, the controller watcher and the signal
handler only post events to its queue; it dispatches them to the part and base streams.
"""
import logging
import os
import queue
import threading
import time
from typing import Dict, List, Optional

import actionlib
import rospy
from control_msgs.msg import FollowJointTrajectoryAction
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import Configuration, ConfigurationError, configuration_items
from cssr_system.animate_behaviour.contract import (ACCEPTED_STATES, ENABLED, NODE_NAME, REPLY_FAILURE,
                                                    REPLY_SUCCESS, SERVICE_NAME, parse_activation_state,
                                                    JOINT_STATES_TOPIC)
from cssr_system.animate_behaviour.event_log import EventLog, default_log_path
from cssr_system.animate_behaviour.motion.trajectory_timing import time_trajectory
from cssr_system.animate_behaviour.motion.waypoints import (animated_parts, make_rng, random_waypoints,
                                                            PartMotion)
from cssr_system.animate_behaviour.node.base_stream import BaseStream
from cssr_system.animate_behaviour.node.controller_watcher import ControllerWatcher
from cssr_system.animate_behaviour.node.events import ControllerConnected, Disable, Enable, GoalDone, Shutdown
from cssr_system.animate_behaviour.node.joint_states import JointStateCache
from cssr_system.animate_behaviour.node.parameters import config_file_parameter, load_node_configuration
from cssr_system.animate_behaviour.node.part_stream import PartStream, Planner
from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.package_files import package_dir, package_version
from cssr_system.pepper.joint_table import PARTS
from cssr_system.srv import setActivation, setActivationResponse


HEARTBEAT_PERIOD = 10.0  # s between "running." lines on the console
SERVICE_REPLY_TIMEOUT = 0.08  # s the service waits for the supervisor to apply a request


class AnimateBehaviour:
    """The node: configuration, service, supervisor and the streams it drives."""

    def __init__(self) -> None:
        self.version = package_version()
        self.log = EventLog(rospy.get_param("~logFile", default_log_path(package_dir(), os.environ.get("ROS_HOME"))))
        self.joint_states = JointStateCache()
        self.events: "queue.Queue" = queue.Queue()
        self.config: Optional[Configuration] = None
        self.enabled = False
        self.rng = None
        # The clock the controllers execute goals on; deadlines of the streams refer to it.
        self.clock = time.monotonic
        self.parts: Dict[str, PartStream] = {}  # by action namespace: one client each, kept for life
        self._parts_lock = threading.Lock()  # the watcher reads `parts` while the supervisor adds
        self.bases: Dict[str, BaseStream] = {}
        self.active_base: Optional[BaseStream] = None
        self._stopped = threading.Event()
        self._supervisor = threading.Thread(target=self._run, name="supervisor", daemon=True)
        self._watcher = ControllerWatcher(self._stream_snapshot, self.events.put, self.log, self._stopped)

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
        self._watcher.thread.start()
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
                config_file, config, topics = load_node_configuration()
            except ConfigurationError as error:
                rospy.logerr("%s: not enabled: %s", NODE_NAME, error)
                self.log.write(contract.CONFIGURATION_INVALID, file=config_file_parameter(),
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
        now = self.clock()
        deadlines = [deadline - now for deadline in (stream.next_deadline() for stream in self.parts.values())
                     if deadline is not None]
        deadlines += [deadline - time.monotonic() for deadline in (base.next_deadline() for base in self.bases.values())
                      if deadline is not None]
        return min([0.5] + [max(0.0, deadline) for deadline in deadlines])

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
            stream = self.parts.get(event.action)
            if stream is not None:
                stream.goal_done(event)
        elif isinstance(event, ControllerConnected):
            stream = self.parts.get(event.action)
            if stream is not None:
                stream.controller_connected()

    def _tick(self) -> None:
        for stream in list(self.parts.values()):
            stream.tick()
        now = time.monotonic()
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
        for stream in list(self.parts.values()):
            if stream.active and (stream.part not in motions or stream.action != topics.get(stream.part)):
                stream.disable(config.home_on_disable)
        for key, motion in motions.items():
            self._stream_for(key, topics[key]).enable(motion, self._planner(motion, config))
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

    def _planner(self, motion: PartMotion, config: Configuration) -> Planner:
        """The next animation goal of a part: random waypoints, timed smoothly from the current state."""
        joints = PARTS[motion.part].joints

        def plan(now, positions, velocities, accelerations):
            return time_trajectory(random_waypoints(motion, config, self.rng), joints, positions, velocities,
                                   config.gesture_duration, start_accelerations=accelerations)
        return plan

    def _disable(self, reason: str) -> None:
        if not self.enabled:
            return
        home = self.config.home_on_disable
        for stream in list(self.parts.values()):
            stream.disable(home)
        if self.active_base is not None:
            self.active_base.stop(home, time.monotonic(), self.log)
            self.active_base = None
        self.enabled = False
        self.log.write(contract.BEHAVIOUR_ENDED, reason=reason, home=home)
        rospy.loginfo("%s: stopped (%s).", NODE_NAME, reason)

    def _stream_for(self, part: str, action: str) -> PartStream:
        with self._parts_lock:
            if action not in self.parts:
                # The goal-handle client, not SimpleActionClient: its transitions carry their handle, so
                # a result that arrives before send_goal returns is not lost.
                client = actionlib.ActionClient(action, FollowJointTrajectoryAction)
                self.parts[action] = PartStream(part, action, client, self.clock, self.joint_states.positions,
                                                self.events.put, self.log)
            return self.parts[action]

    def _stream_snapshot(self) -> List[PartStream]:
        with self._parts_lock:
            return list(self.parts.values())

    def _base_for(self, topic: str) -> BaseStream:
        if topic not in self.bases:
            self.bases[topic] = BaseStream(topic)
        return self.bases[topic]
