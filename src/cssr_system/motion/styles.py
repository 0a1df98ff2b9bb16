"""Motion styles (README: "Motion styles"): what the goals of a part carry. `random` is the band formula's
random waypoints, timed smoothly (`planners.RandomPlanner`); `breathing` is `breathing.BreathingPlanner`. Either way
a part's goals are built by a `planners.Planner`. The mode of the conversation (`modes`) shapes them: listening slows
the tempo, speaking makes the arms and hands beat (`modes.BeatPlanner`) whatever the style."""
from typing import Dict, Tuple

import numpy

from cssr_system.animate_behaviour.configuration import MOTION_STYLES
from cssr_system.motion.breathing import BreathingPlanner
from cssr_system.motion.modes import BEAT_PARTS, IDLE, SPEAKING, BeatPlanner, mode_config
from cssr_system.motion.planners import Planner, RandomPlanner
from cssr_system.motion.waypoints import PartMotion

RANDOM, BREATHING = MOTION_STYLES
# The base in the breathing style turns rarely and slowly: longer pauses, half the peak speed.
BASE_PAUSES = {RANDOM: (1.0, 4.0), BREATHING: (8.0, 20.0)}  # s of stillness after each turn
BASE_SPEED_SHARE = {RANDOM: 1.0, BREATHING: 0.5}


class MotionStyle:
    """The planners of the parts of one enable: parts of the breathing style share its rhythm and clock."""

    def __init__(self, config, rng: numpy.random.Generator, mode: str = IDLE) -> None:
        self.name = config.motion_style
        self.mode = mode
        self._config = mode_config(config, mode)
        self._rng = rng
        self._shared: Dict[str, object] = {}
        self._epoch: Dict[str, float] = {}

    def planner(self, motion: PartMotion) -> Planner:
        if self.mode == SPEAKING and motion.part in BEAT_PARTS:
            return BeatPlanner(motion, self._config, self._rng)
        if self.name == BREATHING:
            return BreathingPlanner(motion, self._config, self._shared, self._rng, self._epoch)
        return RandomPlanner(motion, self._config, self._rng)

    @property
    def base_pauses(self) -> Tuple[float, float]:
        return BASE_PAUSES[self.name]

    @property
    def base_speed_share(self) -> float:
        return BASE_SPEED_SHARE[self.name]
