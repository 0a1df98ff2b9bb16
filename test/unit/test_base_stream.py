"""Unit tests of the base stream (core/base_stream.py) with a fake publisher and clock: it turns only while a node
other than ours listens to the Wheels topic, and a return turns back only what was heard. No ROS master."""
import math

import numpy
import pytest
from conftest import default_configuration
from fakes import FakeLog

from cssr_system.animate_behaviour import contract
from cssr_system.core.base_stream import BaseStream
from cssr_system.core.motion_stream import StreamState
from cssr_system.motion.styles import MotionStyle

MOVETO = "/pepper_dcm/cmd_moveto"
VELOCITY = "/pepper/cmd_vel"
CONFIG = default_configuration(random_seed=5)


class Rig:
    def __init__(self, topic: str, listened: bool) -> None:
        self.now = 10.0
        self.turns = []  # angular.z of each Twist published
        self.listened = listened
        self.log = FakeLog()
        self.base = BaseStream(topic, self.turns.append, lambda: self.listened, self.log,
                               debug=lambda *args: None, warn=lambda *args: None)
        self.watch()

    def watch(self) -> None:
        """What the controller watcher does with the answer of `listened()`, then the supervisor's tick."""
        if self.base.controller_ready():
            self.base.controller_connected()
        else:
            self.base.controller_lost()
        self.base.tick(self.now)

    def enable(self) -> None:
        rng = numpy.random.default_rng(5)
        self.base.start(CONFIG, MotionStyle(CONFIG, rng), rng, self.now)
        self.base.tick(self.now)

    def run(self, seconds: float, period: float = 0.01) -> None:
        for _ in range(int(round(seconds / period))):
            self.now += period
            self.base.tick(self.now)

    def run_until_turns(self, count: int, seconds: float = 10.0, period: float = 0.01) -> None:
        while len(self.turns) < count and seconds > 0.0:
            self.run(period, period)
            seconds -= period


def test_nothing_is_published_while_nobody_listens_and_the_first_turn_leaves_when_somebody_does():
    rig = Rig(MOVETO, listened=False)
    rig.enable()
    rig.run(5.0)
    assert rig.base.state == StreamState.WAITING
    assert rig.turns == [] and rig.log.events(contract.BASE_COMMAND) == []
    rig.listened = True
    rig.watch()
    assert rig.base.state == StreamState.ANIMATING
    assert len(rig.turns) == 1 and rig.log.events(contract.CONTROLLER_CONNECTED) == [
        {"part": "Wheels", "action": MOVETO}]


def test_disabled_while_nobody_ever_listened_the_base_sends_no_return():
    rig = Rig(MOVETO, listened=False)
    rig.enable()
    rig.run(2.0)
    rig.base.stop(True, rig.now)
    rig.run(5.0)
    assert rig.base.state == StreamState.IDLE and rig.turns == []


def test_nothing_is_sent_while_nobody_listens():
    for topic in (MOVETO, VELOCITY):
        rig = Rig(topic, listened=True)
        rig.enable()
        rig.run(0.5)  # the first turn under way (a streamed one is cut short part way)
        rig.listened = False
        rig.watch()
        heard = list(rig.turns)
        assert rig.base.state == StreamState.WAITING and heard, topic
        rig.run(10.0)
        assert rig.turns == heard, topic


def test_the_return_turns_back_exactly_the_turns_heard():
    rig = Rig(MOVETO, listened=True)
    rig.enable()
    rig.run(0.5)
    rig.listened = False
    rig.watch()
    rig.run(10.0)
    rig.listened = True
    rig.watch()  # a new turn leaves at once
    rig.base.stop(True, rig.now)
    rig.run(10.0)  # the return leaves when that turn has ended
    assert rig.base.state == StreamState.IDLE
    assert len(rig.turns) == 3 and abs(math.fsum(rig.turns)) < 1e-12


def test_losing_the_listener_while_returning_cancels_the_return():
    rig = Rig(MOVETO, listened=True)
    rig.enable()
    rig.run(1.0)
    rig.base.stop(True, rig.now)
    rig.run_until_turns(2)  # the first turn and its settle time end, then the return is sent
    assert rig.base.state == StreamState.HOMING and len(rig.turns) == 2
    rig.listened = False
    rig.watch()
    assert rig.base.state == StreamState.IDLE
    assert rig.log.events(contract.CONTROLLER_LOST) == [{"part": "Wheels", "action": MOVETO}]


@pytest.mark.parametrize("topic", [MOVETO, VELOCITY])
@pytest.mark.parametrize("stop_after", [0.7, 1.9, 3.3, 6.1])
def test_the_return_lasts_as_long_as_return_duration_said(topic, stop_after):
    """An animate goal's end starts the base back this long before it (core/session.py): it must be right, wherever
    the base is in its turns when asked."""
    rig = Rig(topic, listened=True)
    rig.enable()
    rig.run(stop_after)
    said = rig.base.return_duration(rig.now)
    stopped_at = rig.now
    rig.base.stop(True, rig.now)
    while rig.base.state != StreamState.IDLE and rig.now < stopped_at + 10.0:
        rig.run(0.01)
    assert rig.now - stopped_at == pytest.approx(said, abs=0.02)


@pytest.mark.parametrize("topic", [MOVETO, VELOCITY])
def test_a_base_the_mode_paused_keeps_its_frame_of_enable_and_a_disable_turns_it_back(topic):
    """Listening and speaking stop the base where it is (README: "Modes"); idle goes on from the heading it had since
    enable, never from a new zero, so the bound holds; a disable meanwhile turns it back to the heading of enable."""
    rig = Rig(topic, listened=True)
    rig.enable()
    rig.run(4.0)
    rig.base.park(rig.now)
    rig.run(3.0)
    heading = 0.25  # where its turns since enable left it (the planner's frame)
    rig.base.planner.set_heading(heading)
    assert rig.base.state == StreamState.IDLE
    published = len(rig.turns)
    rig.run(2.0)
    assert len(rig.turns) == published, "nothing while paused"
    rig.enable()
    first = rig.log.events(contract.BASE_COMMAND)[-1]
    assert first["target_heading"] - first["angle"] == pytest.approx(heading), "idle goes on in the frame of enable"
    rig.run(6.0)
    assert abs(rig.base.planner.heading) <= CONFIG.heading_bound + 1e-9
    rig.base.park(rig.now)
    rig.run(3.0)
    rig.base.stop(True, rig.now)
    assert rig.base.state in (StreamState.HOMING, StreamState.IDLE)
    rig.run(5.0)
    assert rig.base.state == StreamState.IDLE and rig.base.planner.heading == pytest.approx(0.0, abs=0.02)
