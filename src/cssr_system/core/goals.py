"""What a part stream (core/part_stream.py) keeps of the goals it sends, and the controller client it sends them
through (README: "Controllers: what each goal carries").

The client is the front-end's (ros1/trajectory_client.py on ROS 1, ros2/trajectory_client.py on ROS 2):

- ``client.goal(joints, timed)``: the FollowJointTrajectory goal of a planned trajectory (`planners.settled` already
  applied), built before it is sent: a stop builds every part's goal before the first one leaves;
- ``client.send(goal, done)``: sends it and returns a handle with ``cancel()`` and ``release()`` (the goal no longer
  runs for us: only its end is awaited). When the goal ends, ``done(state, error_code, error_string)`` is called
  from any thread, with `state` one of the names below and the result's error code (None without a result);
  WITHHELD when the client's last look before sending found another client's goal on the controller, so that the
  goal never left (README: "Sharing the robot").
"""
from typing import NamedTuple, Optional

import numpy

from cssr_system.motion.trajectory_timing import TimedTrajectory, to_points
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline

# A goal's end, as the log names it: actionlib's names, which the ROS 2 front-end maps its own states onto.
SUCCEEDED, ABORTED, PREEMPTED, REJECTED, RECALLED, LOST = (
    "SUCCEEDED", "ABORTED", "PREEMPTED", "REJECTED", "RECALLED", "LOST")
# A goal not sent after all: another client's goal had reached the controller (core/foreign_goals.py).
WITHHELD = "WITHHELD"
# The log's final state of a goal whose end had not been reported when the node exited.
RUNNING_AT_EXIT = "RUNNING_AT_EXIT"
# control_msgs' FollowJointTrajectory result code for a goal aborted for its end state (the same on ROS 1 and 2).
GOAL_TOLERANCE_VIOLATED = -5


class OutgoingGoal(NamedTuple):
    """A goal planned and built, not yet sent: a stop plans every part's goal before the first one leaves."""
    purpose: str  # PURPOSE_ANIMATE or PURPOSE_HOME
    planned_at: Optional[float]  # on the stream's clock, when the goal starts; None: that clock does not run yet
    start_state: tuple  # (positions, velocities, accelerations) it starts from
    timed: TimedTrajectory  # as planned (the log's waypoints)
    duration: float  # s, with the hold the goal carries (planners.settled)
    goal: object  # the client's message
    replaced_after: Optional[float] = None  # s after its start when the next goal replaces it (None: at its end)


class RunningGoal:
    """A goal of ours: its number, purpose, the client's handle, and the motion the controller makes of it.

    A goal sent while the clock did not run yet (simulated time before its first /clock message) starts when the
    clock starts: `start(now)` dates it then."""

    def __init__(self, number: int, purpose: str, handle, outgoing: OutgoingGoal) -> None:
        self.number = number
        self.purpose = purpose
        self.handle = handle
        self.duration = outgoing.duration
        self.replaced_by = ""  # the other node whose goal or trajectory replaced this one on the controller
        self.replaced_after = outgoing.replaced_after
        self.start_time: Optional[float] = None
        self.end_time = float("inf")
        self.last_positions = numpy.array(outgoing.timed.positions[-1], dtype=float)
        self._start_state = tuple(None if vector is None else numpy.array(vector, dtype=float)
                                  for vector in outgoing.start_state)  # a copy: the callers' arrays may change
        self._timed: Optional[TimedTrajectory] = outgoing.timed
        self._spline: Optional[JointTrajectorySpline] = None
        if outgoing.planned_at is not None:
            self.start(outgoing.planned_at)

    def start(self, now: float) -> None:
        self.start_time = now
        self.end_time = now + self.duration

    @property
    def replacement_time(self) -> Optional[float]:
        """When the next goal replaces this one, on the stream's clock (None: when it ends, or not dated yet)."""
        if self.replaced_after is None or self.start_time is None:
            return None
        return self.start_time + self.replaced_after

    @property
    def dated(self) -> bool:
        return self.start_time is not None

    @property
    def spline(self) -> JointTrajectorySpline:
        """What the controller executes. Built when first needed (the next goal's start), not while goals are
        being sent: at an enable every millisecond before the last part's goal counts."""
        if self._spline is None:
            self._spline = JointTrajectorySpline(*self._start_state, to_points(self._timed),
                                                 start_time=self.start_time or 0.0)
        return self._spline

    def prepare(self) -> None:
        """Builds the spline and every segment's polynomial ahead, while nothing waits, so that the next goal or a
        stop that starts from this one only samples it."""
        if self._timed is not None and self.dated:
            self.spline.compute_segments()

    def release(self) -> None:
        """The goal no longer runs for us (replaced, cancelled, yielded): only its end is still awaited, for the log.
        Its motion is let go, and the client lets the message's points go, so that up to
        part_stream.MAX_UNFINISHED_GOALS of them cost little."""
        self.handle.release()
        self._start_state = self._timed = self._spline = None
