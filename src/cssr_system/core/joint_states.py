"""The measured joints (README: "Faults"): where every joint is (`JointStateCache`), and whether the node listens
to /joint_states at all (`JointStateFeed`, `SubscriptionSwitch`).

A message is used only when it is sound: as many positions as names, every position finite, a stamp neither far in
the past nor in the future of the node's clock (ROS time; a zero stamp counts as "now"). Each joint keeps its own
stamp, so a message that lacks some joints updates the others only. A joint's measurement is current for
MAX_AGE seconds; planning asks for whole parts and gets None when one of its joints has no current measurement,
and then plans as without a measurement. Each kind of problem is reported once, to the `report` callable; nothing
here ever raises into rospy's callback thread. Pure Python: the clock and the report are injected.

/joint_states comes 50 times a second, and each message costs the client library a thread wake-up and a decode: on
ROS 2 more than everything else the node does. So the node reads the measured joints only when a decision needs them:
- where a part starts when enabled or resumed: the joints at rest, measured once and then held (below);
- whether a goal that the controller aborted for its end state reached its end: a fresh measurement, read then
  (core/supervisor.py waits for it, JUDGE_WAIT at most);
- whether another node's motion has calmed, and where a part waiting for its controller or a retry starts: the feed
  listens while that lasts.
A goal of ours needs no measurement: the controller plays it, so the plan says where the joints are while it runs,
and a goal that SUCCEEDED leaves them at its last point, where the controller holds them (`settle`). A joint-angle
stream stops where its calls have brought the joints. `moving` marks the joints a motion of ours takes away from
their measurements: a measurement older than that no longer counts for them.

The feed listens while a decision needs the measured joints (`busy`), and while some joint that no motion of ours
drives has no current measurement. Once neither holds, for REST_DELAY seconds, it holds those joints' measurements
(`JointStateCache.hold`: they stay current however old they grow, until a motion of ours or another node's moves
them) and unsubscribes. It listens again when a decision needs them, when another node moves a part, and when a
controller comes or goes (a restarted controller may have moved its joints).

`JointStateCache` and `JointStateFeed` are pure (the clock, the report and the switching are injected);
`SubscriptionSwitch` subscribes and unsubscribes on its own thread, because registering with the master may wait
for it.
"""
import enum
import math
import threading
from typing import Callable, Dict, Optional, Sequence, Set, Tuple

import numpy

from cssr_system.animate_behaviour.contract import JOINT_STATES_TOPIC, NODE_NAME

MAX_AGE = 1.0  # s: older measurements are not trusted as the current position
MAX_AHEAD = 1.0  # s: stamps further in the future than this are not trusted either
REST_DELAY = 2.0  # s of quiet, with every joint measured, before the measurements are held: the joints settle
RETRY_PERIOD = 1.0  # s before a failed subscription or unsubscription is tried again


class JointStateCache:
    def __init__(self, clock: Callable[[], float], report: Callable[[str], None],
                 topic: str = "/" + JOINT_STATES_TOPIC) -> None:
        """`topic`: the resolved name of the joint states' topic, for the messages."""
        self._clock = clock
        self._report = report
        self._topic = topic
        self._lock = threading.Lock()
        self._joints: Dict[str, Tuple[float, float]] = {}  # name -> (position, stamp)
        self._reported = set()
        self._moved_at: Dict[str, float] = {}  # name -> when a motion of ours last took it away from its measurement
        self._resting = False  # /joint_states is not listened to
        self._held: Set[str] = set()  # joints whose measurement stays current: nothing moves them

    def _report_once(self, kind: str, text: str) -> None:
        if kind not in self._reported:
            self._reported.add(kind)
            self._report(text)

    def update(self, message, received_at: Optional[float] = None) -> None:
        """A ROS 1 /joint_states message (rospy's callback thread) that came at `received_at` (default: now)."""
        try:
            names, positions = list(message.name), list(message.position)
            stamp = message.header.stamp.to_sec()
        except Exception as error:  # a message rospy could decode but that is not a JointState
            self._report_once("unreadable", "%s: unusable message (%s); ignored" % (self._topic, error))
            return
        self.record(names, positions, stamp, received_at)

    def record(self, names: Sequence[str], positions: Sequence[float], stamp: float,
               received_at: Optional[float] = None) -> None:
        """A /joint_states message's joints, positions and stamp (s; 0: "now"), from any ROS."""
        now = self._clock() if received_at is None else received_at
        if len(names) != len(positions):
            self._report_once("length", "%s: %d names but %d positions; such messages are ignored"
                              % (self._topic, len(names), len(positions)))
            return
        if not all(math.isfinite(position) for position in positions):
            self._report_once("finite", "%s: a position that is not a finite number (NaN or infinite); such "
                                        "messages are ignored" % self._topic)
            return
        if stamp == 0.0:
            stamp = now
        elif now - stamp > MAX_AGE or stamp - now > MAX_AHEAD:
            self._report_once("stamp", "%s: stamp %.3f s %s the node's clock; such messages are ignored"
                              % (self._topic, abs(now - stamp), "behind" if stamp < now else "ahead of"))
            return
        with self._lock:
            for name, position in zip(names, positions):
                self._joints[name] = (position, stamp)

    def _measurements(self, joints: Sequence[str]):
        """The (position, stamp) of each of `joints` or None, and whether each is current, read at once."""
        now = self._clock()
        with self._lock:
            measured = [self._joints.get(name) for name in joints]
            current = [value is not None and self._current(name, value[1], now)
                       for name, value in zip(joints, measured)]
        return measured, current

    def _current(self, name: str, stamp: float, now: float) -> bool:
        """Held, or recent and taken since a motion of ours last moved the joint."""
        return name in self._held or (now - stamp <= MAX_AGE and stamp >= self._moved_at.get(name, stamp))

    def positions(self, joints: Sequence[str]) -> Optional[numpy.ndarray]:
        """Current positions of `joints`, or None when one of them has no current measurement."""
        measured, current = self._measurements(joints)
        if any(value is None for value in measured):
            missing = [name for name, value in zip(joints, measured) if value is None]
            self._report_once("missing " + ",".join(missing), "%s: no measurement of %s; planning from the plan "
                                                              "instead" % (self._topic, ", ".join(missing)))
            return None
        if not all(current):
            return None
        return numpy.array([position for position, _ in measured], dtype=float)

    def complete(self, joints: Sequence[str]) -> bool:
        """True when every one of `joints` has a current measurement (reports only bad messages)."""
        return all(self._measurements(joints)[1])

    def moving(self, joints: Sequence[str]) -> None:
        """A motion of ours moves `joints` from now: their measurements so far no longer say where they are."""
        now = self._clock()
        with self._lock:
            for name in joints:
                self._moved_at[name] = now
                self._held.discard(name)

    def settle(self, joints: Sequence[str], positions: Sequence[float]) -> None:
        """A goal of ours brought `joints` to `positions`, where the controller holds them: as good as a measurement
        of now, and held while /joint_states is not listened to."""
        now = self._clock()
        with self._lock:
            for name, position in zip(joints, positions):
                self._joints[name] = (float(position), now)
                if self._resting:
                    self._held.add(name)

    def hold(self, joints: Sequence[str]) -> None:
        """/joint_states is no longer listened to, and nothing moves `joints`: their measurements stay current."""
        with self._lock:
            self._resting = True
            self._held = set(joints)

    def release(self) -> None:
        """Listening again: measurements age as before (the held ones are soon too old, then replaced)."""
        with self._lock:
            self._resting = False
            self._held.clear()


class FeedState(enum.Enum):
    LISTENING = "listening"
    RESTING = "resting"


class JointStateFeed:
    def __init__(self, cache, switch: Callable[[bool], None], debug: Callable[..., None]) -> None:
        self._cache = cache  # JointStateCache: held while resting
        self._switch = switch  # switch(True) subscribes, switch(False) unsubscribes; never blocks
        self._debug = debug
        self.state = FeedState.LISTENING
        self._quiet_since: Optional[float] = None

    def transition_to(self, new_state: FeedState, why: str) -> None:
        self._debug("%s: joint states: %s -> %s (%s).", NODE_NAME, self.state.value, new_state.value, why)
        self.state = new_state

    def update(self, busy: Optional[str], still: Sequence[str], now: float) -> None:
        """`busy`: why a decision needs the measured joints (None: none does); `still`: the joints that no motion of
        ours drives, to be measured, then held; `now`: the node's clock."""
        if busy is not None:
            self.listen(busy)
            return
        measured = self._cache.complete(still)
        if self.state == FeedState.RESTING:
            if not measured:  # a motion of ours ended where no plan says (cancelled, say): measure its joints
                self.listen("a joint at rest has no current measurement")
            return
        if self._quiet_since is None or now < self._quiet_since:  # a clock set back starts the wait again
            self._quiet_since = now
        if measured and now - self._quiet_since >= REST_DELAY:
            self._cache.hold(still)
            self._switch(False)
            self.transition_to(FeedState.RESTING, "quiet for %.1f s" % (now - self._quiet_since))

    def listen(self, why: str) -> None:
        """The joints may move (`why`): listen again, and wait for a new quiet spell before resting."""
        self._quiet_since = None
        if self.state == FeedState.RESTING:
            self._switch(True)
            self._cache.release()
            self.transition_to(FeedState.LISTENING, why)


class SubscriptionSwitch:
    """Subscribes and unsubscribes on its own thread, to whatever was asked last: registering with the master
    waits for it, and the supervisor that asks must never wait."""

    def __init__(self, subscribe: Callable[[], object], subscription, report_error: Callable[[str, Exception], None],
                 where: str) -> None:
        self._subscribe = subscribe  # makes a subscription (an object with unregister())
        self._subscription = subscription  # the one made at start-up
        self._report_error = report_error
        self._where = where
        self._wanted = subscription is not None
        self._lock = threading.Lock()
        self._asked = threading.Event()
        self.thread = threading.Thread(target=self.run, name="joint-state-switch", daemon=True)

    def start(self) -> None:
        """Subscribes now (the first enable plans from the measured joints), then switches on its own thread."""
        self(True)
        self.apply()
        self.thread.start()

    def __call__(self, listening: bool) -> None:
        with self._lock:
            self._wanted = listening
        self._asked.set()

    def run(self) -> None:
        while True:
            self._asked.wait()
            self._asked.clear()
            if not self.apply():
                self._asked.wait(RETRY_PERIOD)
                self._asked.set()

    def apply(self) -> bool:
        """Makes the subscription what was asked last (the thread's work; callable directly); False when that
        failed (reported)."""
        with self._lock:
            wanted = self._wanted
        try:
            if wanted and self._subscription is None:
                self._subscription = self._subscribe()
            elif not wanted and self._subscription is not None:
                subscription, self._subscription = self._subscription, None
                subscription.unregister()
            return True
        except Exception as error:  # the master is away, say: try again
            self._report_error(self._where, error)
            return False
