"""The supervisor: the one thread that owns the motion state.

The services, the action clients' callbacks, the controller watcher, the watch on other nodes and the signal
handlers only post events (core/events.py) to its queue; it applies them to the part streams (core/part_stream.py,
core/joint_angle_stream.py) and the base stream (core/base_stream.py), runs what is due in time, and publishes the
status. It does no ROS communication of its own: the front-end (ros1/animate_behaviour_node.py on ROS 1,
ros2/animate_behaviour_node.py on ROS 2) injects the streams' factories, the clock and the publishers, so unit
tests drive it with fakes.
"""
import queue
import threading
from typing import Callable, Dict, List, Optional, Tuple

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import (AUTO_MODE, TRAJECTORY_ACTUATION, Configuration,
                                                         configuration_items)
from cssr_system.animate_behaviour.console import console, set_verbose
from cssr_system.animate_behaviour.contract import NODE_NAME
from cssr_system.animate_behaviour.live_settings import changed_settings
from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.core.base_stream import BaseStream
from cssr_system.core.conversation import Conversation, ModeChange
from cssr_system.core.events import (AnimateCancel, AnimateGoal, ControllerConnected, ControllerLost,
                                     ConversationHeard, ConversationPresent, Disable, Enable, ForeignCommand,
                                     ForeignGoal, ForeignJointAngles, ForeignResult, ForeignTwist, GoalDone,
                                     Reconfigure, Shutdown)
from cssr_system.core.foreign_motion import GOAL, JOINT_ANGLES
from cssr_system.core.joint_states import FeedState
from cssr_system.core.motion_stream import StreamState
from cssr_system.core.part_stream import PartStream
from cssr_system.core.session import CANCELLED, DISABLED, DURATION_ELAPSED, HOMED, REPLACED, Session, starts_return
from cssr_system.core.status import part_rows
from cssr_system.figure.clearance import close_hand_warnings
from cssr_system.motion.modes import IDLE, shaped_motions, turns_base
from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.waypoints import animated_parts, make_rng, narrow_bands
from cssr_system.pepper.joint_table import DRIVER_JOINT_PRECISION, PARTS

# A part or the base in these states is still to be stopped at the end of an animate goal's duration.
MOVING_STATES = (StreamState.ANIMATING, StreamState.WAITING, StreamState.YIELDING)
LONGEST_WAIT = 0.5  # s the supervisor sleeps at most while anything may be due
# A goal's end judged from the measured joints (core/part_stream.py: an abort for the end state only) waits this long
# at most for a current measurement, looking every JUDGE_POLL s: the feed subscribes, and its first message comes well
# within it.
JUDGE_WAIT = 0.5  # s
JUDGE_POLL = 0.02  # s


def judging_reason(event: GoalDone) -> str:
    """Why /joint_states is listened to while a goal's end waits for a measurement."""
    return "judging the end of %s goal %d" % (event.part, event.goal_number)


class Supervisor:
    """Owns the streams and the event loop.

    `clock`: the clock the controllers execute goals on; `log`: the event log; `make_part(part, action)` and
    `make_base(topic)`: new streams (with their clients and watches); `publish_status(enabled, parts, bases)`;
    `feed`: whether /joint_states is listened to (core/joint_states.py);
    `report_error(where, error)`: an unexpected error, in one line; `action`: the front-end's animate action server,
    which ends the action's goals and publishes their feedback (`accept`, `succeed`, `stop`, `feedback`);
    `sync_settings(config)`: tells the front-end's live settings (dynamic_reconfigure, ROS 2 parameters) the
    settings a service or the action brought."""

    def __init__(self, clock: Callable[[], float], log, make_part: Callable[[str, str], PartStream],
                 make_base: Callable[[str], BaseStream], publish_status: Callable[..., None], feed,
                 report_error: Callable[[str, Exception], None], action=None,
                 sync_settings: Callable[[Configuration], None] = lambda config: None,
                 sends_on_another_thread: bool = False) -> None:
        self.events: "queue.Queue" = queue.Queue()
        # True: a client's send only hands the goal over to a thread that sends it (ROS 2's executor thread).
        self._sends_on_another_thread = sends_on_another_thread
        self.clock = clock
        self.log = log
        self._make_part = make_part
        self._make_base = make_base
        self._publish_status = publish_status
        self._feed = feed
        self._report_error = report_error
        self._action = action
        self._sync_settings = sync_settings
        self.session: Optional[Session] = None  # the animate action's goal in force
        self.settings_by = "configuration"  # who set the live settings in force
        self.actuation = TRAJECTORY_ACTUATION  # the configuration's actuation at start-up, which made the part streams
        self.parts: Dict[str, PartStream] = {}  # by action namespace: one client each, kept for life
        self._parts_lock = threading.Lock()  # the watcher reads `parts` while the supervisor adds
        self.bases: Dict[str, BaseStream] = {}
        self.active_base: Optional[BaseStream] = None
        self.enabled = False
        self.config: Optional[Configuration] = None
        self._config_file, self._topics = "", {}  # of the configuration in force: a mode switch enables them again
        # The mode in force and the sources of the conversation (core/conversation.py; README: "Modes").
        self.conversation = Conversation()
        self.rng = None
        self._band_warnings: List[str] = []  # the robot driver's dead band: what the console last said
        self._judging: List[Tuple[float, GoalDone]] = []  # ends waiting for a measurement, with their deadlines
        self.stopped = threading.Event()
        self.on_end: Callable[[], None] = lambda: None  # told when the thread ends
        self.thread = threading.Thread(target=self._supervise, name="supervisor", daemon=True)
        self._handlers = {Enable: self._on_enable, Disable: self._on_disable, Shutdown: self._on_shutdown,
                          GoalDone: self._on_goal_done, ControllerConnected: self._on_controller_connected,
                          ControllerLost: self._on_controller_lost, ForeignGoal: self._on_foreign_goal,
                          ForeignResult: self._on_foreign_result, ForeignCommand: self._on_foreign_command,
                          ForeignTwist: self._on_foreign_twist, Reconfigure: self._on_reconfigure,
                          ForeignJointAngles: self._on_foreign_joint_angles,
                          AnimateGoal: self._on_animate_goal, AnimateCancel: self._on_animate_cancel,
                          ConversationHeard: self._on_conversation_heard,
                          ConversationPresent: self._on_conversation_present}

    # -- start-up -----------------------------------------------------------------------------------
    def set_up(self, config: Configuration, topics: Dict[str, str], sources=()) -> None:
        """Before the thread starts: a stream for every part and the base that `topics` names (their clients and
        publishers connect while the node is still disabled, so the first commands leave at once and none is lost
        to a connection not yet made), the console's verbosity and configuration lines, and the conversation's
        `sources` ((key, resolved name, means) of each the front-end watches)."""
        self.conversation = Conversation(sources, config.conversation_timeout, config.mode)
        for key, name in topics.items():
            if key in PARTS:
                self.stream_for(key, name)
            elif key == WHEELS_KEY:
                self.base_for(name)
        set_verbose(config.verbose_mode)
        for key, value in configuration_items(config).items():
            console.info("%s: %-18s %s", NODE_NAME, key, value)
        # Before the node serves anyone: the check takes a few tenths of a second (README: "See Pepper move").
        for line in close_hand_warnings(config):
            console.warning("%s: %s.", NODE_NAME, line)
        self.config = config

    def start(self) -> None:
        """Publishes the status (disabled), then runs the event loop on its thread."""
        self._publish_status(False, self.part_streams(), list(self.bases.values()), self.config, self.settings_by,
                             self.conversation.mode, self.conversation.by)
        self.thread.start()

    # -- streams ------------------------------------------------------------------------------------
    def stream_for(self, part: str, action: str) -> PartStream:
        with self._parts_lock:
            if action not in self.parts:
                self.parts[action] = self._make_part(part, action)
            return self.parts[action]

    def base_for(self, topic: str) -> BaseStream:
        with self._parts_lock:
            if topic not in self.bases:
                self.bases[topic] = self._make_base(topic)
            return self.bases[topic]

    def part_streams(self) -> List[PartStream]:
        """A snapshot of the part streams, from any thread."""
        with self._parts_lock:
            return list(self.parts.values())

    def controlled_streams(self) -> list:
        """A snapshot of the part streams and the base streams, from any thread: what the controller watcher
        watches (a controller, naoqi_driver's topic, a Wheels topic listened to)."""
        with self._parts_lock:
            return list(self.parts.values()) + list(self.bases.values())

    # -- the thread ---------------------------------------------------------------------------------
    def _supervise(self) -> None:
        try:
            while not self.stopped.is_set():
                self.step(self._next_timeout())
        finally:
            self.on_end()

    def step(self, timeout: Optional[float]) -> None:
        """Handles the next event (waiting at most `timeout` s for it), then whatever is due."""
        try:
            event = self.events.get(timeout=timeout)
        except queue.Empty:
            event = None
        try:
            if event is not None:
                self._handlers[type(event)](event)
            self._tick()
            self._publish_status(self.enabled, self.part_streams(), list(self.bases.values()), self.config,
                                 self.settings_by, self.conversation.mode, self.conversation.by)
            self._update_feed()
            if self.events.empty():  # nothing waits: what the next goal or a stop starts from, built now
                for stream in self.part_streams():
                    stream.prepare()
        except Exception as error:  # the supervisor must survive anything a callback brings
            self._report_error("supervisor", error)
        if isinstance(event, Shutdown):
            event.done.set()
            self.stopped.set()

    def _next_timeout(self) -> Optional[float]:
        now = self.clock()
        deadlines = [stream.next_deadline() for stream in self.parts.values()]
        deadlines += [base.next_deadline(now) for base in self.bases.values()]
        deadlines += [self.session.next_deadline(now)] if self.session is not None else []
        deadlines += [now + JUDGE_POLL] if self._judging else []
        deadlines += [self.conversation.next_deadline()]
        deadlines = [deadline - now for deadline in deadlines if deadline is not None]
        if not deadlines and not self.enabled and self._feed.state == FeedState.RESTING:
            return None  # at rest nothing is due until an event comes: no wake-ups while nothing moves
        return min([LONGEST_WAIT] + [max(0.0, deadline) for deadline in deadlines])

    def _tick(self) -> None:
        self._hand_over_judged_ends(self.clock())
        for stream in list(self.parts.values()):
            stream.tick()
        now = self.clock()
        for base in self.bases.values():
            base.tick(now)
        if self.session is not None:
            self._tick_session(now)
        self._follow(self.conversation.look(now))  # a source's time-out

    def _update_feed(self) -> None:
        """/joint_states is listened to while a decision needs the measured joints (core/joint_states.py)."""
        streams, now = self.part_streams(), self.clock()
        still = [joint for stream in streams if not (stream.active and stream.drives_joints)
                 for joint in PARTS[stream.part].joints]
        self._feed.update(self._why_measurements_are_needed(streams, now), still, now)

    def _why_measurements_are_needed(self, streams: List[PartStream], now: float) -> Optional[str]:
        """Why a decision needs the measured joints now (None: none does)."""
        if self._judging:
            return judging_reason(self._judging[0][1])
        for stream in streams:
            if stream.active and stream.needs_measurements():
                return "%s %s" % (stream.part, stream.state.value)
            if not stream.foreign.calm(now):
                return "another node moves %s" % stream.part
        return None

    def _hand_over_judged_ends(self, now: float, at_exit: bool = False) -> None:
        """Hands each goal end that waits for a measurement to its stream once one is current, or its wait is over."""
        waiting = []
        for deadline, event in self._judging:
            stream = self.parts[event.action]
            if at_exit or now >= deadline or stream.measured_positions() is not None:
                stream.goal_done(event)
            else:
                waiting.append((deadline, event))
        self._judging = waiting

    # -- events -------------------------------------------------------------------------------------
    def _on_enable(self, event: Enable) -> None:
        self._set_mode(event.config, "configuration")  # every enable starts from the configuration again
        self._enable(event.config_file, event.config, event.topics, "setActivation")
        event.done.set()
        self._end_session(REPLACED, "setActivation")
        self._sync_settings(event.config)

    def _on_disable(self, event: Disable) -> None:
        was_enabled = self._disable()
        event.done.set()  # the robot is told to stop: the caller's reply need not wait for the lines below
        self._report_disabled(was_enabled, event.reason)
        self._end_session(event.reason, event.by)

    def _on_shutdown(self, event: Shutdown) -> None:
        """Stops the robot; then every goal still running gets its final line (RUNNING_AT_EXIT): the node exits
        before their results come."""
        self._report_disabled(self._disable(), event.reason)
        self._end_session(DISABLED, event.reason)
        self._hand_over_judged_ends(self.clock(), at_exit=True)
        for stream in self.part_streams():
            stream.finish_at_exit()

    def _on_reconfigure(self, event: Reconfigure) -> None:
        """Live settings changed: applied at once while enabled (a stream's new goal splices onto its motion),
        kept for the next enable otherwise. The mode setting changes only where the change sets it."""
        sets_mode = "mode" in event.changed if event.changed is not None else \
            event.config.mode != self.conversation.setting
        config = self._set_mode(event.config, event.by) if sets_mode else self._keep_mode(event.config)
        if self.enabled:
            self._enable(event.config_file, config, event.topics, event.by)
        else:
            self._log_settings(config, event.by)
            self.config, self._config_file, self._topics = config, event.config_file, event.topics

    # -- the animate action -------------------------------------------------------------------------
    def _on_animate_goal(self, event: AnimateGoal) -> None:
        self._end_session(REPLACED, event.by)
        server = event.server or self._action
        server.accept(event.handle)
        self.session = Session(event.handle, self.clock(), event.duration, server, event.by, event.home,
                               self._motions_completed())
        self.log.write(contract.ANIMATE_GOAL, outcome="accepted", by=event.by, duration=event.duration,
                       **({"home": True} if event.home else {}))
        config = self._set_mode(event.config, event.by) if event.sets_mode else self._keep_mode(event.config)
        if event.home:
            self._home_every_part()
        else:
            self._enable(event.config_file, config, event.topics, event.by)
        self._sync_settings(config)

    def _on_animate_cancel(self, event: AnimateCancel) -> None:
        if self.session is None or self.session.handle != event.handle:
            return  # a goal that has ended already (replaced, say)
        self._report_disabled(self._disable(), CANCELLED)
        self._end_session(CANCELLED, self.session.by)

    def _tick_session(self, now: float) -> None:
        session = self.session
        if session.returns_due(now):
            self._return_in_time(session, now)
        if session.succeeds(now, any(stream.active for stream in self.controlled_streams())):
            self._end_session(HOMED if session.home else DURATION_ELAPSED, session.by)
        elif session.feedback_due(now):
            session.server.feedback(session.handle, now - session.started,
                                    part_rows(self.part_streams(), list(self.bases.values())),
                                    self._motions_completed() - session.motions_before)

    def _return_in_time(self, session: Session, now: float) -> None:
        """In the last seconds of a goal with a duration, each part (and the base) starts back to its centre when
        its own return, planned from where it is now, needs to; once all have, the node is disabled."""
        home = self.config.home_on_disable
        for stream in self.part_streams():
            if stream.state in MOVING_STATES:
                planned = stream.plan_stop(home)
                if starts_return(now, stream.return_duration(planned), session.ends_at):
                    stream.disable(home, planned)
        base = self.active_base
        if base is not None and starts_return(now, base.return_duration(now) if home else 0.0, session.ends_at):
            base.stop(home, now)
            self.active_base = None
        if self.active_base is None and not any(stream.state in MOVING_STATES for stream in self.part_streams()):
            session.homing = True
            self._report_disabled(self._disable(), DURATION_ELAPSED)

    def _home_every_part(self) -> None:
        """A home goal: what moves returns to its centre, and every other part too, from where it is (not while
        another node moves it)."""
        self._report_disabled(self._disable(home=True), HOMED)
        for stream in self.part_streams():
            stream.go_home()

    def _motions_completed(self) -> int:
        return sum(stream.motions_completed for stream in self.part_streams())

    def _end_session(self, reason: str, by: str) -> None:
        """The action's goal in force, if any, ends: SUCCEEDED when its duration elapsed (or a home goal's parts are
        back), else PREEMPTED; `by`: who ended it."""
        session, self.session = self.session, None
        if session is None:
            return
        animated = max(0.0, self.clock() - session.started)
        succeeded = reason in (DURATION_ELAPSED, HOMED)
        (session.server.succeed if succeeded else session.server.stop)(session.handle, animated, reason)
        self.log.write(contract.ANIMATE_GOAL, outcome="succeeded" if succeeded else "preempted",
                       animated=round(animated, 3), reason=reason, by=by)

    def _on_goal_done(self, event: GoalDone) -> None:
        stream = self.parts.get(event.action)
        if stream is None:
            return
        if stream.end_needs_measurement(event):  # measured first (core/joint_states.py), then judged
            self._judging.append((self.clock() + JUDGE_WAIT, event))
            self._feed.listen(judging_reason(event))
            return
        stream.goal_done(event)

    def _on_controller_connected(self, event: ControllerConnected) -> None:
        if event.action in self.bases:
            self.bases[event.action].controller_connected()
            return
        self._feed.listen("controller %s connected" % event.action)
        self.parts[event.action].controller_connected()

    def _on_controller_lost(self, event: ControllerLost) -> None:
        if event.action in self.bases:
            self.bases[event.action].controller_lost()
            return
        self._feed.listen("controller %s lost" % event.action)
        self.parts[event.action].controller_lost()

    def _on_foreign_goal(self, event: ForeignGoal) -> None:
        self.parts[event.action].foreign_motion(event.goal_id, event.caller, GOAL, event.last_point_at)

    def _on_foreign_result(self, event: ForeignResult) -> None:
        self.parts[event.action].foreign_result(event.goal_id)

    def _on_foreign_command(self, event: ForeignCommand) -> None:
        self.parts[event.action].foreign_command(event.caller, event.last_point_at)

    def _on_foreign_joint_angles(self, event: ForeignJointAngles) -> None:
        """Another node's setAngles call: each part with a joint it names yields (one motion per caller and joints:
        a later call on the same joints takes over, as setAngles does)."""
        key = "%s:%s" % (event.caller, ",".join(event.joints))
        for stream in list(self.parts.values()):
            if set(event.joints) & set(PARTS[stream.part].joints):
                stream.foreign_command(event.caller, event.last_point_at, JOINT_ANGLES, key)

    def _on_foreign_twist(self, event: ForeignTwist) -> None:
        self.bases[event.topic].foreign_twist(event.caller, event.twist, self.clock())

    # -- the conversation ----------------------------------------------------------------------------
    def _on_conversation_heard(self, event: ConversationHeard) -> None:
        self._follow(self.conversation.heard(event.source, event.active, self.clock()))

    def _on_conversation_present(self, event: ConversationPresent) -> None:
        self._follow(self.conversation.present(event.source, self.clock()))

    def _set_mode(self, config: Configuration, by: str) -> Configuration:
        """The mode setting of `config`, set by `by`: the mode in force changes with it (applied by the caller)."""
        self.conversation.timeout = config.conversation_timeout
        self._note_mode(self.conversation.set_mode(config.mode, by, self.clock()))
        return config

    def _keep_mode(self, config: Configuration) -> Configuration:
        """`config` with the mode setting in force (a change of other settings leaves the mode alone)."""
        self.conversation.timeout = config.conversation_timeout
        return config._replace(mode=self.conversation.setting)

    def _note_mode(self, change: Optional[ModeChange]) -> None:
        """A change of the mode in force: one mode_changed line and a console line."""
        if change is None:
            return
        self.log.write(contract.MODE_CHANGED, mode=change.new, old=change.old, by=change.by, setting=change.setting)
        console.info("%s: mode %s -> %s (%s).", NODE_NAME, change.old, change.new, change.by)

    def _follow(self, change: Optional[ModeChange]) -> None:
        """The conversation changed the mode in force: a mode set by hand is back to auto (shown as such), and an
        enabled node's parts splice onto the new mode's motion, as at a live change."""
        if change is None:
            return
        self._note_mode(change)
        if self.config is not None and self.config.mode != AUTO_MODE:
            self.config = self.config._replace(mode=AUTO_MODE)
            self._sync_settings(self.config)
        if self.enabled and not (self.session is not None and self.session.homing):
            self._enable(self._config_file, self.config, self._topics, self.settings_by)

    # -- enable and disable -------------------------------------------------------------------------
    def _log_settings(self, config: Configuration, by: str) -> None:
        """Each live setting that `config` changes: one setting_changed line, with who asked."""
        if self.config is not None:
            for key, old, new in changed_settings(self.config, config):
                self.log.write(contract.SETTING_CHANGED, key=key, old=old, new=new, by=by)
                console.info("%s: %s %s -> %s (%s).", NODE_NAME, key, old, new, by)
        self.settings_by = by

    def _enable(self, config_file: str, config: Configuration, topics: Dict[str, str], by: str) -> None:
        reconfigured = self.enabled
        if config.random_seed is not None or self.rng is None or reconfigured:
            self.rng = make_rng(config.random_seed)
        self._log_settings(config, by)
        self.config, self._config_file, self._topics = config, config_file, topics
        mode = self.conversation.mode
        set_verbose(config.verbose_mode)
        self._warn_actuation(config)
        self.log.write(contract.CONFIGURATION_LOADED, file=config_file, items=configuration_items(config))
        motions = {motion.part: motion for motion in shaped_motions(
            animated_parts(config, [key for key in topics if key in PARTS]), config, mode)}
        # Parts that no longer move (new behaviour or platform) go home as on disable.
        for stream in list(self.parts.values()):
            if stream.active and (stream.part not in motions or stream.action != topics.get(stream.part)):
                stream.disable(config.home_on_disable)
        style = MotionStyle(config, self.rng, mode)
        # The goals first (console lines take milliseconds each). Sent from this thread, each is planned before the
        # first one leaves, as at a disable: once a goal is on the wire, the controllers' replies come in and their
        # threads take turns with the planning of the other parts. Handed over to a thread that sends them, each goes
        # at once: its controller takes it on while the next part is planned. Planner, then plan, part by part: the
        # breathing style draws from `rng` as it makes its planners, so a seeded run's goals stay the same.
        starting = []
        for key, motion in motions.items():
            stream, plan = self.stream_for(key, topics[key]), style.planner(motion)
            starting.append((stream, motion, plan, stream.plan_start(plan, config.yield_quiet_time)))
            if self._sends_on_another_thread:
                self._start_parts(starting, config)
        self._start_parts(starting, config)
        wheels = self._start_base(config, topics, style)
        self.enabled = True
        self.log.write(contract.BEHAVIOUR_STARTED, behaviour=sorted(config.behaviour), platform=config.platform,
                       parts=sorted(motions), wheels=wheels, reconfigured=reconfigured, mode=mode)
        console.info("%s: animating %s.", NODE_NAME, ", ".join(sorted(motions) + ([WHEELS_KEY] if wheels else [])))
        if mode == IDLE:  # the configuration's bands; listening's are narrow by design (README: "Modes")
            self._warn_narrow_bands(config, list(motions.values()))

    @staticmethod
    def _start_parts(starting: list, config: Configuration) -> None:
        """Sends each planned first goal of `starting` (stream, motion, plan, goal) and empties it."""
        for stream, motion, plan, planned in starting:
            stream.enable(motion, plan, config.yield_quiet_time, planned)
        starting.clear()

    def _start_base(self, config: Configuration, topics: Dict[str, str], style: MotionStyle) -> Optional[str]:
        """Starts (or keeps) the base turning when the behaviour asks for rotation and the mode lets it; its topic, or
        None."""
        rotation = "rotation" in config.behaviour and config.turn_base
        turns = rotation and turns_base(style.mode)
        wheels = topics.get(WHEELS_KEY) if turns else None
        if self.active_base is not None and self.active_base.topic != wheels:
            if rotation and self.active_base.topic == topics.get(WHEELS_KEY):
                # Listening or speaking: stopped where it is, kept in its frame of enable (idle goes on in it, a
                # disable turns it back).
                self.active_base.park(self.clock())
                return None
            # Switched off, the base stops where it is; a new platform's returns as on disable.
            self.active_base.stop(config.home_on_disable and turns, self.clock())
            self.active_base = None
        if wheels is not None:
            self.active_base = self.base_for(wheels)
            self.active_base.start(config, style, self.rng, self.clock())
        return wheels

    def _warn_actuation(self, config: Configuration) -> None:
        """The streams were made for the actuation of start-up (`actuation`): another one needs a restart."""
        if config.actuation != self.actuation:
            console.warning("%s: actuation %s is read at start-up only: this node goes on with %s.", NODE_NAME,
                            config.actuation, self.actuation)

    def _warn_narrow_bands(self, config: Configuration, motions: list) -> None:
        """Once per configuration, not at every enable: the same lines again and again say nothing new. Only for
        pepper_dcm's goals: naoqi_driver's setAngles has no dead band."""
        dead_band = config.platform == "robot" and self.actuation == TRAJECTORY_ACTUATION
        warnings = narrow_bands(motions, DRIVER_JOINT_PRECISION) if dead_band else []
        if warnings != self._band_warnings:
            for line in warnings:
                console.warning("%s: %s.", NODE_NAME, line)
            self._band_warnings = warnings

    def _disable(self, home: Optional[bool] = None) -> bool:
        """Stops every part and the base, returning them home as `home` says (None: as the configuration says);
        False when the node was not enabled."""
        if not self.enabled:
            return False
        home = self.config.home_on_disable if home is None else home
        if self.active_base is not None:  # first: a streamed turn ends with one zero Twist, sent at once
            self.active_base.stop(home, self.clock())
            self.active_base = None
        streams = list(self.parts.values())
        # Every part's return goal is planned before the first one leaves: once a goal is on the wire, the
        # controller's replies come in, and their threads would take turns with the planning of the other parts.
        planned = [stream.plan_stop(home) for stream in streams]
        for stream, goal in zip(streams, planned):
            stream.disable(home, goal)
        self.enabled = False
        return True

    def _report_disabled(self, was_enabled: bool, reason: str) -> None:
        if was_enabled:
            self.log.write(contract.BEHAVIOUR_ENDED, reason=reason, home=self.config.home_on_disable)
            console.info("%s: stopped (%s).", NODE_NAME, reason)

    def stop_without_thread(self) -> None:
        """The last resort when the supervisor thread has ended: cancel every goal, stop the base."""
        for stream in self.part_streams():
            try:
                stream.disable(home=False)
            except Exception as error:  # the other parts must still be stopped
                self._report_error(stream.part, error)
        if self.active_base is not None:
            try:
                self.active_base.stop(False, self.clock())
            except Exception as error:
                self._report_error(WHEELS_KEY, error)
