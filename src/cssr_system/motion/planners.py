"""What the node asks of the motion: the next goal of a part, from where the part is (README: "Motion styles").

A `Planner` gives, for a part's current state (positions, velocities and accelerations at time `now` on the clock
the controller executes goals on), its next goal as a `TimedTrajectory` with times relative to `now`. Three kinds:
the random style (`RandomPlanner`), the breathing style (`breathing.BreathingPlanner`) and the return to the centre
after a disable (`HomePlanner`). Every goal ends at rest. `replacement_time` tells the node when to send the next
goal: None, when the goal has ended; a number of seconds after the goal's start, before its ending begins (a
continuous style, whose goals are replaced while they move; their ending only plays when no next goal comes).

Every goal is sent with a hold (`settled`; README: "Controllers: what each goal carries"): its last
position again, SETTLE_TIME later. joint_trajectory_controller judges a goal at the first control update after its
last point: every joint's velocity must then be within `stopped_velocity_tolerance` (0.01 rad/s by default).
Hardware that measures velocity as a difference of positions still reports motion for one or two control periods
after the command has stopped (up to 0.17 s at the robot driver's 12 Hz); after the hold it reports none. The goal's
`goal_time_tolerance` (GOAL_TIME_TOLERANCE) gives joints that lag further (a simulator's velocity controllers) time
to settle before the controller would abort.

Pure Python and numpy.
"""
from typing import Optional

import numpy

from cssr_system.motion.trajectory_timing import TimedTrajectory, time_trajectory
from cssr_system.motion.waypoints import PartMotion, random_waypoints
from cssr_system.pepper.joint_table import PARTS

SETTLE_TIME = 0.25  # s a goal that ends at rest holds its last point: 3 control periods at 12 Hz
GOAL_TIME_TOLERANCE = 0.5  # s after a goal's end the controller may wait for the joints to settle (every goal)
HOME_GESTURE_DURATION = 0.5  # s, the shortest return to the centre on disable (stretched as needed)
REFERENCE_TEMPO = 12.0  # breaths per minute at which the random style's gestures take gestureDuration


class Planner:
    """The next goal of one part: ``planner(now, positions, velocities, accelerations)`` -> a `TimedTrajectory`."""

    def __call__(self, now: float, positions, velocities, accelerations) -> TimedTrajectory:
        raise NotImplementedError

    def replacement_time(self, timed: TimedTrajectory) -> Optional[float]:
        """Seconds after the start of the goal `timed` when the next goal replaces it (None: when it has ended)."""
        return None


def settled(timed: TimedTrajectory) -> TimedTrajectory:
    """`timed` with its last point held for SETTLE_TIME more, if it ends at rest (else `timed` itself)."""
    last = len(timed.times) - 1
    if numpy.any(timed.velocities[last]) or numpy.any(timed.accelerations[last]):
        return timed
    return TimedTrajectory(numpy.append(timed.times, timed.times[last] + SETTLE_TIME),
                           numpy.vstack([timed.positions, timed.positions[last:]]),
                           numpy.vstack([timed.velocities, numpy.zeros_like(timed.velocities[last:])]),
                           numpy.vstack([timed.accelerations, numpy.zeros_like(timed.accelerations[last:])]))


class RandomPlanner(Planner):
    """The random style: the band formula's random waypoints, timed smoothly, ending at rest."""

    def __init__(self, motion: PartMotion, config, rng: numpy.random.Generator) -> None:
        self._motion = motion
        self._config = config
        self._rng = rng

    def __call__(self, now, positions, velocities, accelerations) -> TimedTrajectory:
        waypoints = random_waypoints(self._motion, self._config, self._rng)
        # The tempo (breathsPerMinute) paces this style too.
        duration = self._config.gesture_duration * REFERENCE_TEMPO / self._config.breaths_per_minute
        return time_trajectory(waypoints, self._motion.joints, positions, velocities, duration,
                               start_accelerations=accelerations)


class HomePlanner(Planner):
    """One goal to the part's centre; from a moving joint it brakes inside the band it was animated in."""

    def __init__(self, part: str, motion: Optional[PartMotion] = None) -> None:
        self._part = part
        bands = motion.bounds if motion is not None else ()
        self._bounds = ([b.lower for b in bands], [b.upper for b in bands]) if bands else None

    def __call__(self, now, positions, velocities, accelerations) -> TimedTrajectory:
        part = PARTS[self._part]
        return time_trajectory(numpy.array([part.centre]), part.joints, positions, velocities, HOME_GESTURE_DURATION,
                               start_accelerations=accelerations, position_bounds=self._bounds)
