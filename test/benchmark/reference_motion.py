"""The reference nodes' motion (reference_node.py, reference_node_ros2.py): each animated part's goals one after
another, planned by the node's own planner (`motion.planners.RandomPlanner`, the random style) from where the part's
previous goal ended, so that the reference sends goals of the same length, points and period as the node, without
listening to /joint_states. Pure Python: the front-end's `send(part, joints, timed)` and `cancel()` do the I/O.

The configuration is the shipped one, for the platform, behaviour `all`, and the keys the benchmark gives
(`configuration_of`)."""
import threading
import time
from typing import Callable, Dict

import numpy

from cssr_system.animate_behaviour.configuration import ALL_BEHAVIOURS, load_configuration
from cssr_system.animate_behaviour.configuration import shipped_configuration_path, topic_file_path
from cssr_system.animate_behaviour.topics import load_topic_map
from cssr_system.motion.planners import RandomPlanner, settled
from cssr_system.motion.waypoints import animated_parts, make_rng
from cssr_system.pepper.joint_table import PARTS

SETTINGS = ("gestureDuration", "numPoints", "numPointsLeg")  # what the benchmark's busy configuration changes


def configuration_of(platform: str, settings: Dict[str, object]):
    """The configuration and the topic map (key -> controller) the node would have with these settings."""
    configuration = load_configuration(shipped_configuration_path(),
                                       dict(settings, platform=platform, behaviour=ALL_BEHAVIOURS))
    return configuration, load_topic_map(topic_file_path(configuration)).topics


class ReferenceMotion:
    """Enabled: every part's goals back to back, each planned at its predecessor's end (and its hold) from that
    goal's last point; disabled: no more goals, the last ones cancelled (`cancel`)."""

    def __init__(self, configuration, part_keys, send: Callable, cancel: Callable[[], None]) -> None:
        rng = make_rng(None)
        self._planners = {motion.part: RandomPlanner(motion, configuration, rng)
                          for motion in animated_parts(configuration, part_keys)}
        self._send, self._cancel = send, cancel
        self._positions = {key: numpy.array(PARTS[key].centre, dtype=float) for key in self._planners}
        self._due: Dict[str, float] = {}  # part -> when its goal ends (monotonic); empty while disabled
        self._condition = threading.Condition()
        self._running = True
        threading.Thread(target=self._run, name="reference motion", daemon=True).start()

    def _next_goal(self, key: str, now: float) -> None:
        zeros = numpy.zeros(len(PARTS[key].joints))
        held = settled(self._planners[key](now, self._positions[key], zeros, zeros))
        self._positions[key] = held.positions[-1]
        self._due[key] = now + float(held.times[-1])
        self._send(key, PARTS[key].joints, held)

    def enable(self) -> None:
        with self._condition:
            now = time.monotonic()
            for key in self._planners:
                self._next_goal(key, now)
            self._condition.notify()

    def disable(self) -> None:
        with self._condition:
            self._due.clear()
            self._cancel()

    def close(self) -> None:
        with self._condition:
            self._running = False
            self._condition.notify()

    def _run(self) -> None:
        with self._condition:
            while self._running:
                now = time.monotonic()
                for key in [key for key, due in self._due.items() if due <= now]:
                    self._next_goal(key, now)
                self._condition.wait(min(self._due.values()) - now if self._due else None)
