"""What the activation services do with a request (core/activation.py): a `disabled` replies once the supervisor has
sent the stop, however busy the machine, and a supervisor that never sends it does not hold the reply for ever."""
import logging
import threading
import time

from cssr_system.animate_behaviour.console import console
from cssr_system.core.activation import SLOW_STOP, Activation
from cssr_system.core.events import Disable


class Supervisor:
    """Applies each request `delay` s after it comes (None: never), on a thread of its own, as the node's does."""

    def __init__(self, delay):
        self.delay = delay
        self.applied_at = None

    def post(self, event):
        assert isinstance(event, Disable)
        if self.delay is not None:
            threading.Timer(self.delay, self.apply, (event,)).start()

    def apply(self, event):
        self.applied_at = time.monotonic()
        event.done.set()


def activation(supervisor, limit=0.5):
    return Activation(supervisor.post, log=None, configure=lambda: None, config_file=lambda: "", stop_reply_limit=limit)


def test_a_disabled_replies_only_once_a_slow_supervisor_has_sent_the_stop(caplog):
    supervisor = Supervisor(delay=SLOW_STOP + 0.1)
    with caplog.at_level(logging.WARNING, logger=console.name):
        assert activation(supervisor).activate("disabled") == (True, "disabled")
        replied_at = time.monotonic()
    assert supervisor.applied_at is not None and supervisor.applied_at <= replied_at, "the stop went before the reply"
    assert [record.getMessage() for record in caplog.records if "the stop took" in record.getMessage()], \
        "the console names a slow stop"


def test_a_prompt_stop_replies_at_once_without_a_console_line(caplog):
    supervisor = Supervisor(delay=0.0)
    with caplog.at_level(logging.WARNING, logger=console.name):
        started = time.monotonic()
        assert activation(supervisor).activate("disabled") == (True, "disabled")
        assert time.monotonic() - started < SLOW_STOP + 0.5  # generous: a loaded machine
    assert supervisor.applied_at is not None
    assert not [record for record in caplog.records if "stop" in record.getMessage()]


def test_a_supervisor_that_never_sends_the_stop_does_not_hold_the_reply(caplog):
    with caplog.at_level(logging.WARNING, logger=console.name):
        started = time.monotonic()
        assert activation(Supervisor(delay=None), limit=0.2).activate("disabled") == (True, "disabled")
        waited = time.monotonic() - started
    assert 0.2 <= waited < 2.0
    assert [record for record in caplog.records if "not been sent within 200 ms" in record.getMessage()]


def test_an_unknown_state_changes_nothing_and_names_the_accepted_ones():
    posted = []
    accepted, message = Activation(posted.append, None, lambda: None, lambda: "").activate("start")
    assert not accepted and "'start'" in message and "enabled, disabled" in message
    assert posted == []
