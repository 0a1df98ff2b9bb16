"""Unit tests of what the node's main thread sleeps on (ros1/wakeup.py), with real signals and threads."""
import os
import signal
import threading
import time

import pytest

from cssr_system.ros1.wakeup import Wakeup

PROMPT = 0.5  # s: generous for a loaded machine, and far below the waits' 10 s


@pytest.fixture
def wakeup():
    woken = Wakeup()
    woken.receive_signals()
    previous = signal.signal(signal.SIGUSR1, lambda number, frame: handled.append(threading.current_thread()))
    handled.clear()
    yield woken
    signal.signal(signal.SIGUSR1, previous)
    signal.set_wakeup_fd(-1)  # signals are no longer written to the pipe


handled = []


def timed_wait(wakeup, timeout=10.0):
    started = time.monotonic()
    woken = wakeup.wait(timeout)
    return woken, time.monotonic() - started


def test_a_signal_sent_while_another_thread_runs_wakes_the_main_thread_and_its_handler_runs_there(wakeup):
    # The kernel may deliver a process's signal to any thread that does not block it: the other thread here
    # blocks nothing, as rospy's threads.
    sender = threading.Timer(0.1, os.kill, args=(os.getpid(), signal.SIGUSR1))
    sender.start()
    woken, waited = timed_wait(wakeup)
    sender.join()
    assert woken and waited < PROMPT
    assert handled == [threading.main_thread()]


def test_a_signal_that_lands_in_another_thread_wakes_the_main_thread(wakeup):
    def deliver_here():
        signal.pthread_kill(threading.get_ident(), signal.SIGUSR1)  # this thread, not the main one

    sender = threading.Timer(0.1, deliver_here)
    sender.start()
    woken, waited = timed_wait(wakeup)
    sender.join()
    assert woken and waited < PROMPT
    assert handled == [threading.main_thread()], "Python runs the handler in the main thread once it is awake"


def test_wake_from_another_thread_ends_the_wait_and_is_drained(wakeup):
    for _ in range(3):
        threading.Timer(0.1, wakeup.wake).start()
        woken, waited = timed_wait(wakeup)
        assert woken and waited < PROMPT
    assert wakeup.wait(0.05) is False, "each wake ends one wait: nothing is left for the next"


def test_a_wake_before_the_wait_ends_it_at_once(wakeup):
    wakeup.wake()
    wakeup.wake()
    woken, waited = timed_wait(wakeup)
    assert woken and waited < PROMPT


def test_without_a_wake_the_wait_lasts_its_timeout(wakeup):
    woken, waited = timed_wait(wakeup, 0.2)
    assert not woken and waited >= 0.19


def test_wakes_beyond_what_the_pipe_holds_are_not_an_error(wakeup):
    for _ in range(200000):  # more bytes than a pipe's buffer
        wakeup.wake()
    woken, _ = timed_wait(wakeup)
    assert woken
    assert wakeup.wait(0.05) is False
