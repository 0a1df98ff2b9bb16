"""The latest measured position of every joint, from /joint_states (README: "Faults").

A message is used only when it is sound: as many positions as names, every position finite, a stamp neither far in
the past nor in the future of the node's clock (ROS time; a zero stamp counts as "now"). Each joint keeps its own
stamp, so a message that lacks some joints updates the others only. A joint's measurement is current for
MAX_AGE seconds; planning asks for whole parts and gets None when one of its joints has no current measurement,
and then plans as without a measurement. Each kind of problem is reported once, to the `report` callable; nothing
here ever raises into rospy's callback thread. Pure Python: the clock and the report are injected.

Messages are received undecoded (`receive`, rospy's AnyMsg: the callback thread only keeps the bytes and when they
came) and decoded when positions are asked for, the latest RAW_KEPT of them: at 50 Hz the node would otherwise
decode 50 messages a second to use one every few seconds. A stamp is judged against the message's arrival.

While the robot rests the node stops listening (node/joint_state_feed.py): `hold` keeps the last measurements
current however old they grow, until `release`.
"""
import collections
import math
import threading
from typing import Callable, Dict, Optional, Sequence, Tuple

import numpy

MAX_AGE = 1.0  # s: older measurements are not trusted as the current position
MAX_AHEAD = 1.0  # s: stamps further in the future than this are not trusted either
# Undecoded messages kept, the latest: 0.16 s at 50 Hz, and every publisher's latest when a few publish.
RAW_KEPT = 8


class JointStateCache:
    def __init__(self, clock: Callable[[], float], report: Callable[[str], None],
                 decode: Optional[Callable[[bytes], object]] = None) -> None:
        self._clock = clock
        self._report = report
        self._decode = decode  # bytes -> a JointState, for `receive`
        self._raw: "collections.deque" = collections.deque(maxlen=RAW_KEPT)  # (arrival, bytes), appended atomically
        self._lock = threading.Lock()
        self._joints: Dict[str, Tuple[float, float]] = {}  # name -> (position, stamp)
        self._reported = set()
        self._held = False  # the measurements stay current: nothing moves and nothing is listened to

    def _report_once(self, kind: str, text: str) -> None:
        if kind not in self._reported:
            self._reported.add(kind)
            self._report(text)

    def receive(self, message) -> None:
        """An undecoded /joint_states message (rospy.AnyMsg, in rospy's callback thread): kept for later."""
        self._raw.append((self._clock(), message._buff))

    def _decode_received(self) -> None:
        while True:
            try:
                received_at, data = self._raw.popleft()
            except IndexError:
                return
            try:
                message = self._decode(data)
            except Exception as error:  # bytes that are not a JointState
                self._report_once("unreadable", "/joint_states: unusable message (%s); ignored" % error)
                continue
            self.update(message, received_at)

    def update(self, message, received_at: Optional[float] = None) -> None:
        """A decoded /joint_states message that came at `received_at` (default: now)."""
        try:
            names, positions = list(message.name), list(message.position)
            stamp = message.header.stamp.to_sec()
        except Exception as error:  # a message rospy could decode but that is not a JointState
            self._report_once("unreadable", "/joint_states: unusable message (%s); ignored" % error)
            return
        now = self._clock() if received_at is None else received_at
        if len(names) != len(positions):
            self._report_once("length", "/joint_states: %d names but %d positions; such messages are ignored"
                              % (len(names), len(positions)))
            return
        if not all(math.isfinite(position) for position in positions):
            self._report_once("finite", "/joint_states: a position that is not a finite number (NaN or infinite); "
                                        "such messages are ignored")
            return
        if stamp == 0.0:
            stamp = now
        elif now - stamp > MAX_AGE or stamp - now > MAX_AHEAD:
            self._report_once("stamp", "/joint_states: stamp %.3f s %s the node's clock; such messages are ignored"
                              % (abs(now - stamp), "behind" if stamp < now else "ahead of"))
            return
        with self._lock:
            for name, position in zip(names, positions):
                self._joints[name] = (position, stamp)

    def _measurements(self, joints: Sequence[str]):
        """(now, the (position, stamp) of each of `joints` or None), once what was received is decoded."""
        self._decode_received()
        now = self._clock()
        with self._lock:
            return now, [self._joints.get(name) for name in joints]

    def _current(self, stamp: float, now: float) -> bool:
        return self._held or now - stamp <= MAX_AGE

    def positions(self, joints: Sequence[str]) -> Optional[numpy.ndarray]:
        """Current positions of `joints`, or None when one of them has no current measurement."""
        now, measured = self._measurements(joints)
        if any(value is None for value in measured):
            missing = [name for name, value in zip(joints, measured) if value is None]
            self._report_once("missing " + ",".join(missing), "/joint_states: no measurement of %s; planning from "
                                                              "the plan instead" % ", ".join(missing))
            return None
        if not all(self._current(stamp, now) for _, stamp in measured):
            return None
        return numpy.array([position for position, _ in measured], dtype=float)

    def complete(self, joints: Sequence[str]) -> bool:
        """True when every one of `joints` has a current measurement (reports only bad messages)."""
        now, measured = self._measurements(joints)
        return all(value is not None and self._current(value[1], now) for value in measured)

    def hold(self) -> None:
        """The robot rests and /joint_states is no longer listened to: the last measurements stay current."""
        self._decode_received()
        self._held = True

    def release(self) -> None:
        """Listening again: measurements age as before (the held ones are soon too old, then replaced)."""
        self._held = False
