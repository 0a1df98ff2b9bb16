"""The animateBehaviour node's supervisor: configuration, service, and the one thread that owns the
motion state. The service callback, actionlib's callbacks, the controller watcher and the signal
handler only post events to its queue; it dispatches them to the part and base streams.
"""
import io
import logging
import os
import queue
import threading
import time
from typing import Dict, List, Optional, Tuple

import actionlib
import numpy
import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryActionGoal
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import JointState
from std_srvs.srv import SetBool, SetBoolResponse

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import Configuration, ConfigurationError, configuration_items
from cssr_system.animate_behaviour.contract import (ACCEPTED_STATES, ENABLED, NODE_NAME, REPLY_FAILURE,
                                                    REPLY_SUCCESS, SERVICE_NAME, parse_activation_state,
                                                    JOINT_STATES_TOPIC, DIAGNOSTICS_TOPIC, DISABLED,
                                                    SET_ENABLED_SERVICE_NAME, STATUS_TOPIC)
from cssr_system.animate_behaviour.event_log import (EventLog, default_log_path, format_log_line,
                                                     format_timestamp)
from cssr_system.animate_behaviour.motion.trajectory_timing import time_trajectory, to_points
from cssr_system.animate_behaviour.motion.waypoints import (animated_parts, make_rng, random_waypoints,
                                                            PartMotion)
from cssr_system.animate_behaviour.node.base_stream import BaseStream
from cssr_system.animate_behaviour.node.controller_watcher import ControllerWatcher
from cssr_system.animate_behaviour.node.events import (ControllerConnected, Disable, Enable, GoalDone,
                                                       Shutdown, ForeignCommand, ForeignGoal, ForeignResult,
                                                       ForeignTwist, ControllerLost)
from cssr_system.animate_behaviour.node.foreign_motion import COMMAND, GOAL
from cssr_system.animate_behaviour.node.foreign_watch import ForeignCommandWatch
from cssr_system.animate_behaviour.node.joint_states import JointStateCache
from cssr_system.animate_behaviour.node.parameters import config_file_parameter, load_node_configuration
from cssr_system.animate_behaviour.node.part_stream import PartStream, Planner, goal_message
from cssr_system.animate_behaviour.node.status import status_diagnostics
from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.msg import AnimateBehaviourStatus, PartStatus
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
        # The clock the controllers execute goals on (ROS time, as Gazebo's controllers): the streams' deadlines.
        self.clock = rospy.get_time
        self.watch = ForeignCommandWatch(rospy.get_caller_id(), self.events.put, self.clock)
        self.status_publisher = rospy.Publisher(STATUS_TOPIC, AnimateBehaviourStatus, queue_size=1, latch=True)
        self.diagnostics_publisher = rospy.Publisher(DIAGNOSTICS_TOPIC, DiagnosticArray, queue_size=1)
        self._published_status = None
        self._command_count = 0  # numbers the command-topic trajectories of other nodes
        self.parts: Dict[str, PartStream] = {}  # by action namespace: one client each, kept for life
        self._parts_lock = threading.Lock()  # the watcher reads `parts` while the supervisor adds
        self.bases: Dict[str, BaseStream] = {}
        self.active_base: Optional[BaseStream] = None
        self._stopped = threading.Event()
        self._supervisor = threading.Thread(target=self._run, name="supervisor", daemon=True)
        self._watcher = ControllerWatcher(self._stream_snapshot, self.events.put, self.log, self._stopped,
                                          self.report_error)

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
        self._rehearse(config, topics)
        self._supervisor.start()
        self._watcher.thread.start()
        self._publish_status()
        rospy.Service(SERVICE_NAME, setActivation, self.handle_set_activation)
        rospy.Service(SET_ENABLED_SERVICE_NAME, SetBool, self.handle_set_enabled)
        rospy.loginfo("%s: service %s ready (requests: %s); %s ready.", NODE_NAME,
                      rospy.resolve_name(SERVICE_NAME), ", ".join(ACCEPTED_STATES),
                      rospy.resolve_name(SET_ENABLED_SERVICE_NAME))
        rospy.Timer(rospy.Duration(HEARTBEAT_PERIOD), self._heartbeat)

    def _rehearse(self, config: Configuration, topics: Dict[str, str]) -> None:
        """Plans, builds and encodes one goal and its log line per part without sending them, so that the
        first `enabled` pays no first-use costs (on the robot laptop's Python they made it take ~80 ms)."""
        self.rng = make_rng(config.random_seed)
        for motion in animated_parts(config, [key for key in topics if key in PARTS]):
            joints = PARTS[motion.part].joints
            centre, zeros = numpy.array(PARTS[motion.part].centre), numpy.zeros(len(joints))
            timed = self._planner(motion, config)(0.0, centre, zeros, zeros)
            goal = FollowJointTrajectoryActionGoal(goal=goal_message(joints, to_points(timed)))
            goal.serialize(io.BytesIO())
            format_log_line(format_timestamp(time.time()), contract.GOAL_SENT,
                            dict(times=timed.times, positions=timed.positions))

    @staticmethod
    def apply_verbosity(config: Configuration) -> None:
        logging.getLogger("rosout").setLevel(logging.DEBUG if config.verbose_mode else logging.INFO)

    def _heartbeat(self, _event) -> None:
        rospy.loginfo("%s: running.", NODE_NAME)

    # -- services (any thread): only request transitions ---------------------------------------
    def handle_set_activation(self, request) -> setActivationResponse:
        accepted, _ = self._activate(request.state)
        reply = REPLY_SUCCESS if accepted else REPLY_FAILURE
        self.log.write(contract.ACTIVATION_REQUEST, state=request.state, reply=reply)
        return setActivationResponse(reply)

    def handle_set_enabled(self, request) -> SetBoolResponse:
        state = ENABLED if request.data else DISABLED
        accepted, message = self._activate(state)
        self.log.write(contract.ACTIVATION_REQUEST, state=state, reply=REPLY_SUCCESS if accepted else REPLY_FAILURE,
                       service="set_enabled")
        return SetBoolResponse(success=accepted, message=message)

    def _activate(self, requested: str) -> Tuple[bool, str]:
        """Apply a request of either service: (accepted, what happened, in one line)."""
        state = parse_activation_state(requested)
        if state is None:
            message = "unknown state %r; expected one of: %s" % (requested, ", ".join(ACCEPTED_STATES))
            rospy.logwarn("%s: setActivation: %s.", NODE_NAME, message)
            return False, message
        if state == DISABLED:
            self._request(lambda done: Disable("disabled", done))
            return True, "disabled"
        try:
            config_file, config, topics = load_node_configuration()
        except ConfigurationError as error:
            rospy.logerr("%s: not enabled: %s", NODE_NAME, error)
            self.log.write(contract.CONFIGURATION_INVALID, file=config_file_parameter(), problems=list(error.problems))
            return False, "not enabled: %s" % error
        self._request(lambda done: Enable(config_file, config, topics, done))
        return True, "enabled"

    def _request(self, make_event) -> None:
        done = threading.Event()
        self.events.put(make_event(done))
        if not done.wait(SERVICE_REPLY_TIMEOUT):
            rospy.logwarn("%s: the request is taking longer than %.0f ms; it will still be applied.",
                          NODE_NAME, SERVICE_REPLY_TIMEOUT * 1000)

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
                self._publish_status()
            except Exception as error:  # the supervisor must survive anything a callback brings
                self.report_error("supervisor", error)
            if isinstance(event, Shutdown):
                event.done.set()
                self._stopped.set()

    def _next_timeout(self) -> float:
        now = self.clock()
        deadlines = [deadline - now for deadline in (stream.next_deadline() for stream in self.parts.values())
                     if deadline is not None]
        deadlines += [deadline - now for deadline in (base.next_deadline(now) for base in self.bases.values())
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
            self.parts[event.action].controller_connected()
        elif isinstance(event, ControllerLost):
            self.parts[event.action].controller_lost()
        elif isinstance(event, ForeignGoal):
            self.parts[event.action].foreign_motion(event.goal_id, event.caller, GOAL, event.last_point_at)
        elif isinstance(event, ForeignResult):
            self.parts[event.action].foreign_result(event.goal_id)
        elif isinstance(event, ForeignCommand):
            self._command_count += 1
            self.parts[event.action].foreign_motion("command-%d" % self._command_count, event.caller, COMMAND,
                                                    event.last_point_at)
        elif isinstance(event, ForeignTwist):
            self.bases[event.topic].foreign_twist(event.caller, event.twist, self.clock(), self.log)

    def _tick(self) -> None:
        for stream in list(self.parts.values()):
            stream.tick()
        now = self.clock()
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
            self._stream_for(key, topics[key]).enable(motion, self._planner(motion, config), config.yield_quiet_time)
        wheels = topics.get(WHEELS_KEY) if "rotation" in config.behaviour else None
        if self.active_base is not None and self.active_base.topic != wheels:
            self.active_base.stop(config.home_on_disable, self.clock(), self.log)
            self.active_base = None
        if wheels is not None:
            self.active_base = self._base_for(wheels)
            self.active_base.start(config, self.rng, self.clock(), self.log)
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
            self.active_base.stop(home, self.clock(), self.log)
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
                # Feedback is not used: no connection, no thread, no decoding at the controller's rate (the
                # watcher's server_ready does not need it).
                client.feedback_sub.unregister()
                # Cancels are rare and small: published at once rather than through a queue thread per controller.
                client.pub_cancel.impl.set_queue_size(None)
                self.parts[action] = PartStream(part, action, client, self.clock, self.joint_states.positions,
                                                self.events.put, self.log)
                self.watch.watch_controller(action)
            return self.parts[action]

    def report_error(self, where: str, error: Exception) -> None:
        """An unexpected error in a thread of the node: one line on the console and in the log; the thread goes on."""
        rospy.logerr("%s: %s: %s: %s", NODE_NAME, where, type(error).__name__, error)
        self.log.write(contract.ERROR, where=where, message="{}: {}".format(type(error).__name__, error))

    def _stream_snapshot(self) -> List[PartStream]:
        with self._parts_lock:
            return list(self.parts.values())

    def _base_for(self, topic: str) -> BaseStream:
        if topic not in self.bases:
            self.bases[topic] = BaseStream(topic)
            self.watch.watch_base(topic)
        return self.bases[topic]

    # -- status ---------------------------------------------------------------------------------
    def _publish_status(self) -> None:
        """The status topic and /diagnostics, when anything changed (README: "Status")."""
        with self._parts_lock:
            streams = list(self.parts.values())
        parts = tuple((stream.part, stream.action, stream.state.value, stream.yielding_to) for stream in streams)
        parts += tuple((WHEELS_KEY, base.topic, base.status, base.yielding_to) for base in self.bases.values())
        status = (self.enabled, parts)
        if status == self._published_status:
            return
        self._published_status = status
        message = AnimateBehaviourStatus(enabled=self.enabled, parts=[
            PartStatus(part=part, controller=controller, state=state, yielding_to=caller)
            for part, controller, state, caller in parts])
        message.header.stamp = rospy.Time.now()
        self.status_publisher.publish(message)
        self.diagnostics_publisher.publish(status_diagnostics(message))
