"""The latest measured position of every joint, from /joint_states (README: "Faults").

A message is used only when it is sound: as many positions as names, every position finite, a stamp neither far in
the past nor in the future of the node's clock (ROS time; a zero stamp counts as "now"). Each joint keeps its own
stamp, so a message that lacks some joints updates the others only. A joint's measurement is current for
MAX_AGE seconds; planning asks for whole parts and gets None when one of its joints has no current measurement,
and then plans as without a measurement. Each kind of problem is reported once, to the `report` callable; nothing
here ever raises into rospy's callback thread. Pure Python: the clock and the report are injected.

While the robot rests the node stops listening (node/joint_state_feed.py): `hold` keeps the last measurements
current however old they grow, until `release`.
"""
import math
import threading
from typing import Callable, Dict, Optional, Sequence, Tuple

import numpy

MAX_AGE = 1.0  # s: older measurements are not trusted as the current position
MAX_AHEAD = 1.0  # s: stamps further in the future than this are not trusted either


class JointStateCache:
    def __init__(self, clock: Callable[[], float], report: Callable[[str], None]) -> None:
        self._clock = clock
        self._report = report
        self._lock = threading.Lock()
        self._joints: Dict[str, Tuple[float, float]] = {}  # name -> (position, stamp)
        self._reported = set()
        self._held = False  # the measurements stay current: nothing moves and nothing is listened to

    def _report_once(self, kind: str, text: str) -> None:
        if kind not in self._reported:
            self._reported.add(kind)
            self._report(text)

    def update(self, message) -> None:
        """A /joint_states message (rospy's callback thread)."""
        try:
            names, positions = list(message.name), list(message.position)
            stamp = message.header.stamp.to_sec()
        except Exception as error:  # a message rospy could decode but that is not a JointState
            self._report_once("unreadable", "/joint_states: unusable message (%s); ignored" % error)
            return
        now = self._clock()
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

    def positions(self, joints: Sequence[str]) -> Optional[numpy.ndarray]:
        """Current positions of `joints`, or None when one of them has no current measurement."""
        now = self._clock()
        with self._lock:
            measured = [self._joints.get(name) for name in joints]
        if any(value is None for value in measured):
            missing = [name for name, value in zip(joints, measured) if value is None]
            self._report_once("missing " + ",".join(missing), "/joint_states: no measurement of %s; planning from "
                                                              "the plan instead" % ", ".join(missing))
            return None
        if not self._held and any(now - stamp > MAX_AGE for _, stamp in measured):
            return None
        return numpy.array([position for position, _ in measured], dtype=float)

    def complete(self, joints: Sequence[str]) -> bool:
        """True when every one of `joints` has a current measurement (reports nothing)."""
        now = self._clock()
        with self._lock:
            measured = [self._joints.get(name) for name in joints]
        return all(value is not None and (self._held or now - value[1] <= MAX_AGE) for value in measured)

    def hold(self) -> None:
        """The robot rests and /joint_states is no longer listened to: the last measurements stay current."""
        self._held = True

    def release(self) -> None:
        """Listening again: measurements age as before (the held ones are soon too old, then replaced)."""
        self._held = False
