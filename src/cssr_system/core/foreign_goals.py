"""Other action clients' goals on our controllers, from each controller's status list (README: "Sharing the robot").

An action server publishes the states of every client's goals, at each change and a few times a second (ROS 1:
``<action>/status``; ROS 2: ``<action>/_action/status``). Each front-end's watch hands every list here as (goal id,
running) pairs of the goals that are not ours; the supervisor is told when one is first seen running and when it
ends (a terminal state, or gone from the list). A goal that began and ended between two lists is told as both.

Where a client's goals travel on a topic that the node can watch too (ROS 1: ``<action>/goal``), each is told on its
way (`goal_sent`), as early as the server itself learns of it, and counts as running until the server's lists show
its end; one that no list names within UNLISTED_GRACE s has ended.

The same lock guards the last look before each of our goals leaves (`send_unless_foreign`): a list or a goal handed
over while a goal of ours is being sent waits until it has left, and one handed over before is in the look.
"""
import threading
import time
from collections import defaultdict
from typing import Callable, Dict, Iterable, Optional, Set, Tuple

from cssr_system.core.events import ForeignGoal, ForeignResult

UNLISTED_GRACE = 1.0  # s: a goal told on its way and named by no status list since has ended (a server never takes
# this long to list a goal it has received; its lists come a few times a second)


class ForeignGoals:
    """`post`: the supervisor's queue; `clock`: seconds, for the goals told on their way. Safe from any thread."""

    def __init__(self, post: Callable[[object], None], clock: Callable[[], float] = time.monotonic) -> None:
        self._post = post
        self._clock = clock
        self._unlisted: Dict[str, Dict[str, float]] = defaultdict(dict)  # per action: goals told on their way, when
        self._running: Dict[str, Set[str]] = defaultdict(set)  # per action: other clients' goals seen running
        self._listed: Dict[str, Set[str]] = {}  # per action: other clients' goals in its latest list
        self._started: Dict[str, int] = defaultdict(int)  # per action: other clients' goals told so far
        self._latest: Dict[str, str] = {}  # per action: the latest of them
        self._lock = threading.Lock()

    def status_list(self, action: str, goals: Iterable[Tuple[str, bool]], caller_of: Callable[[str], str]) -> None:
        """One status list of `action`'s server: (goal id, running) of each goal not ours; `caller_of(goal id)`
        names the client of a goal first seen running."""
        listed = set()
        with self._lock:
            running = self._running[action]
            before = self._listed.get(action)  # None: the first list, whose ended goals are old news
            for goal_id, is_running in goals:
                listed.add(goal_id)
                if is_running and goal_id not in running:
                    running.add(goal_id)
                    self._tell_started(action, goal_id, caller_of)
                elif not is_running and goal_id in running:
                    running.discard(goal_id)
                    self._post(ForeignResult(action, goal_id))
                elif not is_running and before is not None and goal_id not in before:
                    self._tell_started(action, goal_id, caller_of)  # it moved the part all the same
                    self._post(ForeignResult(action, goal_id))
            self._end_unlisted(action, running - listed, listed)
            self._listed[action] = listed

    def _end_unlisted(self, action: str, unlisted: Set[str], listed: Set[str]) -> None:
        """Running goals that a list does not name have ended, but those told on their way in the last
        UNLISTED_GRACE s: the server may not have listed them yet."""
        on_their_way = self._unlisted[action]
        for goal_id in listed:
            on_their_way.pop(goal_id, None)
        now = self._clock()
        for goal_id in unlisted:
            if goal_id in on_their_way and now - on_their_way[goal_id] < UNLISTED_GRACE:
                continue
            on_their_way.pop(goal_id, None)
            self._running[action].discard(goal_id)
            self._post(ForeignResult(action, goal_id))

    def goal_sent(self, action: str, goal_id: str, caller_of: Callable[[str], str]) -> None:
        """Another client's goal on its way to `action`'s server: running from now, unless a list has named it."""
        with self._lock:
            if not goal_id or goal_id in self._running[action] or goal_id in self._listed.get(action, ()):
                return  # no id: the server gives it one, and lists it so
            self._running[action].add(goal_id)
            self._unlisted[action][goal_id] = self._clock()
            self._tell_started(action, goal_id, caller_of)

    def _tell_started(self, action: str, goal_id: str, caller_of: Callable[[str], str]) -> None:
        self._started[action] += 1
        self._latest[action] = goal_id
        self._post(ForeignGoal(action, goal_id, caller_of(goal_id), None))

    def started(self, action: str) -> int:
        """How many other clients' goals on `action` have been told so far: a send handed over to another thread
        notes it, and its last look withholds the goal if one came since."""
        with self._lock:
            return self._started[action]

    def send_unless_foreign(self, action: str, send: Callable[[], None], since: Optional[int] = None
                            ) -> Optional[str]:
        """The last look before a goal of ours leaves for `action`: calls `send` unless, in the latest status list,
        another client's goal runs there, or one was told after `since` (`started` when the send was decided);
        then returns that goal's id and sends nothing (its ForeignGoal is on the supervisor's queue already, and
        makes the part yield). None: sent."""
        with self._lock:
            running = sorted(self._running[action])
            if running:
                return running[0]
            if since is not None and self._started[action] > since:
                return self._latest[action]
            send()
            return None
