"""Unit tests of listening to /joint_states only while the joints may move (core/joint_states.py)."""
import threading
import time

import genpy
import numpy
from sensor_msgs.msg import JointState

from cssr_system.core.joint_states import (MAX_AGE, REST_DELAY, FeedState, JointStateCache,
                                           JointStateFeed, SubscriptionSwitch)

ARM = ("RShoulderPitch", "RShoulderRoll")


class Rig:
    def __init__(self):
        self.now = 1000.0
        self.switched = []  # True: subscribe, False: unsubscribe
        self.lines = []
        self.cache = JointStateCache(lambda: self.now, lambda text: None)
        self.feed = JointStateFeed(self.cache, self.switched.append, lambda text, *args: self.lines.append(text % args))

    def measure(self, positions=(1.5, -0.1)):
        message = JointState(name=list(ARM), position=list(positions))
        message.header.stamp = genpy.Time.from_sec(self.now)
        self.cache.update(message)

    def quiet(self, seconds, step=0.5):
        """The supervisor's updates while nothing moves, measuring while listening."""
        end = self.now + seconds
        while self.now < end - 1e-9:
            if self.feed.state == FeedState.LISTENING:
                self.measure()
            self.feed.update(None, ARM, self.now)
            self.now += step
        self.feed.update(None, ARM, self.now)


def test_rests_after_the_rest_delay_of_quiet_and_holds_the_measurements():
    rig = Rig()
    rig.quiet(REST_DELAY - 0.5)
    assert rig.feed.state == FeedState.LISTENING and rig.switched == []
    rig.quiet(1.0)
    assert rig.feed.state == FeedState.RESTING
    assert rig.switched == [False], "unsubscribed once"
    rig.now += 600.0
    numpy.testing.assert_array_equal(rig.cache.positions(ARM), [1.5, -0.1])
    assert rig.lines == ["animateBehaviour: joint states: listening -> resting (quiet for 2.0 s)."]


def test_no_rest_without_a_measurement_of_every_joint():
    rig = Rig()
    for _ in range(20):
        rig.feed.update(None, ARM, rig.now)
        rig.now += 0.5
    assert rig.feed.state == FeedState.LISTENING and rig.switched == []


def test_motion_restarts_the_wait():
    rig = Rig()
    rig.quiet(REST_DELAY - 0.5)
    rig.feed.update("RArm waiting", ARM, rig.now)
    rig.quiet(REST_DELAY - 0.5)
    assert rig.feed.state == FeedState.LISTENING, "the quiet spell starts again after the motion"
    rig.quiet(1.0)
    assert rig.feed.state == FeedState.RESTING


def test_motion_while_resting_listens_again_and_releases_the_measurements():
    rig = Rig()
    rig.quiet(REST_DELAY + 0.5)
    rig.feed.update("another node moves RArm", ARM, rig.now)
    assert rig.feed.state == FeedState.LISTENING
    assert rig.switched == [False, True]
    rig.now += MAX_AGE + 0.01
    assert rig.cache.positions(ARM) is None, "the held measurements no longer count"
    assert rig.lines[-1] == "animateBehaviour: joint states: resting -> listening (another node moves RArm)."
    rig.feed.update("RArm waiting", ARM, rig.now)
    assert rig.switched == [False, True], "already listening: nothing to switch"


def test_a_joint_at_rest_without_a_current_measurement_is_measured_then_held_again():
    rig = Rig()
    rig.quiet(REST_DELAY + 0.5)
    rig.cache.moving(ARM[:1])  # a goal of ours moved it, and was cancelled: where it stopped, nothing says
    rig.feed.update(None, (), rig.now)
    assert rig.feed.state == FeedState.RESTING, "driven by a goal of ours: not measured while it runs"
    rig.feed.update(None, ARM, rig.now)
    assert rig.feed.state == FeedState.LISTENING and rig.switched == [False, True]
    rig.quiet(REST_DELAY + 0.5)
    assert rig.feed.state == FeedState.RESTING and rig.switched == [False, True, False]


def test_joints_that_a_goal_of_ours_drives_are_not_held():
    rig = Rig()
    rig.cache.moving(ARM[:1])
    end = rig.now + REST_DELAY + 0.5
    while rig.now < end:
        rig.measure()
        rig.feed.update(None, ARM[1:], rig.now)
        rig.now += 0.5
    assert rig.feed.state == FeedState.RESTING
    rig.now += 600.0
    assert rig.cache.complete(ARM[1:]) and not rig.cache.complete(ARM[:1])


def test_listen_while_resting_and_while_listening():
    rig = Rig()
    rig.quiet(REST_DELAY + 0.5)
    rig.feed.listen("controller /a connected")
    rig.feed.listen("controller /a lost")
    assert rig.switched == [False, True]
    assert rig.feed.state == FeedState.LISTENING


def test_a_clock_set_back_starts_the_wait_again():
    rig = Rig()
    rig.quiet(REST_DELAY - 0.5)
    rig.now -= 100.0
    rig.quiet(REST_DELAY - 0.5)
    assert rig.feed.state == FeedState.LISTENING
    rig.quiet(1.0)
    assert rig.feed.state == FeedState.RESTING


def subscribed(made):
    """A subscription is in force: the latest one made is not unregistered."""
    return bool(made) and not made[-1].unregistered


class Subscription:
    def __init__(self, made):
        self.unregistered = False
        made.append(self)

    def unregister(self):
        self.unregistered = True


def test_the_switch_makes_the_subscription_what_was_asked_last():
    made, errors = [], []
    switch = SubscriptionSwitch(lambda: Subscription(made), Subscription(made),
                                lambda where, error: errors.append(where), "joint_states")
    switch(False)
    switch(True)
    assert switch.apply() and subscribed(made) and len(made) == 1, "asked back: nothing changes"
    switch(False)
    assert switch.apply() and not subscribed(made) and made[0].unregistered
    switch(True)
    assert switch.apply() and subscribed(made) and len(made) == 2
    assert errors == []


def test_a_failed_subscription_is_reported_and_tried_again():
    made, errors, attempts = [], [], []

    def subscribe():
        attempts.append(1)
        if len(attempts) == 1:
            raise OSError("master unreachable")
        return Subscription(made)
    switch = SubscriptionSwitch(subscribe, None, lambda where, error: errors.append((where, str(error))),
                                "joint_states")
    switch(True)
    assert not switch.apply() and not subscribed(made)
    assert errors == [("joint_states", "master unreachable")]
    assert switch.apply() and subscribed(made)


def wait_for(condition, timeout=5.0):
    deadline = time.monotonic() + timeout
    while not condition() and time.monotonic() < deadline:
        time.sleep(0.005)
    return condition()


def test_the_switch_thread_applies_requests_without_blocking_the_caller():
    made = []
    release = threading.Event()

    def slow_subscribe():
        release.wait(5.0)  # a master that answers late
        return Subscription(made)
    switch = SubscriptionSwitch(slow_subscribe, Subscription(made), lambda where, error: None, "joint_states")
    switch.thread.start()
    switch(False)
    assert wait_for(lambda: made[0].unregistered and not subscribed(made))
    asked = time.monotonic()
    switch(True)
    assert time.monotonic() - asked < 0.1, "the caller does not wait for the master"
    assert not subscribed(made)
    release.set()
    assert wait_for(lambda: subscribed(made) and len(made) == 2)


def test_the_switch_starts_subscribed_then_switches_on_its_thread():
    made = []
    switch = SubscriptionSwitch(lambda: Subscription(made), None, lambda where, error: None, "joint_states")
    switch.start()
    assert subscribed(made), "subscribed when start returns: the first enable plans from the measured joints"
    switch(False)
    assert wait_for(lambda: not subscribed(made))
