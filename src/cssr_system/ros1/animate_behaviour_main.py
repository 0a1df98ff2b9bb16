"""The animateBehaviour program: starts the node, waits for a signal or a ROS shutdown, stops the robot, exits.

SIGINT, SIGTERM and a ROS shutdown (``rosnode kill``, the master going away) stop the robot as ``disabled`` does,
in any state, then the program exits with status 0 (README: "Faults"). A ROS shutdown is met in rospy's
shutdown hook, before rospy closes the publishers, so the stop still reaches the controllers. If the
supervisor thread, the one that commands the robot, has ended, the program stops the robot from its own
thread and exits 1 with one line that says so.
"""
import gc
import logging
import os
import signal
import sys
import threading
import time
from typing import Callable, List, Optional

import rospy

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import ConfigurationError
from cssr_system.animate_behaviour.console import Heartbeat, route_console
from cssr_system.animate_behaviour.contract import NODE_NAME
from cssr_system.animate_behaviour.process_setup import MemoryReturn, set_up_process
from cssr_system.ros1.animate_behaviour_node import AnimateBehaviourNode
from cssr_system.ros1.parameters import (config_file_parameter, load_node_configuration,
                                         parameter_overrides)
from cssr_system.ros1.wakeup import Wakeup

TEARDOWN_TIME = 0.1  # s at most for rospy's teardown (unregistering from the master), once the robot is stopped
# s between checks that the supervisor still runs and rospy has not shut down. A signal, a stop request and the
# supervisor's end wake the main thread at once (ros1/wakeup.py): this only bounds what nothing announces.
ALIVE_CHECK_PERIOD = 1.0


def print_banner(version: str) -> None:
    rospy.loginfo("%s %s: makes the Pepper robot look alive with small random movements.",
                  NODE_NAME, version)
    rospy.loginfo("%s: start-up.", NODE_NAME)


class Stopper:
    """Stops the robot once, whoever asks first: a signal, rospy's shutdown hook, or the main loop."""

    def __init__(self, node: AnimateBehaviourNode, wake: Callable[[], None]) -> None:
        self._node = node
        self._wake = wake  # the main thread's
        self._lock = threading.Lock()
        self.reason = ""
        self.requested = threading.Event()

    def request(self, reason: str) -> None:
        self.reason = self.reason or reason
        self.requested.set()
        self._wake()

    def stop(self, reason: str) -> None:
        with self._lock:
            if self._node.stopped:
                return
            self.reason = self.reason or reason
            self._node.request_shutdown(self.reason)
            self._node.services.withdraw()
            # The stop (cancels, home goals, a zero Twist) is on the wire: those publishers write at once.
            self._node.log.write(contract.NODE_STOPPED, reason=self.reason)


def on_ros_shutdown(stopper: Stopper) -> None:
    """rospy's shutdown hook: the robot is stopped here, and the main loop told (rospy reports the shutdown only
    once its hooks have run)."""
    stopper.request("ROS shutdown")
    stopper.stop("ROS shutdown")


def main(argv: Optional[List[str]] = None) -> int:
    argv = rospy.myargv(sys.argv if argv is None else argv)
    set_up_process()  # before any thread starts: one malloc arena, a short switch interval
    # The node handles SIGINT and SIGTERM itself: it stops the robot before rospy shuts down.
    rospy.init_node(NODE_NAME, disable_signals=True)
    # The node's console lines (core/console.py) go to rospy's console and /rosout. Their own level (verboseMode)
    # decides what is shown: handed to rospy's handlers directly, not through its logger's level.
    route_console(logging.getLogger("rosout").handle)
    try:
        node = AnimateBehaviourNode()
    except Exception as error:  # nothing moves yet: say why, once, and exit
        print("{}: cannot start: {}: {}".format(NODE_NAME, type(error).__name__, error), file=sys.stderr, flush=True)
        return 1
    print_banner(node.version)
    node.log.write(contract.NODE_STARTED, version=node.version, node=rospy.get_name(), namespace=rospy.get_namespace(),
                   config_file=config_file_parameter(), log_file=node.log.path,
                   parameters={key: str(value) for key, value in parameter_overrides().items()},
                   arguments=argv[1:])
    try:
        config_file, config, topics = load_node_configuration()
    except ConfigurationError as error:
        print("{}: invalid configuration: {}".format(NODE_NAME, error), file=sys.stderr, flush=True)
        node.log.write(contract.CONFIGURATION_INVALID, file=config_file_parameter(),
                       problems=list(error.problems))
        rospy.signal_shutdown("invalid configuration")
        return 1
    wakeup = Wakeup()
    wakeup.receive_signals()
    stopper = Stopper(node, wakeup.wake)
    signal.signal(signal.SIGINT, lambda number, frame: stopper.request("SIGINT"))
    signal.signal(signal.SIGTERM, lambda number, frame: stopper.request("SIGTERM"))
    rospy.on_shutdown(lambda: on_ros_shutdown(stopper))  # runs before rospy closes the publishers
    node.supervisor.on_end = wakeup.wake
    node.start(config_file, config, topics)
    # What start-up made (rospy, numpy, the messages' classes) lives as long as the node: out of the collector's
    # sight, a full collection no longer walks it, and no command waits for one.
    gc.freeze()

    status = 0
    heartbeat, memory = Heartbeat(time.monotonic), MemoryReturn()
    while not stopper.requested.is_set() and not rospy.is_shutdown():
        wakeup.wait(ALIVE_CHECK_PERIOD)
        heartbeat.beat()
        memory.tick()
        if not stopper.requested.is_set() and not node.stopped and not node.supervisor_alive():
            print("{}: the supervisor thread has ended; stopping the robot and exiting.".format(NODE_NAME),
                  file=sys.stderr, flush=True)
            node.supervisor.stop_without_thread()
            stopper.request("supervisor ended")
            status = 1
    stopper.stop(stopper.reason or "ROS shutdown")
    node.log.close()
    # The robot is stopped: rospy's teardown (unregistering every topic from the master, closing connections whose
    # writer threads the interpreter would wait for) gets a bounded time, so the node exits within half a second.
    teardown = threading.Thread(target=rospy.signal_shutdown, args=(stopper.reason,), daemon=True)
    teardown.start()
    teardown.join(TEARDOWN_TIME)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
