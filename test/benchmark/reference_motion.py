"""The reference nodes' motion (reference_node.py, reference_node_ros2.py): each animated part's goals one after
another, planned by the node's own planner (`motion.styles.MotionStyle`, the configured style) from where the part's
previous goal ended, so that the reference sends goals of the same length, points and period as the node, without
listening to /joint_states; and, where the behaviour turns the base, the node's base turns
(`motion.base_rotation.BaseRotationPlanner`: one command a turn on `cmd_moveto`, a velocity sample every 50 ms of a
turn on a velocity topic). At a disable (and at the exit) it stops as the node does with the shipped `homeOnDisable`:
each part's goal is replaced by one back to its centre (`motion.planners.HomePlanner`, planned from where the part's
goal ends), a velocity turn under way ends with a zero, and the base turns back to its heading of enable. Pure
Python: the front-end's `send(part, joints, timed)` and `turn(angular_z)` do the I/O.

The configuration is the shipped one, for the platform, behaviour `all`, and the keys the benchmark gives
(`configuration_of`)."""
import threading
import time
from typing import Callable, Dict, Optional

import numpy

from cssr_system.animate_behaviour.configuration import ALL_BEHAVIOURS, load_configuration
from cssr_system.animate_behaviour.configuration import shipped_configuration_path, topic_file_path
from cssr_system.animate_behaviour.topics import WHEELS_KEY, load_topic_map
from cssr_system.motion.base_rotation import BaseRotationPlanner
from cssr_system.motion.planners import HomePlanner, settled
from cssr_system.motion.styles import MotionStyle
from cssr_system.motion.waypoints import animated_parts, make_rng
from cssr_system.pepper.joint_table import PARTS, VELOCITY, wheels_command_kind

SETTINGS = ("gestureDuration", "numPoints", "numPointsLeg")  # what the benchmark's busy configuration changes


def configuration_of(platform: str, settings: Dict[str, object]):
    """The configuration and the topic map (key -> controller) the node would have with these settings."""
    configuration = load_configuration(shipped_configuration_path(),
                                       dict(settings, platform=platform, behaviour=ALL_BEHAVIOURS))
    return configuration, load_topic_map(topic_file_path(configuration)).topics


class BaseTurns:
    """The base's turns as the node plans them: each step's command or velocity samples, then its pause."""

    def __init__(self, configuration, style: MotionStyle, wheels: str, rng, turn: Callable[[float], None]) -> None:
        self.planner = BaseRotationPlanner(wheels_command_kind(wheels),
                                           configuration.rot_maximum_range * style.base_speed_share,
                                           configuration.heading_bound, rng, pause_range=style.base_pauses)
        self._turn = turn
        self._step, self._started, self._sample = None, 0.0, 0
        self._returning = False  # the turn under way is the return to the heading of enable: none follows it
        self.due: Optional[float] = None  # when the next sample or step is due (monotonic); None: stopped

    def start(self, now: float) -> None:
        self._begin(self.planner.next_step(), now)

    def _begin(self, step, now: float) -> None:
        self._step, self._started, self._sample = step, now, 0
        if self._step.kind == VELOCITY:
            self.due = now
        else:
            self._turn(self._step.angle)
            self.due = now + self._step.duration

    def tick(self, now: float) -> None:
        step = self._step
        if step.kind == VELOCITY and self._sample < len(step.velocities):
            self._turn(step.velocities[self._sample])
            self._sample += 1
            self.due = self._started + (self._sample * step.period if self._sample < len(step.velocities)
                                        else step.duration)
        elif self._returning:
            self._returning, self.due = False, None
        else:
            self.start(now)

    def stop(self, now: float) -> None:
        """A velocity turn under way ends with an explicit zero, as the node's does; then the turn back."""
        if self.due is not None and self._step.kind == VELOCITY and 0 < self._sample < len(self._step.velocities):
            self._turn(0.0)
        self.due = None
        step = self.planner.return_step()
        if step is not None:
            self._returning = True
            self._begin(step, now)


class ReferenceMotion:
    """Enabled: every part's goals back to back, each planned at its predecessor's end (and its hold) from that
    goal's last point, and the base's turns; disabled: each part's return to its centre, the base's turn back."""

    def __init__(self, configuration, topics: Dict[str, str], send: Callable, turn: Callable[[float], None]) -> None:
        rng = make_rng(None)
        style = MotionStyle(configuration, rng)
        motions = animated_parts(configuration, topics)
        self._planners = {motion.part: style.planner(motion) for motion in motions}
        self._home_planners = {motion.part: HomePlanner(motion.part, motion) for motion in motions}
        self._send = send
        wheels = topics.get(WHEELS_KEY) if "rotation" in configuration.behaviour and configuration.turn_base else None
        self._base = BaseTurns(configuration, style, wheels, rng, turn) if wheels else None
        self._positions = {key: numpy.array(PARTS[key].centre, dtype=float) for key in self._planners}
        self._due: Dict[str, float] = {}  # part -> when its goal ends (monotonic); empty while disabled
        self._condition = threading.Condition()
        self._running = True
        threading.Thread(target=self._run, name="reference motion", daemon=True).start()

    def _next_goal(self, key: str, now: float, planners: Dict[str, Callable]) -> None:
        zeros = numpy.zeros(len(PARTS[key].joints))
        held = settled(planners[key](now, self._positions[key], zeros, zeros))
        self._positions[key] = held.positions[-1]
        self._due[key] = now + float(held.times[-1])
        self._send(key, PARTS[key].joints, held)

    def enable(self) -> None:
        with self._condition:
            now = time.monotonic()
            for key in self._planners:
                self._next_goal(key, now, self._planners)
            if self._base is not None:
                self._base.start(now)
            self._condition.notify()

    def disable(self) -> None:
        with self._condition:
            now = time.monotonic()
            # Every return goal is planned and sent before the reply, as the node's are.
            for key in list(self._due):
                self._next_goal(key, now, self._home_planners)
            self._due.clear()
            if self._base is not None:
                self._base.stop(now)
            self._condition.notify()

    def close(self) -> None:
        with self._condition:
            self._running = False
            self._condition.notify()

    def _next_due(self) -> Optional[float]:
        dues = list(self._due.values()) + ([self._base.due] if self._base is not None and self._base.due else [])
        return min(dues) if dues else None

    def _run(self) -> None:
        with self._condition:
            while self._running:
                now = time.monotonic()
                for key in [key for key, due in self._due.items() if due <= now]:
                    self._next_goal(key, now, self._planners)
                if self._base is not None and self._base.due is not None and self._base.due <= now:
                    self._base.tick(now)
                due = self._next_due()
                self._condition.wait(None if due is None else max(0.0, due - time.monotonic()))
