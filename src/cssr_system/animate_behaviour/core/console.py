"""The node's console lines from its ROS-free parts: one Python logger, which each front-end routes to its ROS's
console and log (node/main.py on ROS 1: rospy's ``rosout`` logger; ros2/animate_behaviour_node.py: the node's
rclpy logger). Debug lines appear with verboseMode (`set_verbose`)."""
import logging

from cssr_system.animate_behaviour.contract import NODE_NAME

console = logging.getLogger(NODE_NAME)
console.setLevel(logging.INFO)


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
