"""The console's "running." line (core/console.py Heartbeat), said by the ROS 1 program's main loop."""
import logging

from cssr_system.animate_behaviour.console import HEARTBEAT_PERIOD, Heartbeat, console


class FakeClock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def running_lines(caplog) -> int:
    return sum(1 for record in caplog.records if record.getMessage() == "animateBehaviour: running.")


def test_running_is_said_once_every_period_and_not_before(caplog):
    clock = FakeClock()
    heartbeat = Heartbeat(clock)
    with caplog.at_level(logging.INFO, logger=console.name):
        for _ in range(int(HEARTBEAT_PERIOD) * 3):  # the main loop wakes once a second
            heartbeat.beat()
            assert running_lines(caplog) == int((clock.now - 100.0) // HEARTBEAT_PERIOD)
            clock.now += 1.0
    assert running_lines(caplog) == 2


def test_a_long_wait_gives_one_line_not_a_burst(caplog):
    clock = FakeClock()
    heartbeat = Heartbeat(clock, period=10.0)
    with caplog.at_level(logging.INFO, logger=console.name):
        clock.now += 95.0
        heartbeat.beat()
        heartbeat.beat()
        assert running_lines(caplog) == 1
        clock.now += 10.0
        heartbeat.beat()
    assert running_lines(caplog) == 2
