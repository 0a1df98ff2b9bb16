"""The mode in force (README: "Modes"): `idle`, `listening` or `speaking`, set by hand or following the conversation.

The mode setting (configuration key ``mode``, a live setting, a field of the animate action) is a mode or `auto`.
The conversation is what the sources say: a std_msgs/Bool topic (true: the robot speaks, or listens) or the status of
an action (a goal running: the robot speaks, or listens). Each source counts while it is active and shows signs of
life: a message, or a publisher still on its topic (the front-end tells when it sees one). A source that shows none
for `conversationTimeout` s counts no more, so the robot is never stuck in speaking when a speech node dies. Speaking
wins over listening, listening over idle.

In `auto` the mode in force is the conversation's. A mode set by hand holds until the next conversation event (the
conversation's mode changes), which puts the setting back to `auto`, or until the setting is `auto` again.

The supervisor (core/supervisor.py) owns one `Conversation` and asks it on each event and when a time-out is due
(`next_deadline`); every method that may change the mode in force returns the `ModeChange`, or None. Pure Python.
"""
import threading
import time
from typing import Callable, Dict, List, NamedTuple, Optional, Tuple

from cssr_system.animate_behaviour.configuration import AUTO_MODE, CONVERSATION_SOURCES, MODES, Configuration, KEYS
from cssr_system.core.events import ConversationHeard

IDLE, LISTENING, SPEAKING = MODES
PRIORITY = (SPEAKING, LISTENING)  # the first whose source counts wins; none: IDLE


class ModeChange(NamedTuple):
    old: str
    new: str
    by: str  # who or what changed it
    setting: str  # the mode setting now: AUTO_MODE, or the mode set by hand


class Source:
    """One watched source: what its activity means, what it last said, and its last sign of life."""

    def __init__(self, key: str, name: str, means: str) -> None:
        self.key, self.name, self.means = key, name, means
        self.active = False
        self.last_sign: Optional[float] = None

    def counts(self, now: float, timeout: float) -> bool:
        return self.active and self.last_sign is not None and now - self.last_sign <= timeout

    def label(self) -> str:
        return "%s %s" % (self.key, self.name)


def configured_sources(config: Configuration) -> List[Tuple[str, str, str, str]]:
    """(key, name, means, kind) of each source `config` names: kind ``topic`` (std_msgs/Bool) or ``action``."""
    return [(key, getattr(config, KEYS[key].attribute), means, kind) for key, means, kind in CONVERSATION_SOURCES
            if getattr(config, KEYS[key].attribute)]


class Conversation:
    """`sources`: (key, name, means) of each watched source; `timeout`: conversationTimeout."""

    def __init__(self, sources=(), timeout: float = 3.0, setting: str = AUTO_MODE, by: str = "configuration") -> None:
        self.sources: Dict[str, Source] = {key: Source(key, name, means) for key, name, means in sources}
        self.timeout = timeout
        self.setting = setting
        self.heard_mode = IDLE  # the conversation's mode at the last look
        self.mode = IDLE if setting == AUTO_MODE else setting
        self.by = by
        self._ended = "the conversation"  # why the conversation is idle when no source is silent: the last one ended

    # -- the mode setting ---------------------------------------------------------------------------
    def set_mode(self, setting: str, by: str, now: float) -> Optional[ModeChange]:
        """The mode setting, from the configuration, a live setting or an animate goal's caller (`by`)."""
        self.setting = setting
        self.heard_mode = self._heard(now)[0]
        return self._change(self.heard_mode if setting == AUTO_MODE else setting, by)

    # -- the sources --------------------------------------------------------------------------------
    def heard(self, key: str, active: bool, now: float) -> Optional[ModeChange]:
        """A message of source `key`: whether the robot speaks (or listens) now, as it says."""
        source = self.sources.get(key)
        if source is None:
            return None
        if source.active and not active:
            self._ended = "%s ended" % source.label()
        source.active, source.last_sign = bool(active), now
        return self.look(now)

    def present(self, key: str, now: float) -> Optional[ModeChange]:
        """Source `key` still has a publisher: a sign of life."""
        source = self.sources.get(key)
        if source is not None:
            source.last_sign = now
        return self.look(now)

    def look(self, now: float) -> Optional[ModeChange]:
        """The conversation at `now` (a time-out may have passed): a conversation event sets the mode in force, and
        puts a mode set by hand back to auto."""
        heard, why = self._heard(now)
        if heard == self.heard_mode:
            return None
        self.heard_mode = heard
        self.setting = AUTO_MODE
        return self._change(heard, why)

    def next_deadline(self) -> Optional[float]:
        """When a counting source's time-out passes (None: none counts)."""
        ends = [source.last_sign + self.timeout for source in self.sources.values()
                if source.active and source.last_sign is not None]
        return min(ends) if ends else None

    # -- inside -------------------------------------------------------------------------------------
    def _heard(self, now: float) -> Tuple[str, str]:
        """The conversation's mode and why: the first source of the highest priority that counts."""
        for mode in PRIORITY:
            for source in self.sources.values():
                if source.means == mode and source.counts(now, self.timeout):
                    return mode, source.label()
        silent = [source.label() for source in self.sources.values() if source.active]
        return IDLE, ("%s silent" % ", ".join(silent)) if silent else self._ended

    def _change(self, mode: str, by: str) -> Optional[ModeChange]:
        if mode == self.mode:
            return None
        change = ModeChange(self.mode, mode, by, self.setting)
        self.mode, self.by = mode, by
        return change


PRESENCE_PERIOD = 0.5  # s between the front-ends' looks for a source's publishers, and between repeated messages


class HeardFilter:
    """What a front-end passes on of a source's messages (an action's status list comes several times a second): a
    change at once, the same again at most every PRESENCE_PERIOD s (`monotonic`: the front-end's clock, in s)."""

    def __init__(self) -> None:
        self._last: Dict[str, Tuple[bool, float]] = {}

    def passes(self, key: str, active: bool, monotonic: float) -> bool:
        last = self._last.get(key)
        if last is not None and last[0] == active and monotonic - last[1] < PRESENCE_PERIOD:
            return False
        self._last[key] = (active, monotonic)
        return True


class HeardMessages:
    """What both front-ends' watches (ros1/ and ros2/conversation_watch.py) do with a source's message: a Bool's
    value, or whether an action's status list holds a goal in one of `active_states` (the front-end's codes of a goal
    that runs), posted to the supervisor (`post`) as `ConversationHeard` when `HeardFilter` lets it pass. The
    client library's threads call it, in any number."""

    def __init__(self, post: Callable[[object], None], active_states: Tuple[int, ...]) -> None:
        self._post = post
        self._active_states = active_states
        self._filter = HeardFilter()
        self._lock = threading.Lock()

    def heard(self, key: str, active: bool) -> None:
        with self._lock:
            passes = self._filter.passes(key, active, time.monotonic())
        if passes:
            self._post(ConversationHeard(key, active))

    def bool_message(self, message, key: str) -> None:
        """A std_msgs/Bool of either front-end."""
        self.heard(key, bool(message.data))

    def status_message(self, message, key: str) -> None:
        """An action's GoalStatusArray of either front-end."""
        self.heard(key, any(status.status in self._active_states for status in message.status_list))
