"""Streaming a planned motion to naoqi_driver as ``/joint_angles`` messages (naoqi_bridge_msgs/JointAnglesWithSpeed).

naoqi_driver executes each message at once as one ALMotion setAngles(names, angles, speed) call: every named joint
moves from where it is toward its angle at speed x its maximum velocity (the same fraction for every joint the
message names), then stands still; a later message takes over the joints it names, the others keep their targets.
So between two messages a joint moves at a constant speed, then possibly stops. The planned motion (a
`JointTrajectorySpline`, or anything with ``sample(t) -> (positions, velocities, accelerations)`` and `end_time`)
is sent every PERIOD = 1 / RATE s, at the `send_times`; `tick` makes the messages of one send time.

Why these choices. A message sent at t asks the joint to reach a target at some speed; the joint travels
speed x vmax x PERIOD at most before the next message. If that is more than the distance, it arrives early and
stops until the next message (stop-and-go: the stepping that naoqi_dcm_driver shows); if less, it falls behind, and
a lag that each message only carries forward. The one speed at which neither happens makes the joint arrive exactly
when the next message comes. Hence:

* LOOK_AHEAD = PERIOD: the target is where the plan is at the next send time (`stream_targets`), and the speed
  covers the distance from where the joint is to it in exactly one period (`speed_fraction`). The joint is then at
  the planned position at every send time and moves along the chord between them: continuous motion, no lag, and
  an error between the send times of at most (peak acceleration) x PERIOD^2 / 8 (the chord of the curve).
* Where the joint is, is known without measuring it: where the previous message sent it (`tick` returns these
  arrivals for the next call). A measured position would carry the sensor's delay into every speed.
* One speed per joint: a message has one speed, and a joint that needs less than the message's would arrive early
  and stop, so one message for all joints at the fastest joint's speed would make every other joint step. Joints
  are grouped into one message per speed instead. To let joints with nearly the same speed share a message, each
  fraction is rounded up onto a geometric grid of ratio GROUP_RATIO: a joint arrives at most 1 - 1 / GROUP_RATIO of
  a period early (a pause under 2 ms at 10 Hz) and never late, so its arrival is still exactly its target. A
  joint whose target is where it already is gets no message (a plan that holds still sends nothing).
* Bounds: at most SPEED_FRACTION (the robot's cap, 20 %): the plan itself stays under it everywhere, and a chord's
  mean speed never exceeds the curve's peak, so the cap only bites when the joint starts far from the plan (then
  it lags, and the arrivals say by how much); at least SPEED_FLOOR, since setAngles needs a speed > 0 (a joint
  needing less moves under a thousandth of its maximum speed: arriving early is invisible).
* RATE = 10 Hz: the random style accelerates by up to about 3 rad/s^2 and breathing by far less, so the chord
  error stays under 0.004 rad; 20 Hz would quarter it but double the messages, up to one per moving joint per
  send time.

The wire carries float32: `tick` sends float32 values, and its arrivals are those of the values sent. A stop is one
message, every joint to its centre at STOP_SPEED (`stop_message`). Pure Python and numpy: nothing here talks ROS.
"""
import math
from typing import List, Mapping, NamedTuple, Sequence, Tuple

import numpy

from cssr_system.pepper.joint_table import JOINTS, SPEED_FRACTION

RATE = 10.0  # Hz: messages per second for each group of joints
PERIOD = 1.0 / RATE  # s between two send times
LOOK_AHEAD = PERIOD  # s: each message targets the plan at the next send time
SPEED_FLOOR = 0.001  # lowest speed fraction sent (setAngles needs more than 0); breathing hands peak at 0.005
GROUP_RATIO = 1.02  # ratio of the grid speed fractions are rounded up onto, so joints share messages
STOP_SPEED = 0.1  # speed fraction of the return to the centre: calm, half the animation's cap

_FLOAT32 = numpy.float32


def _float32_at_most(value: float) -> float:
    """The highest float32 at or under `value`."""
    rounded = _FLOAT32(value)
    return float(rounded if float(rounded) <= value else numpy.nextafter(rounded, _FLOAT32(-numpy.inf)))


# The speed sent never exceeds SPEED_FRACTION, not even by the float32 rounding of the wire.
_WIRE_CAP = _float32_at_most(SPEED_FRACTION)


class JointAngles(NamedTuple):
    """The contents of one naoqi_bridge_msgs/JointAnglesWithSpeed message (angles absolute: relative 0)."""

    joint_names: Tuple[str, ...]
    joint_angles: Tuple[float, ...]
    speed: float  # fraction of each named joint's maximum velocity
    relative: int = 0


class Tick(NamedTuple):
    """What to send at one send time, and where every joint will be at the next one (the next call's origins)."""

    messages: List[JointAngles]
    arrivals: numpy.ndarray


def _limits(names: Sequence[str]) -> Tuple[numpy.ndarray, numpy.ndarray, numpy.ndarray]:
    """Lower limits, upper limits and maximum velocities of `names`."""
    joints = [JOINTS[name] for name in names]
    return (numpy.array([joint.lower for joint in joints]), numpy.array([joint.upper for joint in joints]),
            numpy.array([joint.max_velocity for joint in joints]))


def send_times(start: float, end: float, rate: float = RATE) -> numpy.ndarray:
    """The send times from `start` on, every 1 / rate s, up to the last one before `end` (the message at that one
    already targets `end` or later). Each time is computed from `start`, so rounding never accumulates."""
    count = max(int(math.ceil((end - start) * rate - 1e-9)), 1)
    return start + numpy.arange(count) / rate


def stream_targets(spline, now: float, look_ahead: float, names: Sequence[str]) -> numpy.ndarray:
    """The planned positions of `names` (the spline's joints, in its order) at now + look_ahead, clamped into
    the joint limits (past the plan's end its last positions)."""
    lower, upper, _ = _limits(names)
    positions = numpy.asarray(spline.sample(now + look_ahead)[0], dtype=float)
    return numpy.clip(positions, lower, upper)


def speed_fraction(names: Sequence[str], origins, targets, period: float = PERIOD) -> numpy.ndarray:
    """Per joint, the speed fraction that takes it from `origins` to `targets` in exactly one `period`, rounded
    up onto the GROUP_RATIO grid from SPEED_FLOOR and kept at or under SPEED_FRACTION (as sent: float32)."""
    _, _, max_velocity = _limits(names)
    needed = numpy.abs(numpy.asarray(targets, dtype=float) - numpy.asarray(origins, dtype=float))
    needed = needed / (period * max_velocity)
    steps = numpy.ceil(numpy.log(numpy.maximum(needed, SPEED_FLOOR) / SPEED_FLOOR) / math.log(GROUP_RATIO) - 1e-9)
    fractions = SPEED_FLOOR * GROUP_RATIO ** numpy.maximum(steps, 0.0)
    # Rounded up to float32 so the joint still arrives in time, then capped by the float32 cap.
    wire = fractions.astype(_FLOAT32)
    wire = numpy.where(wire.astype(float) < fractions, numpy.nextafter(wire, _FLOAT32(numpy.inf)), wire)
    return numpy.minimum(wire.astype(float), _WIRE_CAP)


def arrivals(names: Sequence[str], origins, targets, fractions, period: float = PERIOD) -> numpy.ndarray:
    """Where setAngles takes each joint from `origins` toward `targets` at `fractions` within one `period`."""
    _, _, max_velocity = _limits(names)
    origins = numpy.asarray(origins, dtype=float)
    targets = numpy.asarray(targets, dtype=float)
    reach = numpy.asarray(fractions, dtype=float) * max_velocity * period
    within = numpy.abs(targets - origins) <= reach
    return numpy.where(within, targets, origins + numpy.clip(targets - origins, -reach, reach))


def group_messages(names: Sequence[str], targets, fractions, moving=None) -> List[JointAngles]:
    """One message per distinct speed fraction of the `moving` joints (default: all), naming its joints in `names`
    order (slowest speed first)."""
    moving = numpy.ones(len(names), dtype=bool) if moving is None else numpy.asarray(moving, dtype=bool)
    fractions = numpy.asarray(fractions, dtype=float)
    messages = []
    for fraction in sorted(set(fractions[moving].tolist())):
        chosen = [index for index in range(len(names)) if moving[index] and fractions[index] == fraction]
        messages.append(JointAngles(tuple(names[index] for index in chosen),
                                    tuple(float(targets[index]) for index in chosen), fraction))
    return messages


def tick(names: Sequence[str], spline, now: float, origins, period: float = PERIOD,
         look_ahead: float = LOOK_AHEAD) -> Tick:
    """The messages to send at `now` for the joints `names` (the spline's, in its order), whose positions when
    they arrive are `origins` (the previous tick's arrivals; the measured positions at the first tick)."""
    # float32, as the wire carries the angles: the arrivals are those of the angles executed.
    targets = stream_targets(spline, now, look_ahead, names).astype(_FLOAT32).astype(float)
    fractions = speed_fraction(names, origins, targets, period)
    moving = targets != numpy.asarray(origins, dtype=float)
    return Tick(group_messages(names, targets, fractions, moving),
                arrivals(names, origins, targets, fractions, period))


def stop_message(positions: Mapping[str, float], centre: Mapping[str, float],
                 speed: float = STOP_SPEED) -> JointAngles:
    """The one message that sends every joint of `positions` (where the joints are) to its `centre` (clamped into
    its limits) at a calm `speed`; it takes over whatever the stream last sent them."""
    names = tuple(positions)
    lower, upper, _ = _limits(names)
    angles = numpy.clip([centre[name] for name in names], lower, upper).astype(_FLOAT32).astype(float)
    return JointAngles(names, tuple(angles.tolist()), float(_FLOAT32(speed)))


def stop_duration(positions: Mapping[str, float], message: JointAngles) -> float:
    """How long after it is sent the slowest joint of a `stop_message` arrives (s)."""
    _, _, max_velocity = _limits(message.joint_names)
    distances = numpy.abs(numpy.array(message.joint_angles) - [positions[name] for name in message.joint_names])
    return float((distances / (message.speed * max_velocity)).max(initial=0.0))


def set_angles_duration(names: Sequence[str], angles: Sequence[float], speed: float, relative: int,
                        positions: Mapping[str, float]) -> float:
    """How long one setAngles call (any node's /joint_angles message) moves the joints of `positions` (where they
    are) that it names: until the slowest of them arrives (s); 0 for a call naoqi_driver refuses."""
    if len(names) != len(angles) or not (math.isfinite(speed) and 0.0 < speed <= 1.0):
        return 0.0
    longest = 0.0
    for name, angle in zip(names, angles):
        if name not in positions or name not in JOINTS or not math.isfinite(angle):
            continue
        joint = JOINTS[name]
        target = min(max(positions[name] + angle if relative else angle, joint.lower), joint.upper)
        longest = max(longest, abs(target - positions[name]) / (speed * joint.max_velocity))
    return longest
