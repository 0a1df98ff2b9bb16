"""The animateBehaviour node's supervisor: configuration, service, and the one thread that owns the
motion state. The service callback, actionlib's callbacks, the controller watcher and the signal
handler only post events to its queue; it dispatches them to the part and base streams.
"""
import logging
import os
import queue
import threading
from typing import Callable, Dict, List, Optional

import rospy
from sensor_msgs.msg import JointState

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import Configuration, configuration_items
from cssr_system.animate_behaviour.contract import NODE_NAME, JOINT_STATES_TOPIC
from cssr_system.animate_behaviour.event_log import BackgroundLog, EventLog, default_log_path
from cssr_system.animate_behaviour.motion.styles import MotionStyle
from cssr_system.animate_behaviour.motion.waypoints import animated_parts, make_rng, narrow_bands
from cssr_system.animate_behaviour.node.base_stream import BaseStream
from cssr_system.animate_behaviour.node.controller_watcher import ControllerWatcher
from cssr_system.animate_behaviour.node.events import (ControllerConnected, Disable, Enable, GoalDone,
                                                       Shutdown, ForeignCommand, ForeignGoal, ForeignResult,
                                                       ForeignTwist, ControllerLost)
from cssr_system.animate_behaviour.node.foreign_motion import GOAL
from cssr_system.animate_behaviour.node.first_goals import PreparedEnable, prepare_enable
from cssr_system.animate_behaviour.node.foreign_watch import ForeignCommandWatch
from cssr_system.animate_behaviour.node.joint_state_batching import (ReadBatching, set_low_water_mark,
                                                                     subscription_connections)
from cssr_system.animate_behaviour.node.joint_state_feed import FeedState, JointStateFeed, SubscriptionSwitch
from cssr_system.animate_behaviour.node.joint_states import RAW_KEPT, JointStateCache
from cssr_system.animate_behaviour.node.part_stream import PartStream, rehearse, action_client
from cssr_system.animate_behaviour.node.services import ActivationServices
from cssr_system.animate_behaviour.node.status import StatusPublisher
from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.package_files import package_dir, package_version
from cssr_system.pepper.joint_table import PARTS, DRIVER_JOINT_PRECISION


HEARTBEAT_PERIOD = 10.0  # s between "running." lines on the console


def decode_joint_state(data: bytes) -> JointState:
    return JointState().deserialize(data)


class AnimateBehaviour:
    """The node: configuration, service, supervisor and the streams it drives."""

    def __init__(self) -> None:
        self.version = package_version()
        log_file = rospy.get_param("~logFile", default_log_path(package_dir(), os.environ.get("ROS_HOME")))
        self.log = BackgroundLog(EventLog(log_file))
        self.events: "queue.Queue" = queue.Queue()
        self.config: Optional[Configuration] = None
        self.enabled = False
        self.rng = None
        self._expected: Optional[tuple] = None  # (configuration, topics) the next enable is expected to bring
        self._prepared: Optional[PreparedEnable] = None  # its first goals, planned while disabled
        self._band_warnings: List[str] = []  # the robot driver's dead band: what the console last said
        # The clock the controllers execute goals on (ROS time, as Gazebo's controllers): the streams' deadlines.
        self.clock = rospy.get_time
        self.joint_states = JointStateCache(self.clock, lambda text: self.report_problem("joint_states", text),
                                            decode_joint_state)
        self.joint_state_feed: Optional[JointStateFeed] = None
        self._joint_state_switch: Optional[SubscriptionSwitch] = None
        self._joint_state_batching = ReadBatching(
            set_low_water_mark, lambda text: rospy.logdebug("%s: %s: %s.", NODE_NAME, JOINT_STATES_TOPIC, text))
        self.status = StatusPublisher()
        self.services = ActivationServices(self.events.put, self.log)
        self.parts: Dict[str, PartStream] = {}  # by action namespace: one client each, kept for life
        self._parts_lock = threading.Lock()  # the watcher reads `parts` while the supervisor adds
        self.bases: Dict[str, BaseStream] = {}
        self.active_base: Optional[BaseStream] = None
        self._stopped = threading.Event()
        self._supervisor = threading.Thread(target=self._supervise, name="supervisor", daemon=True)
        self.on_supervisor_end: Callable[[], None] = lambda: None  # main's wake-up: the thread has ended
        self._watcher = ControllerWatcher(self._stream_snapshot, self.events.put, self.log, self._stopped,
                                          self.report_error)
        self.watch = ForeignCommandWatch(rospy.get_caller_id(), self.events.put, self.clock, self.report_error,
                                         self._watcher.status_seen)

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
        switch = SubscriptionSwitch(self._subscribe_joint_states, self._subscribe_joint_states(), self.report_error,
                                    JOINT_STATES_TOPIC)
        self.joint_state_feed = JointStateFeed(self.joint_states, switch, rospy.logdebug)
        self._joint_state_switch = switch
        switch.thread.start()
        self._rehearse(config, topics)
        self._expected = (config, topics)
        self._supervisor.start()
        self._watcher.thread.start()
        self._publish_status()
        self.services.advertise()
        rospy.Timer(rospy.Duration(HEARTBEAT_PERIOD), self._heartbeat)

    def _subscribe_joint_states(self):
        # rospy hands over every message of a batched read (up to the cache's), so its counts are the messages'.
        return rospy.Subscriber(JOINT_STATES_TOPIC, rospy.AnyMsg, self.joint_states.receive, queue_size=RAW_KEPT)

    def _rehearse(self, config: Configuration, topics: Dict[str, str]) -> None:
        self.rng = make_rng(config.random_seed)
        style = MotionStyle(config, self.rng)
        for motion in animated_parts(config, [key for key in topics if key in PARTS]):
            rehearse(motion.part, style.planner(motion))

    @staticmethod
    def apply_verbosity(config: Configuration) -> None:
        logging.getLogger("rosout").setLevel(logging.DEBUG if config.verbose_mode else logging.INFO)

    def _heartbeat(self, _event) -> None:
        rospy.loginfo("%s: running.", NODE_NAME)

    def request_shutdown(self, reason: str) -> None:
        """Stops the robot as `disabled` does and ends the supervisor (waits at most 1 s)."""
        if not self.supervisor_alive():
            self._stopped.set()
            return
        done = threading.Event()
        self.events.put(Shutdown(reason, done))
        done.wait(1.0)

    @property
    def stopped(self) -> bool:
        return self._stopped.is_set()

    def supervisor_alive(self) -> bool:
        return self._supervisor.is_alive()

    def stop_without_supervisor(self) -> None:
        """The last resort when the supervisor thread has ended: cancel every goal, stop the base."""
        for stream in self._stream_snapshot():
            try:
                stream.disable(home=False)
            except Exception as error:  # the other parts must still be stopped
                self.report_error(stream.part, error)
        if self.active_base is not None:
            try:
                self.active_base.stop(False, self.clock(), self.log)
            except Exception as error:
                self.report_error(WHEELS_KEY, error)

    # -- supervisor thread: the only owner of the motion state -----------------------------------
    def _supervise(self) -> None:
        try:
            self._run()
        finally:
            self.on_supervisor_end()

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
                self._update_joint_state_feed()
                if self.events.empty():  # nothing waits: build what the next commands need
                    for stream in self.parts.values():
                        stream.prepare()
                    self._prepare_first_goals()
            except Exception as error:  # the supervisor must survive anything a callback brings
                self.report_error("supervisor", error)
            if isinstance(event, Shutdown):
                event.done.set()
                self._stopped.set()

    def _next_timeout(self) -> Optional[float]:
        now = self.clock()
        deadlines = [deadline - now for deadline in (stream.next_deadline() for stream in self.parts.values())
                     if deadline is not None]
        deadlines += [deadline - now for deadline in (base.next_deadline(now) for base in self.bases.values())
                      if deadline is not None]
        if not deadlines and not self.enabled and self.joint_state_feed.state == FeedState.RESTING:
            return None  # at rest nothing is due until an event comes: no wake-ups while nothing moves
        return min([0.5] + [max(0.0, deadline) for deadline in deadlines])

    def _handle(self, event) -> None:
        if isinstance(event, Enable):
            self._enable(event.config_file, event.config, event.topics)
            event.done.set()
        elif isinstance(event, Disable):
            was_enabled = self._disable()
            event.done.set()  # the robot is told to stop: the caller's reply need not wait for the lines below
            self._report_disabled(was_enabled, event.reason)
        elif isinstance(event, Shutdown):
            self._report_disabled(self._disable(), event.reason)
        elif isinstance(event, GoalDone):
            stream = self.parts.get(event.action)
            if stream is not None:
                stream.goal_done(event)
        elif isinstance(event, ControllerConnected):
            self.joint_state_feed.listen("controller %s connected" % event.action)
            self.parts[event.action].controller_connected()
        elif isinstance(event, ControllerLost):
            self.joint_state_feed.listen("controller %s lost" % event.action)
            self.parts[event.action].controller_lost()
        elif isinstance(event, ForeignGoal):
            self.parts[event.action].foreign_motion(event.goal_id, event.caller, GOAL, event.last_point_at)
        elif isinstance(event, ForeignResult):
            self.parts[event.action].foreign_result(event.goal_id)
        elif isinstance(event, ForeignCommand):
            self.parts[event.action].foreign_command(event.caller, event.last_point_at)
        elif isinstance(event, ForeignTwist):
            self.bases[event.topic].foreign_twist(event.caller, event.twist, self.clock(), self.log)

    def _tick(self) -> None:
        for stream in list(self.parts.values()):
            stream.tick()
        now = self.clock()
        for base in self.bases.values():
            base.tick(now, self.log)

    def _update_joint_state_feed(self) -> None:
        """/joint_states is listened to while the joints may move (node/joint_state_feed.py)."""
        now = self.clock()
        streams = self._stream_snapshot()
        busy = self._why_joints_may_move(streams, now)
        measured = busy is None and self.joint_states.complete(
            [joint for stream in streams for joint in PARTS[stream.part].joints])
        self.joint_state_feed.update(busy, measured, now)
        self._joint_state_batching.update(subscription_connections(self._joint_state_switch.subscription), now)

    def _why_joints_may_move(self, streams: List[PartStream], now: float) -> Optional[str]:
        if self.enabled:
            return "enabled"
        for stream in streams:
            if stream.active:
                return "%s %s" % (stream.part, stream.state.value)
            if not stream.foreign.calm(now):
                return "another node moves %s" % stream.part
        return None

    def _prepare_first_goals(self) -> None:
        if self.enabled or self._expected is None or (self._prepared is not None and self._prepared.fits(self.parts)):
            return
        self._prepared = prepare_enable(*self._expected, self.rng, self.parts)
        if self._prepared is not None:
            self.rng = self._prepared.rng
            rospy.logdebug("%s: first goals of the next enable planned (%s).", NODE_NAME,
                           ", ".join(sorted(self._prepared.goals)))

    def _enable(self, config_file: str, config: Configuration, topics: Dict[str, str]) -> None:
        reconfigured = self.enabled
        prepared, self._prepared = self._prepared, None
        if prepared is None or reconfigured or not prepared.matches(config, topics):
            prepared = None
            if config.random_seed is not None or self.rng is None or reconfigured:
                self.rng = make_rng(config.random_seed)
        self._expected = (config, topics)
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
        style = MotionStyle(config, self.rng) if prepared is None else prepared.style
        for key, motion in motions.items():  # the goals first: console lines take milliseconds each
            planner, first = prepared.goals[key] if prepared is not None else (style.planner(motion), None)
            self._stream_for(key, topics[key]).enable(motion, planner, config.yield_quiet_time, first)
        wheels = topics.get(WHEELS_KEY) if "rotation" in config.behaviour else None
        if self.active_base is not None and self.active_base.topic != wheels:
            self.active_base.stop(config.home_on_disable, self.clock(), self.log)
            self.active_base = None
        if wheels is not None:
            self.active_base = self._base_for(wheels)
            self.active_base.start(config, style, self.rng, self.clock(), self.log)
        self.enabled = True
        self.log.write(contract.BEHAVIOUR_STARTED, behaviour=sorted(config.behaviour),
                       platform=config.platform, parts=sorted(motions), wheels=wheels,
                       reconfigured=reconfigured)
        rospy.loginfo("%s: animating %s.", NODE_NAME, ", ".join(sorted(motions) + ([WHEELS_KEY] if wheels else [])))
        # Once per configuration, not at every enable: the same lines again and again say nothing new.
        warnings = narrow_bands(list(motions.values()), DRIVER_JOINT_PRECISION) if config.platform == "robot" else []
        if warnings != self._band_warnings:
            for line in warnings:
                rospy.logwarn("%s: %s.", NODE_NAME, line)
            self._band_warnings = warnings

    def _disable(self) -> bool:
        """Stops every part and the base; False when the node was not enabled."""
        if not self.enabled:
            return False
        home = self.config.home_on_disable
        if self.active_base is not None:  # first: a streamed turn ends with one zero Twist, sent at once
            self.active_base.stop(home, self.clock(), self.log)
            self.active_base = None
        streams = list(self.parts.values())
        # Every part's return goal is planned before the first one leaves: once a goal is on the wire, the
        # controller's replies (status, the replaced goal's result) come in, and their threads would take turns
        # with the planning of the other parts.
        planned = [stream.plan_stop(home) for stream in streams]
        for stream, goal in zip(streams, planned):
            stream.disable(home, goal)
        self.enabled = False
        return True

    def _report_disabled(self, was_enabled: bool, reason: str) -> None:
        if was_enabled:
            self.log.write(contract.BEHAVIOUR_ENDED, reason=reason, home=self.config.home_on_disable)
            rospy.loginfo("%s: stopped (%s).", NODE_NAME, reason)

    def _stream_for(self, part: str, action: str) -> PartStream:
        with self._parts_lock:
            if action not in self.parts:
                self.parts[action] = PartStream(part, action, action_client(action), self.clock,
                                                self.joint_states.positions, self.events.put, self.log)
                self.watch.watch_controller(action)
            return self.parts[action]

    def report_error(self, where: str, error: Exception) -> None:
        """An unexpected error in a thread of the node: one line on the console and in the log; the thread goes on."""
        rospy.logerr("%s: %s: %s: %s", NODE_NAME, where, type(error).__name__, error)
        self.log.write(contract.ERROR, where=where, message="{}: {}".format(type(error).__name__, error))

    def report_problem(self, where: str, text: str) -> None:
        """Bad input from outside (README: "Faults"): one line on the console and in the log."""
        rospy.logwarn("%s: %s", NODE_NAME, text)
        self.log.write(contract.ERROR, where=where, message=text)

    def _stream_snapshot(self) -> List[PartStream]:
        with self._parts_lock:
            return list(self.parts.values())

    def _base_for(self, topic: str) -> BaseStream:
        if topic not in self.bases:
            self.bases[topic] = BaseStream(topic)
            self.watch.watch_base(topic)
        return self.bases[topic]

    def _publish_status(self) -> None:
        self.status.publish(self.enabled, self._stream_snapshot(), list(self.bases.values()))
