"""Motion styles (README: "Motion styles"): what the goals of a part carry. `random` is the band formula's
random waypoints, timed smoothly (`waypoints`, `trajectory_timing`); `breathing` is `breathing.BreathingPlanner`.
Either way a part's goals are built by a `Planner`: ``plan(now, positions, velocities, accelerations)`` gives the
next goal of the part as a `TimedTrajectory` from its current state."""
from typing import Callable, Dict, Tuple

import numpy

from cssr_system.animate_behaviour.configuration import MOTION_STYLES
from cssr_system.animate_behaviour.motion.breathing import BreathingPlanner
from cssr_system.animate_behaviour.motion.trajectory_timing import TimedTrajectory, time_trajectory
from cssr_system.animate_behaviour.motion.waypoints import PartMotion, random_waypoints
from cssr_system.pepper.joint_table import PARTS

RANDOM, BREATHING = MOTION_STYLES
# The base in the breathing style turns rarely and slowly: longer pauses, half the peak speed.
BASE_PAUSES = {RANDOM: (1.0, 4.0), BREATHING: (8.0, 20.0)}  # s of stillness after each turn
BASE_SPEED_SHARE = {RANDOM: 1.0, BREATHING: 0.5}

# The next goal of a part: (now, positions, velocities, accelerations) -> a trajectory from that state.
Planner = Callable[[float, numpy.ndarray, numpy.ndarray, numpy.ndarray], TimedTrajectory]


class MotionStyle:
    """The planners of the parts of one enable: parts of the breathing style share its rhythm and clock."""

    def __init__(self, config, rng: numpy.random.Generator) -> None:
        self.name = config.motion_style
        self._config = config
        self._rng = rng
        self._shared: Dict[str, object] = {}
        self._epoch: Dict[str, float] = {}

    def planner(self, motion: PartMotion) -> Planner:
        if self.name == BREATHING:
            return BreathingPlanner(motion, self._config, self._shared, self._rng, self._epoch)
        config, rng, joints = self._config, self._rng, PARTS[motion.part].joints

        def plan(now, positions, velocities, accelerations):
            return time_trajectory(random_waypoints(motion, config, rng), joints, positions, velocities,
                                   config.gesture_duration, start_accelerations=accelerations)
        return plan

    @property
    def base_pauses(self) -> Tuple[float, float]:
        return BASE_PAUSES[self.name]

    @property
    def base_speed_share(self) -> float:
        return BASE_SPEED_SHARE[self.name]
