"""What the part streams (core/part_stream.py) and the base stream (core/base_stream.py) share: their states, one
transition helper, and yielding to another node (README: "Status", "Sharing the robot").

States: ``idle`` (nothing of ours runs), ``animating``, ``yielding`` (another node moves it: we send nothing until
its motion has ended and the quiet time has passed), ``waiting`` (parts only: enabled, but waiting for the
controller or for a retry), ``homing`` (the return to the centre, or to the heading of enable, after a disable).
The status topic names them so. Every change goes through `transition_to`, which checks it against the stream's
table of transitions and logs ``old -> new`` at debug level.
"""
import enum
from typing import Callable, Dict, Optional, Set

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.contract import NODE_NAME
from cssr_system.core.foreign_motion import COMMAND, DEFAULT_QUIET_TIME, ForeignMotionTracker


class StreamState(enum.Enum):
    IDLE = "idle"
    ANIMATING = "animating"
    YIELDING = "yielding"
    WAITING = "waiting"
    HOMING = "homing"


class MotionStream:
    """A state machine over `StreamState` (`transitions`: the allowed changes) that yields to other nodes.

    `name`: the part key (or the wheels key); `controller`: its action namespace or topic; `log`: the event log;
    `debug`: console lines at debug level."""

    def __init__(self, name: str, controller: str, transitions: Dict[StreamState, Set[StreamState]], log,
                 debug: Callable[..., None]) -> None:
        self.name = name
        self.controller = controller
        self.state = StreamState.IDLE
        self.connected = False  # its controller (or its topic's listener) is there, as the controller watcher says
        self.foreign = ForeignMotionTracker()  # other nodes' motion on this controller or topic
        self.yielding_to = ""  # the caller id of the node we yield to
        self._transitions = transitions
        self._log = log
        self._debug = debug
        self._yield_started = 0.0
        self.motions_completed = 0  # motions of ours that played out and went on into the next (action feedback)

    @property
    def part(self) -> str:  # the part key (the wheels key for the base), as the watcher and the status name it
        return self.name

    def _connection_changed(self, connected: bool) -> bool:
        """The controller watcher says the controller (or the topic's listener) is there, or gone: False when that
        is no news; else `connected` is set and the log has its controller_connected or controller_lost line."""
        if connected == self.connected:
            return False
        self.connected = connected
        self._log.write(contract.CONTROLLER_CONNECTED if connected else contract.CONTROLLER_LOST, part=self.name,
                        action=self.controller)
        return True

    def transition_to(self, new_state: StreamState, why: str) -> None:
        if new_state not in self._transitions[self.state]:
            raise RuntimeError("%s: no transition %s -> %s (%s)" % (
                self.name, self.state.value, new_state.value, why))
        self._debug("%s: %s: %s -> %s (%s).", NODE_NAME, self.name, self.state.value, new_state.value, why)
        self.state = new_state

    def prepare(self) -> None:
        """Work for later, done while the supervisor has nothing waiting (none by default)."""

    def finish_at_exit(self) -> None:
        """The node exits: the final state of each goal still running goes to the log (no goals by default)."""

    @property
    def active(self) -> bool:
        return self.state != StreamState.IDLE

    def log_yield(self, caller: str, kind: str) -> None:
        """Another node's motion replaces ours (the log's part_yielded)."""
        self._log.write(contract.PART_YIELDED, part=self.name, controller=self.controller, caller=caller, kind=kind)

    def start_yielding(self, caller: str, now: float, why: str) -> None:
        self.yielding_to = caller
        self._yield_started = now
        self.log_yield(caller, self.foreign.kind_of_latest())
        self.transition_to(StreamState.YIELDING, why)

    def stop_yielding(self, now: float) -> str:
        """The other node is done and calm: logs the resume and says why we move again."""
        self._log.write(contract.PART_RESUMED, part=self.name, controller=self.controller, caller=self.yielding_to,
                        seconds=round(now - self._yield_started, 3))
        why = "%s done, calm for %.1f s" % (self.yielding_to, self.foreign.quiet_time)
        self.yielding_to = ""
        return why


class PartMotionStream(MotionStream):
    """A part's stream (core/part_stream.py, core/joint_angle_stream.py): how it starts, and what it does when another
    node moves the part. Subclasses give `_clock`, `_animate(why, planned=None)` (send the next motion from
    where the part is, or `planned`, made by `_plan_first`), `_yield(caller, why)` and `_abandon_home()` (our return
    to the centre is replaced by the other node's motion), and say in `not_connected` what the part waits for."""

    _command_count = 0  # numbers other nodes' command-topic trajectories
    not_connected = "controller not connected"

    @property
    def drives_joints(self) -> bool:
        """A motion of ours moves the part now: its plan, not a measurement, says where the joints are."""
        raise NotImplementedError

    def needs_measurements(self) -> bool:
        """Whether a decision needs the measured joints while the stream is active: not while a motion of ours drives
        the part (a goal that succeeds leaves the joints at its last point, a stop starts from the plan); while the
        part waits for its controller or a retry (it starts again from them) or yields, it does."""
        return not self.drives_joints

    def go_home(self) -> None:
        """A return to the centre from wherever the part is, whoever left it there (an animate goal that asks for
        the parts at their centres): only from idle, with the controller there and no other node moving the part."""
        if self.state == StreamState.IDLE and self.connected and self.foreign.calm(self._clock()):
            self._send_home()
            self.transition_to(StreamState.HOMING, "home asked")

    def _send_home(self) -> None:
        """`go_home`'s motion: one to the centre, from the measured joints."""
        raise NotImplementedError

    def _disabled_without_sending(self) -> bool:
        """What a disable does alike on every part stream: nothing, where nothing of ours runs or returns home; the
        part idle and nothing sent, where another node owns it. True when that is the whole disable."""
        if self.state in (StreamState.IDLE, StreamState.HOMING):
            return True
        if self.state == StreamState.YIELDING:
            self.yielding_to = ""
            self.transition_to(StreamState.IDLE, "disabled while yielding")
            return True
        return False

    def plan_start(self, plan, quiet_time: float = DEFAULT_QUIET_TIME):
        """The first motion `enable(motion, plan, quiet_time)` sends at once, made now without sending it (None: it
        sends none at once, or the stream makes nothing ahead)."""
        self.foreign.quiet_time = quiet_time
        return self._plan_first(plan) if self._moves_at_enable() else None

    def _moves_at_enable(self) -> bool:
        """An enable now sends a motion at once: no other node's motion to yield to, and the controller there."""
        return self.state != StreamState.YIELDING and self.connected and self.foreign.calm(self._clock())

    def _plan_first(self, plan):
        """`plan_start`'s motion (none by default: a joint-angle stream plans its first call as it streams)."""
        return None

    def enable(self, motion, plan, quiet_time: float = DEFAULT_QUIET_TIME, planned=None) -> None:
        """Animate `motion` (a motion.waypoints.PartMotion) with the motion from `plan` (a motion.planners.Planner);
        what runs goes on along the new plan. `planned`: its first motion, from `plan_start` a moment ago."""
        self.motion = motion
        self._plan = plan
        self.foreign.quiet_time = quiet_time
        if self.state == StreamState.YIELDING:
            return
        if self._moves_at_enable():
            self._animate("enabled", planned)
        elif not self.foreign.calm(self._clock()):
            self._yield(self.foreign.caller, "enabled while another node moves the part")
        else:
            self.transition_to(StreamState.WAITING, "enabled; %s yet" % self.not_connected)

    def _resume(self, now: float) -> None:
        """The other node is done and calm: animate again, from the measured joints (nothing of ours runs)."""
        why = self.stop_yielding(now)
        if self.connected:
            self._animate(why)
        else:
            self.transition_to(StreamState.WAITING, why + "; " + self.not_connected)

    def foreign_motion(self, key: str, caller: str, kind: str, last_point_at: Optional[float]) -> None:
        """Another node moves the part: a goal or a trajectory on its controller, or a setAngles call
        (`last_point_at`: when its last point passes)."""
        now = self._clock()
        self.foreign.started(key, caller, kind, now, last_point_at)
        if self.state in (StreamState.ANIMATING, StreamState.WAITING):
            self._yield(caller, "%s sent a %s" % (caller, kind))
        elif self.state == StreamState.HOMING:  # its motion replaced our return to the centre
            self._abandon_home()
            self.log_yield(caller, kind)
            self.transition_to(StreamState.IDLE, "%s moves the part instead of our return to the centre" % caller)
        elif self.state == StreamState.YIELDING:
            self.yielding_to = caller

    def foreign_command(self, caller: str, last_point_at: float, kind: str = COMMAND,
                        key: Optional[str] = None) -> None:
        """Another node's trajectory on the controller's command topic, or (`kind` JOINT_ANGLES) its setAngles call
        on naoqi_driver's topic, which `key` names so that each call replaces the previous one on the same joints."""
        self._command_count += 1
        self.foreign_motion(key or "command-%d" % self._command_count, caller, kind, last_point_at)

    def foreign_result(self, key: str) -> None:
        """A goal's result on the controller's action (ours are ignored by the tracker)."""
        self.foreign.result(key, self._clock())
