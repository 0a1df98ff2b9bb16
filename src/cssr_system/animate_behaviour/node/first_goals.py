"""The first goals of the next enable, planned while the node is disabled (README: "Performance").

Planning and timing a goal of 100 points takes about a millisecond of Python per part; planned ahead, an enable
only sends them, so every part's first goal leaves within milliseconds of the request. They are planned from
where the parts rest, with the configuration the next enable is expected to bring (the last one applied), and
the random generator that enable would use: with a `randomSeed` the motions are the same as if planned at the
enable. An enable whose configuration differs ignores them; a part that has moved since gets a goal planned
afresh. The breathing style is planned at the enable: its rhythm starts then.
"""
from typing import Dict, Mapping, NamedTuple, Optional, Tuple

from cssr_system.animate_behaviour.configuration import Configuration
from cssr_system.animate_behaviour.motion.styles import RANDOM, MotionStyle, Planner
from cssr_system.animate_behaviour.motion.waypoints import animated_parts, make_rng
from cssr_system.animate_behaviour.node.part_stream import PartStream, PreparedGoal, prepare_goal
from cssr_system.pepper.joint_table import PARTS


class PreparedEnable(NamedTuple):
    config: Configuration
    topics: Dict[str, str]
    rng: object  # numpy.random.Generator, advanced past the prepared goals
    style: MotionStyle
    goals: Dict[str, Tuple[Planner, PreparedGoal]]  # part -> its planner and first goal

    def matches(self, config: Configuration, topics: Mapping[str, str]) -> bool:
        return config == self.config and dict(topics) == self.topics

    def fits(self, streams: Mapping[str, PartStream]) -> bool:
        """Every part is idle and still where its first goal starts."""
        for part, (_, goal) in self.goals.items():
            stream = streams.get(self.topics[part])
            measured = None if stream is None or stream.active else stream.measured_positions()
            if measured is None or not goal.fits(measured):
                return False
        return True


def prepare_enable(config: Configuration, topics: Mapping[str, str], rng,
                   streams: Mapping[str, PartStream]) -> Optional[PreparedEnable]:
    """The first goals of an enable with `config` and `topics`, from the measured joints of the idle parts
    (`streams` by action); None for the breathing style, or while a part is not idle or its joints unknown.
    `rng`: the node's generator, used (and advanced) unless the configuration has a seed."""
    if config.motion_style != RANDOM:
        return None
    motions = animated_parts(config, [key for key in topics if key in PARTS])
    starts = {}
    for motion in motions:
        stream = streams.get(topics[motion.part])
        starts[motion.part] = None if stream is None or stream.active else stream.measured_positions()
        if starts[motion.part] is None:
            return None
    rng = make_rng(config.random_seed) if config.random_seed is not None or rng is None else rng
    style = MotionStyle(config, rng)
    goals = {}
    for motion in motions:  # in the order an enable plans them: the same draws from a seeded generator
        planner = style.planner(motion)
        goals[motion.part] = (planner, prepare_goal(motion.part, planner, starts[motion.part]))
    return PreparedEnable(config, dict(topics), rng, style, goals)
