"""How the package's ROS 2 programs start and end: rclpy without its own signal handlers (they would shut the
context down before a program has stopped the robot, ended its goals or written its recording), one node, and a
malformed command line said in one line; and how they wait for a service's reply."""
import signal
import sys
import threading
from typing import Callable, List, Optional

import rclpy
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions


def on_signals(handler: Callable[[str], None]) -> None:
    """`handler(name)` on SIGINT and SIGTERM, instead of rclpy's."""
    for number in (signal.SIGINT, signal.SIGTERM):
        signal.signal(number, lambda received, _frame: handler(signal.Signals(received).name))


def call(client, request, timeout: float):
    """The reply to `request` on `client` within `timeout` s (an executor spins the node); TimeoutError if none."""
    if not client.wait_for_service(timeout_sec=timeout):
        raise TimeoutError("the service is not available")
    done = threading.Event()
    future = client.call_async(request)
    future.add_done_callback(lambda _: done.set())
    if not done.wait(timeout):
        future.cancel()  # a late reply is dropped
        raise TimeoutError("no reply within %g s" % timeout)
    return future.result()


def run_node(name: str, args: Optional[List[str]], body: Callable[[Node], int], failure: int = 1) -> int:
    """`body(node)`'s exit status, for a node named `name`; `failure` when rclpy cannot start."""
    try:
        rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    except Exception as error:  # malformed --ros-args: rclpy's own words, on one line
        print("{}: cannot start: {}".format(name, str(error).strip().splitlines()[0]), file=sys.stderr)
        return failure
    try:
        node = Node(name)
        try:
            return body(node)
        finally:
            node.destroy_node()
    finally:
        rclpy.try_shutdown()
