"""Reading /joint_states a few messages at a time (README: "Performance").

While the node listens, /joint_states comes 50 times a second and rospy wakes a thread for each message: the
largest share of the node's CPU while it animates, for measurements it plans from once every few seconds per part.
A TCP socket's receive low-water mark (SO_RCVLOWAT) lets that thread sleep until so many bytes have come. Set to
the bytes of the whole messages a connection brings in BATCH_PERIOD, the thread wakes once a period and rospy
reads those messages together. The latest measurement is then up to BATCH_PERIOD old (now and then two, below)
instead of one message period; the node plans from measurements where nothing of its own moves the joints, and
trusts one for 1 s.

Linux wakes a reader blocked in `recv` only once the bytes still waiting in the socket reach the mark. rospy reads
again as soon as it has handed a batch over, so the next read nearly always begins with nothing waiting and
returns at the mark. If a message came meanwhile, the read takes it and then waits for a whole mark more: that
batch is up to two periods long.

A connection's message rate and size are measured from rospy's own counts (bytes and messages received) over
RATE_WINDOW seconds, and again every RATE_WINDOW, so a publisher that slows down is soon read one message at a
time again; one that sends fewer than two messages a period always is. A publisher that stops leaves at most two
periods' messages unread, which would be too old to plan from within a second anyway.

`ReadBatching` is pure: the connections and the setting of a socket's mark are injected. `set_low_water_mark` and
`subscription_connections` are what the node injects: a rospy connection's socket option, and a subscription's
connections.
"""
import socket
from typing import Callable, Dict, Iterable, Optional

BATCH_PERIOD = 0.1  # s: how often a listening node reads /joint_states, at most
RATE_WINDOW = 2.0  # s of counts a connection's rate is measured over, and how often it is measured again
WAKE_AT_EACH_MESSAGE = 1  # the socket's default mark: one byte wakes the reader


def messages_per_period(received_messages: int, seconds: float, period: float = BATCH_PERIOD) -> int:
    """Whole messages a connection brings in `period`, from the count received in `seconds`."""
    if received_messages <= 0 or seconds <= 0.0:
        return 0
    return int(received_messages * period / seconds + 0.1)  # 99 messages in 2 s at 50 Hz read as 5 a period


def low_water_mark(received_bytes: int, received_messages: int, seconds: float,
                   period: float = BATCH_PERIOD) -> int:
    """Bytes a connection's reader waits for, from what it received in `seconds`: the messages of one `period`,
    less half a message (a message slightly shorter than the mean must not hold the batch back by one more); at
    least two messages, else WAKE_AT_EACH_MESSAGE."""
    batch = messages_per_period(received_messages, seconds, period)
    if batch < 2 or received_bytes <= 0:
        return WAKE_AT_EACH_MESSAGE
    return int((batch - 0.5) * received_bytes / received_messages)


class _Counts:
    __slots__ = ("since", "received_bytes", "received_messages", "mark")

    def __init__(self, since: float, received_bytes: int, received_messages: int, mark: int) -> None:
        self.mark = mark
        self.restart(since, received_bytes, received_messages)

    def restart(self, since: float, received_bytes: int, received_messages: int) -> None:
        """The next rate is measured from these counts, taken at `since`."""
        self.since = since
        self.received_bytes = received_bytes
        self.received_messages = received_messages


class ReadBatching:
    """Keeps each connection's low-water mark at the bytes of one BATCH_PERIOD.

    `update(connections, now)` is called from time to time (the supervisor's loop) with the subscription's current
    connections: objects with rospy's `stat_bytes` and `stat_num_msg` counts. `set_mark(connection, bytes)` sets a
    connection's mark; it may raise (a connection closing). Each change, and each failure (once per connection), is
    told to `debug` in one line."""

    def __init__(self, set_mark: Callable[[object, int], None], debug: Callable[[str], None],
                 period: float = BATCH_PERIOD, window: float = RATE_WINDOW) -> None:
        self._set_mark = set_mark
        self._debug = debug
        self._period = period
        self._window = window
        self._counts: Dict[object, _Counts] = {}

    def update(self, connections: Iterable[object], now: float) -> None:
        current = list(connections)
        current_ids = {id(connection) for connection in current}
        for connection in [known for known in self._counts if id(known) not in current_ids]:
            del self._counts[connection]  # closed: forget it (and let it go)
        for connection in current:
            received_bytes, received_messages = connection.stat_bytes, connection.stat_num_msg
            counts = self._counts.get(connection)
            if counts is None:
                self._counts[connection] = _Counts(now, received_bytes, received_messages, WAKE_AT_EACH_MESSAGE)
                continue
            seconds = now - counts.since
            if seconds < 0.0:  # a clock set back: measure again
                counts.restart(now, received_bytes, received_messages)
                continue
            if seconds < self._window or counts.mark is None:
                continue
            new_bytes = received_bytes - counts.received_bytes
            new_messages = received_messages - counts.received_messages
            counts.restart(now, received_bytes, received_messages)
            mark = low_water_mark(new_bytes, new_messages, seconds, self._period)
            if mark != counts.mark:
                batch = messages_per_period(new_messages, seconds, self._period) if mark > 1 else 1
                self._apply(connection, counts, mark, "%d message(s) at a time (%.0f a second)"
                            % (batch, new_messages / seconds))

    def _apply(self, connection, counts: _Counts, mark: int, what: str) -> None:
        try:
            self._set_mark(connection, mark)
        except Exception as error:  # the connection is closing, say: it is forgotten when it has gone
            self._debug("cannot batch a connection's reads (%s: %s); it reads each message"
                        % (type(error).__name__, error))
            counts.mark = None  # not tried again on this connection
            return
        counts.mark = mark
        self._debug("a connection is read %s" % what)

    def mark(self, connection) -> Optional[int]:
        """The mark set on `connection` (WAKE_AT_EACH_MESSAGE until one is; None when setting it failed)."""
        counts = self._counts.get(connection)
        return None if counts is None else counts.mark


def set_low_water_mark(connection, mark: int) -> None:
    """Makes the thread that reads a rospy connection (its `socket`) wake once `mark` bytes have come."""
    connection.socket.setsockopt(socket.SOL_SOCKET, socket.SO_RCVLOWAT, mark)


def subscription_connections(subscription) -> list:
    """A rospy subscription's current connections; none without one. rospy replaces the list whole when a
    connection comes or goes, so a copy is consistent."""
    return [] if subscription is None else list(subscription.impl.connections)
