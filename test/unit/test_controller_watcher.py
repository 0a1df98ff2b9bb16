"""Unit tests of the controller watcher (core/controller_watcher.py): when it notices controllers, with fake
action clients and no master."""
import threading
import time
from types import SimpleNamespace

import pytest

from cssr_system.core import controller_watcher
from cssr_system.core.controller_watcher import ControllerWatcher
from cssr_system.core.events import ControllerConnected, ControllerLost
from cssr_system.ros1.rospy_compat import server_ready

ACTION = "/pepper_dcm/RightArm_controller/follow_joint_trajectory"
SERVER = "/pepper_dcm"


class FakePublisher:
    def __init__(self):
        self.impl = SimpleNamespace(has_connection=lambda caller: caller in self.connected)
        self.connected = set()


class FakeClient:
    """What server_ready reads of an actionlib ActionClient."""

    def __init__(self):
        self.last_status_msg = None
        self.pub_goal, self.pub_cancel = FakePublisher(), FakePublisher()
        self.result_sub = SimpleNamespace(impl=SimpleNamespace(connections=[]))

    def appear(self):
        self.pub_goal.connected.add(SERVER)
        self.pub_cancel.connected.add(SERVER)
        self.result_sub.impl.connections = [SimpleNamespace(callerid_pub=SERVER)]
        self.last_status_msg = SimpleNamespace(_connection_header={"callerid": SERVER})

    def vanish(self):
        self.pub_goal.connected.clear()


class FakeStream:
    def __init__(self):
        self.part, self.action, self.client, self.connected = "RArm", ACTION, FakeClient(), False

    def controller_ready(self):
        return server_ready(self.client)  # as a goal stream's ROS 1 client answers


def make_watcher(stream, posted):
    def post(event):
        posted.append((time.monotonic(), event))
        if isinstance(event, ControllerConnected):
            stream.connected = True
        elif isinstance(event, ControllerLost):
            stream.connected = False
    stopped = threading.Event()
    watcher = ControllerWatcher(lambda: [stream], post, SimpleNamespace(write=lambda *a, **k: None), stopped,
                                lambda where, error: posted.append((time.monotonic(), error)))
    return watcher, stopped


def test_server_ready_needs_a_status_and_every_connection_to_the_same_server():
    client = FakeClient()
    assert not server_ready(client)
    client.appear()
    assert server_ready(client)
    client.vanish()
    assert not server_ready(client)


def test_a_check_posts_connected_once_and_lost_when_the_server_goes():
    stream, posted = FakeStream(), []
    watcher, _ = make_watcher(stream, posted)
    watcher.check()
    assert posted == []
    stream.client.appear()
    watcher.check()
    watcher.check()
    assert [event for _, event in posted] == [ControllerConnected("RArm", ACTION)]
    stream.client.vanish()
    watcher.check()
    assert [event for _, event in posted][1:] == [ControllerLost("RArm", ACTION)]


@pytest.mark.parametrize("status_seen", [True, False])
def test_a_status_from_a_controller_not_yet_connected_makes_the_watcher_check_at_once(status_seen):
    stream, posted = FakeStream(), []
    watcher, stopped = make_watcher(stream, posted)
    watcher.thread.start()
    try:
        time.sleep(0.1)  # the first check is made, and finds nothing
        stream.client.appear()
        appeared = time.monotonic()
        if status_seen:
            watcher.status_seen(ACTION)
        deadline = appeared + 2 * controller_watcher.WATCH_PERIOD
        while not posted and time.monotonic() < deadline:
            time.sleep(0.005)
        assert posted and isinstance(posted[0][1], ControllerConnected)
        delay = posted[0][0] - appeared
        if status_seen:
            assert delay < 0.1  # instead of up to WATCH_PERIOD
        else:
            assert delay > 0.2  # the periodic check: the case above is not the period's luck
    finally:
        stopped.set()
        watcher.status_seen(ACTION)
        watcher.thread.join(2)


def test_status_of_a_connected_controller_does_not_wake_the_watcher():
    stream, posted = FakeStream(), []
    watcher, _ = make_watcher(stream, posted)
    stream.client.appear()
    watcher.check()
    watcher.status_seen(ACTION)
    assert not watcher._wake.is_set()
