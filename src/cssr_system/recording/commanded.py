"""What a node commanded the joint controllers, rebuilt from the goals the controllers received.

A FollowJointTrajectory controller (joint_trajectory_controller, and the simulated Pepper that
behaves like it) executes one goal at a time: a new goal is spliced onto the motion in progress (its
first segment starts from the controller's state at that moment), a cancel holds the position
reached, and after its last point the controller holds the last position. `controller_pieces` replays
the goals and cancels of every controller in the order they were received, with the package's model
of the controller's interpolation (`cssr_system.pepper.trajectory_interpolation`), so velocities and
accelerations of the points count as they do on the controller. `commanded_by` samples the pieces of
one node at given times: the position that node told the controller to be at, NaN while another
node's goal (or nothing) was in effect. `goal_marks` turns the goals of other nodes into labelled
intervals of the recording (from receipt to result).

With the joint_angles actuation the node sends setAngles calls to naoqi_driver instead (`SentCall`):
`commanded_by_calls` replays every node's calls with the package's model of setAngles
(`cssr_system.pepper.simulated_pepper.NaoqiDriver`), from the measured joints, and keeps a joint's
positions while the last call naming it was the node's; `call_marks` turns other nodes' calls into
intervals, as `goal_marks` does for goals.

On ROS 2 no third node sees an action's goals (they are service calls), but ros2_controllers'
joint_trajectory_controller, and the simulated Pepper that behaves like it, publishes its desired state at each
update (``<controller>/controller_state``, its ``reference``: `ReferenceSample`). `commanded_by_reference` takes that
as the node's command from the node's first goal to a part (its log's ``goal_sent``) until another node's motion
makes the part yield (``part_yielded``), and again from the node's next goal.

Goals whose joints are not exactly the controller's, or whose times do not increase, are rejected by
the controller and skipped here. A goal's trajectory is taken to start when it was received (the
package's node and the demo's gesture player send a zero stamp: "start now").

Pure Python and numpy: no ROS import.
"""
from collections import OrderedDict
from typing import Dict, Iterable, List, NamedTuple, Optional, Sequence, Tuple

import numpy

from cssr_system.pepper.joint_table import JOINTS, PARTS
from cssr_system.pepper.simulated_pepper import NaoqiDriver, joint_angles_problem
from cssr_system.pepper.trajectory_interpolation import (JointTrajectorySpline, TrajectoryError, TrajectoryPoint,
                                                         sample_trajectory)
from cssr_system.recording.recording import Commanded, Mark


class SentGoal(NamedTuple):
    """A goal as a controller received it."""

    time: float  # when it was received (s, on the recording's clock)
    part: str  # key of joint_table.PARTS
    caller: str  # the node that sent it, e.g. "/animateBehaviour"
    goal_id: str
    joint_names: Tuple[str, ...]
    points: Tuple[TrajectoryPoint, ...]


class CancelRequest(NamedTuple):
    """A cancel as a controller received it (actionlib_msgs/GoalID)."""

    time: float
    part: str
    goal_id: str  # "": every goal sent at or before `stamp` (every goal when `stamp` is 0)
    stamp: float = 0.0


class GoalResult(NamedTuple):
    """The end of a goal as its controller reported it."""

    time: float
    part: str
    goal_id: str
    state: str  # actionlib's terminal state: SUCCEEDED, PREEMPTED, ABORTED, REJECTED, ...


class SentCall(NamedTuple):
    """A setAngles call as naoqi_driver received it (naoqi_bridge_msgs/JointAnglesWithSpeed)."""

    time: float
    caller: str
    joint_names: Tuple[str, ...]
    joint_angles: Tuple[float, ...]
    speed: float
    relative: int = 0


class ReferenceSample(NamedTuple):
    """A controller's desired state at one of its updates (ROS 2's controller_state ``reference``)."""

    time: float  # the update's (s, on the recording's clock)
    part: str  # key of joint_table.PARTS
    joint_names: Tuple[str, ...]
    positions: Tuple[float, ...]


CALL_GAP = 1.0  # s: another node's calls this close together make one mark


class Piece(NamedTuple):
    """What a controller executes from `start` until the next piece of the same controller."""

    start: float
    caller: str
    goal_id: str
    joint_names: Tuple[str, ...]
    spline: Optional[JointTrajectorySpline]  # None: holds `held`
    held: Optional[numpy.ndarray]


Measured = Tuple[Sequence[str], numpy.ndarray, numpy.ndarray]  # (joint names, times, positions (N, J))


def _measured_at(measured: Optional[Measured], joints: Sequence[str], time: float) -> numpy.ndarray:
    """Positions of `joints` at `time` from the measured joint states (nearest sample before or at
    it, else the first); a joint never measured is at its part's rest centre."""
    centres = {name: centre for part in PARTS.values() for name, centre in zip(part.joints, part.centre)}
    result = numpy.array([centres.get(name, 0.0) for name in joints], dtype=float)
    if measured is None or len(measured[1]) == 0:
        return result
    names, times, positions = measured
    row = max(0, int(numpy.searchsorted(times, time, side="right")) - 1)
    for index, name in enumerate(joints):
        if name in names:
            value = positions[row, list(names).index(name)]
            if numpy.isfinite(value):
                result[index] = value
    return result


def _state_of(piece: Piece, joints: Sequence[str], time: float) -> Tuple[numpy.ndarray, ...]:
    """(positions, velocities, accelerations) of `joints` that `piece` commands at `time`."""
    order = [piece.joint_names.index(name) for name in joints]
    if piece.spline is None:
        zeros = numpy.zeros(len(joints))
        return piece.held[order], zeros, zeros
    return tuple(numpy.asarray(values)[order] for values in piece.spline.sample(time))


def _cancels(request: CancelRequest, piece: Piece) -> bool:
    if request.goal_id:
        return request.goal_id == piece.goal_id
    return request.stamp == 0.0 or piece.start <= request.stamp


def controller_pieces(goals: Iterable[SentGoal], cancels: Iterable[CancelRequest] = (),
                      measured: Optional[Measured] = None) -> Dict[str, List[Piece]]:
    """Per part key, the pieces its controller executed, in time order. A goal received while the
    controller executes nothing starts from the measured joints (`measured`), at rest."""
    events = sorted([(goal.time, 0, goal) for goal in goals] + [(cancel.time, 1, cancel) for cancel in cancels],
                    key=lambda event: (event[0], event[1]))
    pieces = OrderedDict()  # type: Dict[str, List[Piece]]
    for time, _, event in events:
        if event.part not in PARTS:
            continue
        current = pieces.get(event.part, [None])[-1]
        if isinstance(event, CancelRequest):
            if current is not None and current.spline is not None and _cancels(event, current):
                held = _state_of(current, current.joint_names, time)[0]
                pieces[event.part].append(Piece(time, current.caller, current.goal_id, current.joint_names,
                                                None, held))
            continue
        joints = tuple(event.joint_names)
        if sorted(joints) != sorted(PARTS[event.part].joints):
            continue  # the controller rejects it (INVALID_JOINTS)
        if current is None:
            zeros = numpy.zeros(len(joints))
            start = (_measured_at(measured, joints, time), zeros, zeros)
        else:
            start = _state_of(current, joints, time)
        try:
            spline = JointTrajectorySpline(start[0], start[1], start[2], event.points, start_time=time)
        except TrajectoryError:
            continue  # the controller rejects it (INVALID_GOAL)
        pieces.setdefault(event.part, []).append(Piece(time, event.caller, event.goal_id, joints, spline, None))
    return pieces


def commanded_by(source: str, pieces: Dict[str, List[Piece]], times: Sequence[float]) -> Optional[Commanded]:
    """The positions `source` commanded at `times`, for every joint of the parts it sent a goal to
    (``PARTS`` order); None when it sent none."""
    times = numpy.asarray(times, dtype=float).reshape(-1)
    parts = [key for key in PARTS if any(piece.caller == source for piece in pieces.get(key, ()))]
    if not parts:
        return None
    joint_names = tuple(name for key in parts for name in PARTS[key].joints)
    positions = numpy.full((len(times), len(joint_names)), numpy.nan)
    column = 0
    for key in parts:
        joints = PARTS[key].joints
        part_pieces = pieces[key]
        which = numpy.searchsorted([piece.start for piece in part_pieces], times, side="right") - 1
        for index, piece in enumerate(part_pieces):
            rows = which == index
            if piece.caller != source or not numpy.any(rows):
                continue
            order = [piece.joint_names.index(name) for name in joints]
            if piece.spline is None:
                positions[rows, column:column + len(joints)] = piece.held[order]
            else:
                positions[rows, column:column + len(joints)] = sample_trajectory(piece.spline, times[rows])[0][:, order]
        column += len(joints)
    return Commanded(joint_names, times, positions, source)


def goal_marks(goals: Iterable[SentGoal], results: Iterable[GoalResult], exclude_caller: str,
               end: float) -> Tuple[Mark, ...]:
    """A mark for every goal not sent by `exclude_caller`: from its receipt to its result (or
    `end` when none came), labelled with the sender and the final state."""
    results = sorted(results, key=lambda result: result.time)
    marks = []
    for goal in sorted(goals, key=lambda goal: goal.time):
        if goal.caller == exclude_caller:
            continue
        result = next((result for result in results
                       if result.goal_id == goal.goal_id and result.time >= goal.time), None)
        state = result.state if result is not None else "no result"
        finish = result.time if result is not None else max(end, goal.time)
        marks.append(Mark(goal.time, finish, "%s: %s" % (goal.caller, state), goal.part))
    return tuple(marks)


def commanded_by_calls(source: str, calls: Iterable[SentCall], times: Sequence[float],
                       measured: Optional[Measured] = None) -> Optional[Commanded]:
    """The positions `source`'s setAngles calls command at `times` (sorted), for every joint of the parts they
    name (``PARTS`` order): every valid call replayed in order from the measured joints at the first of them; a
    joint is NaN before `source` names it and while another node's call is the last to name it. None when
    `source` sent no call."""
    calls = sorted((call for call in calls if joint_angles_problem(call.joint_names, call.joint_angles,
                                                                   call.speed) is None), key=lambda call: call.time)
    named = {name for call in calls if call.caller == source for name in call.joint_names}
    parts = [key for key in PARTS if named & set(PARTS[key].joints)]
    if not parts:
        return None
    joint_names = tuple(name for key in parts for name in PARTS[key].joints)
    column = {name: index for index, name in enumerate(joint_names)}
    driver = NaoqiDriver(JOINTS, _measured_at(measured, tuple(JOINTS), calls[0].time), calls[0].time)
    ours = numpy.zeros(len(joint_names), dtype=bool)  # the last call naming the joint was `source`'s
    times = numpy.asarray(times, dtype=float).reshape(-1)
    positions = numpy.full((len(times), len(joint_names)), numpy.nan)
    pending = 0
    for row, time in enumerate(times):
        while pending < len(calls) and calls[pending].time <= time:
            call = calls[pending]
            driver.set_angles(call.joint_names, call.joint_angles, call.speed, call.time, bool(call.relative))
            for name in call.joint_names:
                if name in column:
                    ours[column[name]] = call.caller == source
            pending += 1
        state = dict(zip(JOINTS, driver.state(time)[0]))
        positions[row] = numpy.where(ours, [state[name] for name in joint_names], numpy.nan)
    return Commanded(joint_names, times, positions, source)


def call_marks(calls: Iterable[SentCall], exclude_caller: str, gap: float = CALL_GAP) -> Tuple[Mark, ...]:
    """A mark for every burst of setAngles calls of a node other than `exclude_caller` (calls less than `gap` s
    apart), on the panel of the part of its first joint."""
    marks: List[Mark] = []
    latest: Dict[str, int] = {}  # caller -> index of its open mark
    for call in sorted(calls, key=lambda call: call.time):
        if call.caller == exclude_caller:
            continue
        index = latest.get(call.caller)
        if index is not None and call.time - marks[index].end <= gap:
            marks[index] = marks[index]._replace(end=call.time)
            continue
        part = next((key for key, part in PARTS.items() if call.joint_names and call.joint_names[0] in part.joints),
                    "")
        latest[call.caller] = len(marks)
        marks.append(Mark(call.time, call.time, "%s: joint_angles" % call.caller, part))
    return tuple(marks)


def _ours(part: str, goals_sent: Iterable[Tuple[float, str]], yielded: Iterable[Tuple[float, str]],
          times: numpy.ndarray) -> numpy.ndarray:
    """Whether the node's command is in effect on `part` at `times`: from each of its goals (`goals_sent`: (time,
    part)) until the part next yields (`yielded`: (time, part))."""
    switches = sorted([(time, True) for time, key in goals_sent if key == part]
                      + [(time, False) for time, key in yielded if key == part])
    if not switches:
        return numpy.zeros(len(times), dtype=bool)
    which = numpy.searchsorted([time for time, _ in switches], times, side="right") - 1
    return (which >= 0) & numpy.array([ours for _, ours in switches])[numpy.maximum(which, 0)]


def commanded_by_reference(source: str, samples: Iterable[ReferenceSample], times: Sequence[float],
                           goals_sent: Iterable[Tuple[float, str]],
                           yielded: Iterable[Tuple[float, str]] = ()) -> Optional[Commanded]:
    """The positions `source` commanded at `times`: for every part it sent a goal to (``PARTS`` order), the
    reference of the part's controller, interpolated between its updates (the desired motion runs on between them, as
    ROS 1's replayed goals show it) and held after the last; NaN before the first update, before the node's first goal
    and while the part yields (`_ours`). None when no part the node sent a goal to has a reference sample."""
    goals_sent, yielded = list(goals_sent), list(yielded)
    by_part: Dict[str, List[ReferenceSample]] = {}
    for sample in samples:
        by_part.setdefault(sample.part, []).append(sample)
    parts = [key for key in PARTS if key in by_part and any(part == key for _, part in goals_sent)]
    if not parts:
        return None
    times = numpy.asarray(times, dtype=float).reshape(-1)
    joint_names = tuple(name for key in parts for name in PARTS[key].joints)
    positions = numpy.full((len(times), len(joint_names)), numpy.nan)
    column = 0
    for key in parts:
        joints = PARTS[key].joints
        # One sample per update (the same update may be published twice).
        part_samples = list({sample.time: sample for sample in by_part[key]}.values())
        part_samples.sort(key=lambda sample: sample.time)
        sample_times = numpy.array([sample.time for sample in part_samples])
        values = numpy.array([[dict(zip(sample.joint_names, sample.positions)).get(name, numpy.nan)
                               for name in joints] for sample in part_samples], dtype=float)
        rows = (times >= sample_times[0]) & _ours(key, goals_sent, yielded, times)
        for index in range(len(joints)):
            positions[rows, column + index] = numpy.interp(times[rows], sample_times, values[:, index])
        column += len(joints)
    return Commanded(joint_names, times, positions, source)
