"""Unit tests of reading /joint_states a few messages at a time (node/joint_state_batching.py)."""
import socket
import threading
import time

import pytest

from cssr_system.animate_behaviour.node.joint_state_batching import (BATCH_PERIOD, RATE_WINDOW, WAKE_AT_EACH_MESSAGE,
                                                                     ReadBatching, low_water_mark,
                                                                     messages_per_period, set_low_water_mark)

MESSAGE = 616  # bytes of one simulated Pepper /joint_states message on the wire, its length included


class Connection:
    """What ReadBatching reads of a rospy connection: its counts of bytes and messages received."""

    def __init__(self):
        self.stat_bytes = 0
        self.stat_num_msg = 0

    def receive(self, messages, size=MESSAGE):
        self.stat_bytes += messages * size
        self.stat_num_msg += messages


class Rig:
    def __init__(self, fail=False):
        self.now = 100.0
        self.marks = []  # (connection, mark) as set
        self.lines = []
        self.fail = fail
        self.batching = ReadBatching(self._set_mark, self.lines.append)

    def _set_mark(self, connection, mark):
        if self.fail:
            raise OSError("Bad file descriptor")
        self.marks.append((connection, mark))

    def run(self, connections, seconds, rate=50.0, size=MESSAGE, step=0.5):
        """The supervisor's updates every `step` s while each connection receives `rate` messages a second."""
        for _ in range(int(round(seconds / step))):
            for connection in connections:
                connection.receive(int(round(rate * step)), size)
            self.now += step
            self.batching.update(connections, self.now)


def test_the_mark_is_the_bytes_of_one_period_of_messages_less_half_a_message():
    assert messages_per_period(100, 2.0) == 5
    assert messages_per_period(99, 2.0) == 5  # a message short of 50 Hz still reads as 5 a period
    assert low_water_mark(100 * MESSAGE, 100, 2.0) == int(4.5 * MESSAGE)
    assert low_water_mark(200 * MESSAGE, 200, 2.0) == int(9.5 * MESSAGE)  # 100 Hz
    assert low_water_mark(40 * MESSAGE, 40, 2.0) == int(1.5 * MESSAGE)  # 20 Hz: two a period


def test_a_publisher_slower_than_two_messages_a_period_is_read_at_each_message():
    assert low_water_mark(24 * MESSAGE, 24, 2.0) == WAKE_AT_EACH_MESSAGE  # the robot's driver at 12 Hz
    assert low_water_mark(0, 0, 2.0) == WAKE_AT_EACH_MESSAGE
    assert low_water_mark(MESSAGE, 1, 0.0) == WAKE_AT_EACH_MESSAGE


def test_a_connection_is_batched_once_its_rate_is_measured_over_the_window():
    rig, connection = Rig(), Connection()
    rig.run([connection], RATE_WINDOW)  # first seen at the first update: not a whole window yet
    assert rig.marks == []
    assert rig.batching.mark(connection) == WAKE_AT_EACH_MESSAGE
    rig.run([connection], 0.5)
    assert rig.marks == [(connection, int(4.5 * MESSAGE))]
    assert rig.batching.mark(connection) == int(4.5 * MESSAGE)
    assert rig.lines == ["a connection is read 5 message(s) at a time (50 a second)"]
    rig.run([connection], 3 * RATE_WINDOW)  # the same rate: nothing set again
    assert len(rig.marks) == 1


def test_a_publisher_that_slows_down_is_read_at_each_message_again():
    rig, connection = Rig(), Connection()
    rig.run([connection], RATE_WINDOW + 0.5)
    rig.run([connection], 2 * RATE_WINDOW, rate=10.0)
    assert rig.marks[-1] == (connection, WAKE_AT_EACH_MESSAGE)
    assert rig.lines[-1] == "a connection is read 1 message(s) at a time (10 a second)"


def test_each_connection_has_its_own_mark_and_a_closed_one_is_forgotten():
    rig, fast, slow = Rig(), Connection(), Connection()
    rig.batching.update([fast, slow], rig.now)
    for _ in range(5):
        fast.receive(25)
        slow.receive(6, size=100)
        rig.now += 0.5
        rig.batching.update([fast, slow], rig.now)
    assert rig.marks == [(fast, int(4.5 * MESSAGE))]
    rig.batching.update([slow], rig.now + 0.5)
    assert rig.batching.mark(fast) is None
    assert rig.batching.mark(slow) == WAKE_AT_EACH_MESSAGE


def test_a_mark_that_cannot_be_set_is_told_once_and_not_tried_again():
    rig, connection = Rig(fail=True), Connection()
    rig.run([connection], 4 * RATE_WINDOW)
    assert rig.lines == ["cannot batch a connection's reads (OSError: Bad file descriptor); it reads each message"]
    assert rig.batching.mark(connection) is None


def test_a_clock_set_back_measures_the_rate_again():
    rig, connection = Rig(), Connection()
    rig.run([connection], RATE_WINDOW - 0.5)
    rig.now -= 60.0  # e.g. a simulation restarted
    rig.run([connection], RATE_WINDOW - 0.5)
    assert rig.marks == []
    rig.run([connection], 1.0)
    assert rig.marks == [(connection, int(4.5 * MESSAGE))]


class SocketConnection:
    """A real TCP connection over loopback, as rospy holds one: its reading end in `socket`."""

    def __init__(self):
        listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        listener.bind(("127.0.0.1", 0))
        listener.listen(1)
        self.writer = socket.create_connection(listener.getsockname())
        self.socket, _ = listener.accept()
        listener.close()

    def close(self):
        self.writer.close()
        self.socket.close()

    def batched_reader(self):
        """The mark of five messages set, a thread blocked in one `recv` as rospy's: (thread, what it read)."""
        set_low_water_mark(self, int(4.5 * MESSAGE))
        received = []
        reader = threading.Thread(target=lambda: received.append(self.socket.recv(65536)), daemon=True)
        reader.start()
        # Blocked before the first message comes, as rospy's reader between batches: a read that begins with bytes
        # waiting takes them and then waits for a whole mark more (see the module's note).
        time.sleep(0.2)
        return reader, received


def test_a_socket_with_the_mark_set_wakes_its_reader_only_once_the_batch_has_come():
    connection = SocketConnection()
    try:
        reader, received = connection.batched_reader()
        for _ in range(4):
            connection.writer.sendall(b"m" * MESSAGE)
            time.sleep(BATCH_PERIOD / 5)
        assert reader.is_alive() and received == [], "four messages do not wake the reader"
        connection.writer.sendall(b"m" * MESSAGE)
        reader.join(2.0)
        assert received == [b"m" * (5 * MESSAGE)], "the fifth wakes it, and it reads the five together"
    finally:
        connection.close()


def test_a_socket_closed_by_its_peer_wakes_a_reader_waiting_for_a_batch():
    connection = SocketConnection()
    try:
        reader, received = connection.batched_reader()
        connection.writer.sendall(b"m" * MESSAGE)
        connection.writer.close()
        reader.join(2.0)
        assert not reader.is_alive(), "a publisher that goes away does not leave the reader waiting"
        assert received == [b"m" * MESSAGE]
    finally:
        connection.socket.close()


def test_a_mark_on_a_closed_connection_raises_for_the_caller_to_report():
    connection = SocketConnection()
    connection.close()
    with pytest.raises(OSError):
        set_low_water_mark(connection, 100)
