"""Listening to /joint_states only while the joints may move (README: "Performance").

/joint_states comes 50 times a second, and each message costs rospy a thread wake-up and a decode: most of what
a disabled node would spend. A joint moves only when its controller is told to: by a goal of ours, or by
another node's goal or ``command`` trajectory, which the node sees on the controller's status and command topics
(node/foreign_watch.py). So once the robot is quiet (the node disabled, every part idle, no other node's motion
within the quiet time) and every joint has a current measurement, for REST_DELAY seconds, the feed holds the
measurements (where the joints rest) and unsubscribes. It listens again at an enable (after the first goals,
planned from the held measurements, have left), when another node moves a part, and when a controller comes or
goes (a restarted controller may have moved its joints).

`JointStateFeed` is the state machine (pure: the subscription is switched by an injected callable);
`SubscriptionSwitch` does the switching on its own thread, because registering with the master may wait for it.
"""
import enum
import threading
from typing import Callable, Optional

from cssr_system.animate_behaviour.contract import NODE_NAME

REST_DELAY = 2.0  # s of quiet, with every joint measured, before the measurements are held: the joints settle
RETRY_PERIOD = 1.0  # s before a failed subscription or unsubscription is tried again


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

    def update(self, busy: Optional[str], measured: bool, now: float) -> None:
        """`busy`: why the joints may move (None: the robot is quiet); `measured`: every joint has a current
        measurement; `now`: the node's clock."""
        if busy is not None:
            self.listen(busy)
            return
        if self.state == FeedState.RESTING:
            return
        if self._quiet_since is None or now < self._quiet_since:  # a clock set back starts the wait again
            self._quiet_since = now
        if measured and now - self._quiet_since >= REST_DELAY:
            self._cache.hold()
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

    @property
    def subscription(self):
        """The current subscription, or None."""
        return self._subscription

    @property
    def subscribed(self) -> bool:
        return self._subscription is not None
