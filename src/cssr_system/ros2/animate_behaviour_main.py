"""The animateBehaviour program on ROS 2 (README: "ROS 2"): starts the node, spins it, waits for a signal, stops
the robot, exits.

  ros2 run cssr_system animate_behaviour [--ros-args -p configFile:=... -p <key>:=<value>]

SIGINT and SIGTERM stop the robot as ``disabled`` does, in any state, then the program exits with status 0. rclpy's
own signal handlers are not installed: they would shut the context down before the stop reaches the controllers.
If the supervisor thread, the one that commands the robot, has ended, the program stops the robot from its own
thread and exits 1 with one line that says so. An invalid configuration: one line, exit 1.
"""
import os
import sys
import threading
import time
from typing import List, Optional

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.logging import LoggingSeverity
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import ConfigurationError
from cssr_system.animate_behaviour.console import route_console
from cssr_system.animate_behaviour.contract import NODE_NAME
from cssr_system.animate_behaviour.process_setup import MemoryReturn, set_up_process
from cssr_system.ros2.animate_behaviour_node import AnimateBehaviourNode
from cssr_system.ros2.program import on_signals

ALIVE_CHECK_PERIOD = 1.0  # s between checks that the supervisor still runs (a signal wakes the wait at once)
HANDOVER_TIMEOUT = 0.3  # s at most for the executor's thread to run the stop's work handed over to it
SEND_GRACE = 0.1  # s for the stop's last messages, written, to leave the process before it ends


def console_to(logger):
    """Hands a console record (core/console.py) to an rclpy logger, at its level."""
    def emit(record) -> None:
        text = record.getMessage()
        if record.levelno >= 40:
            logger.error(text)
        elif record.levelno >= 30:
            logger.warning(text)
        elif record.levelno >= 20:
            logger.info(text)
        else:
            logger.debug(text)
    return emit


def fail(text: str) -> int:
    print("{}: {}".format(NODE_NAME, text), file=sys.stderr, flush=True)
    return 1


def load(wiring: AnimateBehaviourNode):
    """(configuration file, configuration, topics), or None after one line and the log's configuration_invalid."""
    try:
        wiring.parameters.declare_keys()
        return wiring.parameters.load()
    except ConfigurationError as error:
        fail("invalid configuration: {}".format(error))
        wiring.log.write(contract.CONFIGURATION_INVALID, file=wiring.parameters.config_file,
                         problems=list(error.problems))
        return None


def run(wiring: AnimateBehaviourNode, stop: threading.Event, reasons: List[str]) -> int:
    """Waits for `stop`; 1 when the supervisor thread ended first (the robot is stopped from here), or the executor's
    (the node hears nothing more: the robot is stopped as at a signal)."""
    memory = MemoryReturn()
    while not stop.wait(ALIVE_CHECK_PERIOD):
        memory.tick()
        if not wiring.supervisor.thread.is_alive() and not wiring.supervisor.stopped.is_set():
            fail("the supervisor thread has ended; stopping the robot and exiting.")
            wiring.supervisor.stop_without_thread()
            reasons.append("supervisor ended")
            return 1
        if wiring.executor_thread.ended():
            fail("the executor thread has ended, so the node hears and answers nothing; stopping the robot and "
                 "exiting.")
            reasons.append("executor ended")
            return 1
    return 0


def let_the_stop_leave(wiring: AnimateBehaviourNode) -> None:
    """Returns once the executor's thread has run the work handed over so far (the cancels, return goals and zero
    Twist: on a busy machine that can take longer than any fixed wait) and its messages have had SEND_GRACE to leave;
    after HANDOVER_TIMEOUT + SEND_GRACE at most."""
    handed_over = threading.Event()
    wiring.executor_thread.run(handed_over.set)  # runs after the work handed over before it
    handed_over.wait(HANDOVER_TIMEOUT)
    time.sleep(SEND_GRACE)


def main(argv: Optional[List[str]] = None) -> int:
    set_up_process()  # before any thread starts: one malloc arena, a short switch interval
    rclpy.init(args=sys.argv if argv is None else argv, signal_handler_options=SignalHandlerOptions.NO)
    node = Node(NODE_NAME)
    node.get_logger().set_level(LoggingSeverity.DEBUG)  # the console logger's level (verboseMode) decides
    route_console(console_to(node.get_logger()))
    try:
        wiring = AnimateBehaviourNode(node)
    except Exception as error:  # nothing moves yet: say why, once, and exit
        return fail("cannot start: {}: {}".format(type(error).__name__, error))
    wiring.log.write(contract.NODE_STARTED, version=wiring.version, node=node.get_fully_qualified_name(),
                     namespace=node.get_namespace(),
                     config_file=wiring.parameters.config_file, log_file=wiring.log.path, parameters={},
                     arguments=(sys.argv if argv is None else argv)[1:])
    loaded = load(wiring)
    if loaded is None:
        wiring.log.close()
        return 1
    stop = threading.Event()
    reasons: List[str] = []
    on_signals(lambda name: (reasons.append(name), stop.set()))
    node.get_logger().info("{} {}: makes the Pepper robot look alive with small random movements.".format(
        NODE_NAME, wiring.version))
    executor = SingleThreadedExecutor()
    executor.add_node(node)  # first: the goals sent as the node starts wait on it for it to spin
    wiring.start(*loaded)
    # Spun once the clients exist: an rclpy ActionClient made while the executor spins may be waited on before it
    # is complete (rclpy 9.1.2 adds it to the node before making its lock).
    wiring.executor_thread.spin(executor)
    status = run(wiring, stop, reasons)
    reason = reasons[0]
    wiring.request_shutdown(reason)
    if wiring.services is not None:
        wiring.executor_thread.run(wiring.services.withdraw)  # after the stop, which went to the executor first
    wiring.log.write(contract.NODE_STOPPED, reason=reason)
    wiring.log.close()
    let_the_stop_leave(wiring)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)  # rclpy's teardown of a spinning executor is not needed: the robot is stopped


if __name__ == "__main__":
    sys.exit(main())
