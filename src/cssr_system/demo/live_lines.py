"""The demo's live lines: which parts moved in the last second, and the base heading.

``   7 s  enabled   moving: right arm, leg, base        base heading +0.12 rad  yielding: right arm to /gesture``
``   9 s  enabled   moving: right arm, left arm, leg     base heading +0.12 rad  mode: speaking``

`LiveWindow` keeps the last seconds of /joint_states and of the heading (filled from rospy's
threads, read from the main thread); `status_line` formats one line. Pure Python and numpy: no ROS
import.
"""
import math
import threading
from collections import deque
from typing import Deque, List, Optional, Sequence, Tuple

import numpy

from cssr_system.pepper.joint_table import PARTS
from cssr_system.recording.recording import (BASE_LABEL, MOTION_THRESHOLD, moving_parts,
                                             unwrap_heading)

MOVING_COLUMN_WIDTH = len(", ".join([part.label for part in PARTS.values()] + [BASE_LABEL]))
KEPT = 3.0  # s of samples kept


class LiveWindow:
    """The last `KEPT` seconds of joint positions and headings, by wall-clock time of arrival."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.joint_names = ()  # type: Tuple[str, ...]
        self._rows = deque()  # type: Deque[Tuple[float, List[float]]]
        self._headings = deque()  # type: Deque[Tuple[float, float]]

    @staticmethod
    def _trim(samples: Deque, now: float) -> None:
        while samples and samples[0][0] < now - KEPT:
            samples.popleft()

    def add_joint_states(self, now: float, names: Sequence[str], positions: Sequence[float]) -> None:
        with self._lock:
            if not self.joint_names:
                self.joint_names = tuple(names)
            value_of = dict(zip(names, positions))
            self._rows.append((now, [float(value_of.get(name, math.nan)) for name in self.joint_names]))
            self._trim(self._rows, now)

    def add_heading(self, now: float, yaw: float) -> None:
        with self._lock:
            previous = self._headings[-1][1] if self._headings else None
            self._headings.append((now, unwrap_heading(previous, yaw)))
            self._trim(self._headings, now)

    def has_joint_states(self) -> bool:
        with self._lock:
            return bool(self._rows)

    def last(self, now: float, seconds: float) -> Tuple[Tuple[str, ...], numpy.ndarray, numpy.ndarray,
                                                        Optional[float]]:
        """(joint names, positions, headings) of the `seconds` before `now`, and the latest heading."""
        with self._lock:
            rows = [row for moment, row in self._rows if moment >= now - seconds]
            headings = [value for moment, value in self._headings if moment >= now - seconds]
            latest = self._headings[-1][1] if self._headings else None
            return (self.joint_names, numpy.array(rows, dtype=float).reshape(-1, len(self.joint_names)),
                    numpy.array(headings, dtype=float), latest)


def status_line(seconds: int, state: str, joint_names: Sequence[str], positions: numpy.ndarray,
                headings: numpy.ndarray, heading: Optional[float], yielding: Sequence[Tuple[str, str]] = (),
                mode: str = "") -> str:
    """The live line of one second: the parts that moved in `positions` (that second's samples),
    the base when `headings` moved, the latest `heading`, the node's `mode` when given (from its status topic) and
    the parts that yield to another node ((label, caller id) from the node's status topic)."""
    moving = moving_parts(joint_names, positions)
    if len(headings) >= 2 and numpy.ptp(headings) > MOTION_THRESHOLD:
        moving.append(BASE_LABEL)
    heading_text = "base heading %+.2f rad" % heading if heading is not None else "base heading: no odometry"
    line = "%4d s  %-8s  moving: %-*s  %s" % (seconds, state, MOVING_COLUMN_WIDTH,
                                              ", ".join(moving) if moving else "nothing", heading_text)
    if mode:
        line += "  mode: %s" % mode
    if yielding:
        line += "  yielding: " + ", ".join("%s to %s" % (label, caller) for label, caller in yielding)
    return line


LINE, GESTURE, DISABLE, ENGAGED, CONVERSATION = "line", "gesture", "disable", "engaged", "conversation"
CONVERSATION_START = 2.0  # s after enable: the plot shows idle motion before the robot listens


def schedule(duration: float, tail: float, gesture: bool, interaction: bool = False,
             conversation: bool = False) -> List[Tuple[float, str]]:
    """(seconds after enable, what) of a run: a line every second until `duration` + `tail`, the
    gesture half-way when asked, the switch to the engaged preset half-way when asked, the start of the
    conversation (`cssr_system.demo.speech`) at `CONVERSATION_START` when asked, the disable at
    `duration` (after that second's line)."""
    events = [(float(second), LINE) for second in range(1, int(duration + tail) + 1)]
    events.append((duration, DISABLE))
    if gesture:
        events.append((duration / 2.0, GESTURE))
    if interaction:
        events.append((duration / 2.0, ENGAGED))
    if conversation:
        events.append((min(CONVERSATION_START, duration), CONVERSATION))
    rank = {LINE: 0, ENGAGED: 1, GESTURE: 2, CONVERSATION: 3, DISABLE: 4}
    return sorted(events, key=lambda event: (event[0], rank[event[1]]))
