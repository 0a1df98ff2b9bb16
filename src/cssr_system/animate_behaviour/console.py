"""Console lines. The node's, from its ROS-free parts: one Python logger, which each front-end routes to its ROS's
console and log (ros1/animate_behaviour_main.py: rospy's ``rosout`` logger; ros2/animate_behaviour_node.py: the
node's rclpy logger); debug lines appear with verboseMode (`set_verbose`). The tools' (the demo's driver and
gesture player, the recorder): one plain line each (`say`)."""
import logging

from cssr_system.animate_behaviour.contract import NODE_NAME
from cssr_system.animate_behaviour.periodic import Periodic

console = logging.getLogger(NODE_NAME)
console.setLevel(logging.INFO)
HEARTBEAT_PERIOD = 10.0  # s between "running." lines (README: "Log file", the console)


def set_verbose(verbose: bool) -> None:
    console.setLevel(logging.DEBUG if verbose else logging.INFO)


class ForwardingHandler(logging.Handler):
    """Hands each console line (a logging record this logger's level let through) to `emit(record)`: a
    front-end's logger."""

    def __init__(self, emit) -> None:
        super().__init__()
        self._emit = emit

    def emit(self, record: logging.LogRecord) -> None:
        try:
            self._emit(record)
        except Exception:  # a console that fails must not stop the node (logging's own convention)
            self.handleError(record)


_routes = []  # the handler of `route_console`, replaced by another call


def route_console(emit) -> None:
    """Console lines go to `emit(record)` only (not also to Python's root logger)."""
    while _routes:
        console.removeHandler(_routes.pop())
    _routes.append(ForwardingHandler(emit))
    console.addHandler(_routes[-1])
    console.propagate = False


class Heartbeat(Periodic):
    """The console's "running." line every HEARTBEAT_PERIOD s, said by a loop that wakes at least once a second
    anyway (the ROS 1 program's main loop: a timer would be a thread of its own). `clock`: seconds, monotonic."""

    def __init__(self, clock, period: float = HEARTBEAT_PERIOD) -> None:
        super().__init__(clock, period, lambda: console.info("%s: running.", NODE_NAME))

    def beat(self) -> None:
        """Says "running." when a period has passed since the last line (once, however long the wait was)."""
        self.tick()


def say(node_name: str, text: str) -> None:
    """One line, ``<node_name>: <text>``, printed at once (under roslaunch stdout is a pipe, which would hold it
    back)."""
    print("%s: %s" % (node_name, text), flush=True)
