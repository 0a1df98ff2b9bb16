"""Other nodes' motion on one controller or base topic: what runs, who sent it, and when we may move again.

README: "Sharing the robot". Another node's command makes a part yield. A motion counts as running:

- a goal on the controller's action: until it ends (a terminal state on the action's status), or, when its
  last point is known and no end comes, until RESULT_GRACE after that point;
- a trajectory on the controller's ``command`` topic (it has no result): until its last point has passed;
- a Twist on the base topic: until the base is done with it (a relative turn's time on ``cmd_moveto``,
  the velocity time-out on a velocity topic);
- a call on naoqi_driver's JointAngles topic (setAngles): until its slowest joint arrives.

The part may move again `quiet_time` after the last of them ended; a new motion meanwhile (a chain of goals)
keeps it yielding. Times are seconds on the clock the controllers execute on. Pure Python: no ROS.
"""
from typing import Callable, Dict, NamedTuple, Optional, Sequence, Tuple

import numpy

from cssr_system.motion.joint_angle_stream import set_angles_duration
from cssr_system.pepper.joint_table import PARTS, centre_of

GOAL, COMMAND, TWIST, JOINT_ANGLES = "goal", "command", "twist", "joint_angles"
RESULT_GRACE = 1.0  # s after a goal's last point before a missing result no longer holds the part
DEFAULT_QUIET_TIME = 1.0  # s of calm after another node's motion before a part moves again
ANIMATED_JOINTS = frozenset(name for part in PARTS.values() for name in part.joints)


class ForeignMotion(NamedTuple):
    caller: str  # the other node's caller id
    kind: str  # GOAL, COMMAND, TWIST or JOINT_ANGLES
    started: float
    last_point_at: Optional[float]  # when its last point passes or the base is done; None: unknown
    ended_at: Optional[float]  # when its result came (goals only)


class ForeignMotionTracker:
    def __init__(self, quiet_time: float = DEFAULT_QUIET_TIME) -> None:
        self.quiet_time = quiet_time
        self._motions: Dict[str, ForeignMotion] = {}
        self._last_end: Optional[float] = None  # the latest end of a motion already forgotten
        self._latest_caller = ""

    def started(self, key: str, caller: str, kind: str, now: float, last_point_at: Optional[float]) -> None:
        """Another node's motion began (`key`: its goal id, or any key unique to it)."""
        end = None if last_point_at is None else max(now, last_point_at)
        self._motions[key] = ForeignMotion(caller, kind, now, end, None)
        self._latest_caller = caller

    def result(self, key: str, now: float) -> None:
        """A goal's result: it ended (a key we never saw started, e.g. our own goal's, is ignored)."""
        motion = self._motions.get(key)
        if motion is not None and motion.ended_at is None:
            self._motions[key] = motion._replace(ended_at=now)

    def _end_of(self, motion: ForeignMotion) -> float:
        if motion.ended_at is not None:
            return motion.ended_at
        if motion.last_point_at is None:
            return float("inf")  # until its end is reported
        return motion.last_point_at + (RESULT_GRACE if motion.kind == GOAL else 0.0)

    def busy(self, now: float) -> bool:
        """True while another node's motion may still run."""
        return any(now < self._end_of(motion) for motion in self._motions.values())

    def resume_at(self, now: float) -> Optional[float]:
        """When we may move again: None while another motion runs; else the last end + the quiet time
        (in the past when nothing happened lately)."""
        if self.busy(now):
            return None
        ends = [self._end_of(motion) for motion in self._motions.values()]
        if self._last_end is not None:
            ends.append(self._last_end)
        return (max(ends) + self.quiet_time) if ends else None

    def calm(self, now: float) -> bool:
        """True when no other node moved this controller within the quiet time."""
        resume = self.resume_at(now)
        calm = not self.busy(now) and (resume is None or now >= resume)
        if calm and self._motions:  # forget what can no longer matter
            self._last_end = max([self._end_of(motion) for motion in self._motions.values()] +
                                 ([self._last_end] if self._last_end is not None else []))
            self._motions.clear()
        return calm

    def next_deadline(self, now: float) -> Optional[float]:
        """The next moment `calm` may change (None: nothing pending)."""
        pending = [self._end_of(motion) for motion in self._motions.values() if now < self._end_of(motion)]
        if pending:
            return min(pending) if min(pending) < float("inf") else None
        return self.resume_at(now) if self._motions else None

    def kind_of_latest(self) -> str:
        """The kind of the latest motion seen (GOAL, COMMAND, TWIST or JOINT_ANGLES), or "" when none is known."""
        latest = max(self._motions.values(), key=lambda motion: motion.started, default=None)
        return latest.kind if latest is not None else ""

    @property
    def caller(self) -> str:
        """The caller id of the latest other node seen."""
        return self._latest_caller


def set_angles_on_our_joints(names: Sequence[str], angles: Sequence[float], speed: float, relative: int,
                             positions: Callable[[Sequence[str]], Optional[numpy.ndarray]]
                             ) -> Optional[Tuple[Tuple[str, ...], float]]:
    """Another node's setAngles call (a JointAngles message's fields): the joints of our parts it names and how long
    it runs, from the measured `positions` (their centres when unmeasured); None when it names none of ours."""
    joints = tuple(name for name in names if name in ANIMATED_JOINTS)
    if not joints:
        return None
    measured = positions(joints)
    where = dict(zip(joints, measured.tolist() if measured is not None else map(centre_of, joints)))
    return joints, set_angles_duration(names, list(angles), speed, relative, where)
