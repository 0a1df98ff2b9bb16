"""The demo driver's run, shared by its ROS 1 node (`driver`) and its ROS 2 node (``cssr_system.ros2.demo_driver``).

`DemoRun` waits until everything has started, keeps the robot at rest for 1 s, enables the node, prints one line a
second (`live_lines`), disables the node after the duration and prints for the tail; a stop request (a signal)
disables the node first. A subclass gives what needs a ROS: the node's activation service (`activate`), what to
wait for at start (`startup_waits`), and the engaged preset, the gesture and the conversation when the run has them.
`drive` runs it and says how it ended. Pure Python: no ROS import.
"""
import functools
import signal
import threading
import time
from typing import Callable, List, Optional, Sequence, Tuple

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour import console
from cssr_system.animate_behaviour.contract import DISABLED, ENABLED, REPLY_SUCCESS
from cssr_system.animate_behaviour.event_log import read_log
from cssr_system.demo.live_lines import CONVERSATION, DISABLE, ENGAGED, GESTURE, LiveWindow, schedule, status_line

NODE_NAME = "animateBehaviourDemo"
say = functools.partial(console.say, NODE_NAME)
REST_BEFORE = 1.0  # s at rest before enabling, so the plot shows the start
SERVICE_CALL_TIMEOUT = 5.0  # s; the node answers within 100 ms, so this only catches a dead node
STOP_DISABLE_TIMEOUT = 2.0  # s for the disable when stopping early (the node may be stopping too)
EXIT_COMPLETED, EXIT_FAILED, EXIT_INTERRUPTED = 0, 1, 130

Wait = Tuple[str, Callable[[], bool]]  # (what is awaited, whether it is there)


class DemoError(Exception):
    """Something did not start or answer: one line for the user, exit status 1."""


class Interrupted(Exception):
    """A stop was requested (signal or shutdown request)."""


class DemoRun:
    """The run; `log_file`: the node's log, where the reason for a refused enable is (None: unknown); `delay`: s
    more at rest before the enable (a second robot enabled after the first); `name`: the driver's resolved name,
    which its lines begin with (in a namespace, e.g. /robot1/animateBehaviourDemo, they say which robot);
    `conversation`: the stand-in speech node plays its conversation, and the lines say the node's mode."""

    def __init__(self, duration: float, tail: float, startup_timeout: float, log_file: Optional[str],
                 gesture: bool = False, interaction: bool = False, delay: float = 0.0,
                 name: str = "/" + NODE_NAME, conversation: bool = False) -> None:
        self.name = name.lstrip("/")
        self.robot = name.strip("/").rpartition("/")[0]  # the namespace, "" at the root
        self.duration, self.tail, self.gesture, self.interaction = duration, tail, gesture, interaction
        self.delay, self.conversation = delay, conversation
        self.startup_timeout = startup_timeout
        self.log_file = log_file
        self.window = LiveWindow()
        self.stop = threading.Event()
        self.stop_reason = ""
        self._activation_lock = threading.Lock()
        self._enabled = False
        self.disabled_early = False  # disabled because a stop was requested
        self.yielding: List[Tuple[str, str]] = []  # (label, caller) of the parts that yield, from the node's status
        self.mode = ""  # the node's mode, from its status

    # -- what a subclass gives ------------------------------------------------------------------
    def activate(self, state: str, timeout: float) -> str:
        """The node's reply to `state` on its activation service; DemoError when the call fails."""
        raise NotImplementedError

    def startup_waits(self) -> Sequence[Wait]:
        """What must be there before the enable, besides /joint_states."""
        return ()

    def engage(self) -> None:
        """Switch the node to the engaged preset (runs with `interaction` only)."""

    def play_gesture(self) -> None:
        """Have another node play its gesture (runs with `gesture` only)."""

    def play_conversation(self) -> None:
        """Have the stand-in speech node play its conversation (runs with `conversation` only)."""

    # -- stop requests ----------------------------------------------------------------------------
    def request_stop(self, reason: str) -> None:
        self.stop_reason = self.stop_reason or reason
        self.stop.set()  # the main thread disables and exits

    def on_signal(self, signal_number: int, frame) -> None:
        self.request_stop(signal.Signals(signal_number).name)

    # -- the node's service ---------------------------------------------------------------------
    def enable(self) -> None:
        with self._activation_lock:
            if self.stop.is_set():
                raise Interrupted()
            asked = time.time()
            reply = self.activate(ENABLED, SERVICE_CALL_TIMEOUT)
            if reply != REPLY_SUCCESS:
                reason = self._refusal_reason(asked)
                raise DemoError("animateBehaviour refused %r (reply %r): %s" % (ENABLED, reply, reason))
            self._enabled = True

    def disable_if_enabled(self, timeout: float = SERVICE_CALL_TIMEOUT) -> bool:
        """Disable the node when this driver enabled it; True when it was disabled now."""
        with self._activation_lock:
            if not self._enabled:
                return False
            self._enabled = False
            reply = self.activate(DISABLED, timeout)
            if reply != REPLY_SUCCESS:
                raise DemoError("animateBehaviour refused %r (reply %r)" % (DISABLED, reply))
            self.disabled_early = self.stop.is_set()
            return True

    def _refusal_reason(self, since: float) -> str:
        """The problems the node logged for a refused enable, else where to look."""
        if self.log_file is None:
            return "see the node's log file"
        try:
            entries = read_log(self.log_file)
        except (OSError, ValueError):
            entries = []
        for entry in reversed(entries):
            if entry.event == contract.CONFIGURATION_INVALID and entry.timestamp.timestamp() >= since - 1.0:
                return "; ".join(str(problem) for problem in entry.fields.get("problems", [])) or "invalid"
        return "see its log %s" % self.log_file

    # -- the run ----------------------------------------------------------------------------------
    def pause(self, seconds: float) -> None:
        if self.stop.wait(max(0.0, seconds)):
            raise Interrupted()

    def wait_for_start(self) -> None:
        deadline = time.monotonic() + self.startup_timeout
        waits = [("the simulated Pepper (/joint_states)", self.window.has_joint_states)]  # type: List[Wait]
        for what, ready in waits + list(self.startup_waits()):
            while not ready():
                if time.monotonic() > deadline:
                    raise DemoError("%s did not start within %.0f s" % (what, self.startup_timeout))
                self.pause(0.1)

    def run(self) -> None:
        self.wait_for_start()
        self.pause(REST_BEFORE + self.delay)
        self.say("enabling animateBehaviour for %g s (Ctrl-C stops early)" % self.duration)
        self.enable()
        enabled_at = time.monotonic()
        state = ENABLED
        for moment, what in schedule(self.duration, self.tail, self.gesture, self.interaction, self.conversation):
            self.pause(enabled_at + moment - time.monotonic())
            if what == ENGAGED:
                self.engage()
            elif what == DISABLE:
                self.disable_if_enabled()
                state = DISABLED
                self.say("disabled after %g s; recording %g s more to show the stop" % (self.duration, self.tail))
            elif what == GESTURE:
                self.play_gesture()
            elif what == CONVERSATION:
                self.play_conversation()
            else:
                names, positions, headings, heading = self.window.last(time.time(), 1.0)
                line = status_line(int(moment), state, names, positions, headings, heading, self.yielding,
                                   self.mode if self.conversation else "")
                print("%s %s" % (self.robot, line) if self.robot else line, flush=True)

    def say(self, text: str) -> None:
        console.say(self.name, text)


def write_outcome(path: str, status: int, text: str) -> None:
    if not path:
        return
    try:
        with open(path, "w", encoding="utf-8") as outcome:
            outcome.write("%d %s\n" % (status, text))
    except OSError as error:
        say("error: cannot write the outcome file %s: %s" % (path, error))


def drive(run: DemoRun, outcome_file: str, ending: str) -> Tuple[int, str]:
    """Run `run`, never leave the node enabled, write the outcome file: (exit status, why). `ending`: what ends
    with the driver, for its last line (e.g. "the launch")."""
    status, text = EXIT_COMPLETED, "completed"
    try:
        run.run()
        run.say("finished; stopping %s (the recorder writes the plot)" % ending)
    except Interrupted:
        status, text = EXIT_INTERRUPTED, "stopped early (%s)" % run.stop_reason
    except DemoError as error:
        run.say("error: %s" % error)
        status, text = EXIT_FAILED, str(error)
    try:
        run.disable_if_enabled(STOP_DISABLE_TIMEOUT)  # never leave it enabled, also after an error
    except DemoError as error:
        run.say("error: %s" % error)
    if status == EXIT_INTERRUPTED:
        run.say("%s%s; stopping %s" % (text, ": animateBehaviour disabled" if run.disabled_early else "", ending))
    write_outcome(outcome_file, status, text)
    return status, text


def service_failure(service: str, state: str, error: object) -> DemoError:
    return DemoError("%s %s failed: %s" % (service, state, error))
