"""`make soak ROS=2` (doc/soak.md): the ROS 2 driver of a soak, the twin of cssr_system.ros1.soak_driver. The
simulated Pepper and the node as processes of the run on this process's ROS 2 domain (ROS_DOMAIN_ID), and this
process's clients: setActivation, set_parameters for the live settings, the animate action, another node's
gesture on the right arm and the base's listener. The run itself (schedule, sampling, figures) is cssr_system.soak's.

python3 -m cssr_system.ros2.soak_driver --minutes 60 --warm-up 10 --folder DIR --json FILE
"""
import os
import sys
import threading

import rclpy
from control_msgs.action import FollowJointTrajectory
from geometry_msgs.msg import Twist
from cssr_system_interfaces.action import Animate
from cssr_system_interfaces.srv import SetActivation
from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.action import ActionClient
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.live_settings import SETTING_KEYS
from cssr_system.animate_behaviour.topics import WHEELS_KEY
from cssr_system.demo.gesture import GESTURE_PART
from cssr_system.ros2.gesture_player import gesture_goal
from cssr_system.ros2.program import call
from cssr_system.ros2.trajectory_client import STATE_NAMES
from cssr_system.soak.processes import (BUSY, PLATFORM, SIMULATOR, Program, arguments, base_remapping, heap_file,
                                        node_environment, robot_topics, soak, wait_until)

NODE = "/" + contract.NODE_NAME
CALL_TIMEOUT = 5.0  # s
START_TIMEOUT = 30.0  # s


def ros_arguments(parameters: dict) -> list:
    return ["--ros-args"] + [word for item in parameters.items() for word in ("-p", "%s:=%s" % item)]


def parameter(name: str, value) -> Parameter:
    """A live setting (dynamic_reconfigure's name) as the node's parameter (its configuration key)."""
    if isinstance(value, bool):
        typed = ParameterValue(type=ParameterType.PARAMETER_BOOL, bool_value=value)
    elif isinstance(value, str):
        typed = ParameterValue(type=ParameterType.PARAMETER_STRING, string_value=value)
    else:
        typed = ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=float(value))
    return Parameter(name=SETTING_KEYS[name], value=typed)


class Ros2Driver:
    def __init__(self, node: Node, folder: str) -> None:
        self.ros = node
        self.log_file = os.path.join(folder, "node.log")
        self.output_file = os.path.join(folder, "node.out")
        self.heap_file = heap_file(folder)
        self.simulator = Program([sys.executable, "-m", "cssr_system.ros2.simulated_pepper_node"]
                                 + ros_arguments(SIMULATOR) + ["-r", base_remapping()],
                                 os.path.join(folder, "simulatedPepper.out"))
        self.node = Program([sys.executable, "-m", "cssr_system.ros2.animate_behaviour_main"]
                            + ros_arguments(dict(BUSY, platform=PLATFORM, logFile=self.log_file)), self.output_file,
                            node_environment(folder))
        self._activation = node.create_client(SetActivation, NODE + "/" + contract.SET_ACTIVATION)
        self._parameters = node.create_client(SetParameters, NODE + "/set_parameters")
        self._animate = ActionClient(node, Animate, NODE + "/" + contract.ANIMATE_ACTION)
        topics = robot_topics()
        arm = node.resolve_topic_name(topics[GESTURE_PART])
        self._gesture = ActionClient(node, FollowJointTrajectory, arm)
        self._base = node.resolve_topic_name(topics[WHEELS_KEY])
        self._listener = None
        self._ended = None
        self._goals = {}  # name -> accepted goal handle
        self._lock = threading.Lock()

    def attach(self, ended) -> None:
        self._ended = ended

    def start(self) -> None:
        self.simulator.start()
        self.node.start()
        for what, ready in (("its service", lambda: self._activation.wait_for_service(timeout_sec=START_TIMEOUT)),
                            ("the animate action", lambda: self._animate.wait_for_server(timeout_sec=START_TIMEOUT)),
                            ("the right arm's controller",
                             lambda: self._gesture.wait_for_server(timeout_sec=START_TIMEOUT))):
            if not ready():
                raise SystemExit("soak: no %s within %g s (see %s)" % (what, START_TIMEOUT, self.output_file))
        self.base_listener(True)

    def node_pid(self) -> int:
        return self.node.process.pid

    def activate(self, state: str) -> bool:
        return call(self._activation, SetActivation.Request(state=state), CALL_TIMEOUT).success == \
            contract.REPLY_SUCCESS

    def set_setting(self, name: str, value) -> bool:
        reply = call(self._parameters, SetParameters.Request(parameters=[parameter(name, value)]), CALL_TIMEOUT)
        return all(result.successful for result in reply.results)

    def send_animate(self, goal: str, detail: dict) -> None:
        message = Animate.Goal(parts=list(detail["parts"]), intensity=float(detail["intensity"]),
                               duration=float(detail["duration"]))

        def send() -> None:
            self._animate.send_goal_async(message).add_done_callback(lambda future: self._accepted(goal, future))
        self._on_executor(send)

    def _accepted(self, goal: str, future) -> None:
        handle = future.result()
        if not handle.accepted:
            self._ended(goal, "REJECTED", "")
            return
        with self._lock:
            self._goals[goal] = handle
        handle.get_result_async().add_done_callback(lambda result: self._animate_ended(goal, result.result()))

    def _animate_ended(self, goal: str, response) -> None:
        with self._lock:
            self._goals.pop(goal, None)
        self._ended(goal, STATE_NAMES.get(response.status, str(response.status)), response.result.reason)

    def cancel_animate(self, goal: str) -> None:
        with self._lock:
            handle = self._goals.get(goal)
        if handle is not None:
            self._on_executor(handle.cancel_goal_async)

    def play_gesture(self, goal: str) -> None:
        def accepted(future) -> None:
            handle = future.result()
            if not handle.accepted:
                self._ended(goal, "REJECTED", "")
                return
            handle.get_result_async().add_done_callback(
                lambda result: self._ended(goal, STATE_NAMES.get(result.result().status, "?"), ""))

        def send() -> None:
            self._gesture.send_goal_async(gesture_goal()).add_done_callback(accepted)
        self._on_executor(send)

    def _on_executor(self, work) -> None:
        """Runs `work` (a goal or cancel to send) on the executor's thread: rclpy's action client registers a request
        only after sending it, so an answer the executor takes first would be lost (ros2/rclpy#1123)."""
        self.ros.executor.create_task(work)

    def restart_controllers(self) -> None:
        self.simulator.stop()
        self.simulator.start()
        wait_until(lambda: self._gesture.server_is_ready(), START_TIMEOUT)

    def base_listener(self, present: bool) -> None:
        """A subscription to the base's topic, as a base driver's, comes or goes."""
        if present and self._listener is None:
            self._listener = self.ros.create_subscription(Twist, self._base, lambda message: None, 1)
        elif not present and self._listener is not None:
            # Ended on the executor's thread: rclpy 7.1's executor fails (InvalidHandle) when another thread destroys
            # a subscription while it builds its wait set.
            self.ros.executor.create_task(self.ros.destroy_subscription, self._listener)
            self._listener = None

    def stop(self) -> None:
        """The node disabled and stopped, then the simulated Pepper, also after a failure of the run."""
        try:
            self.activate(contract.DISABLED)
        except Exception as error:  # noqa: BLE001 - the processes are stopped all the same
            print("soak: the last disable failed: %s" % error)
        self.node.stop()
        self.simulator.stop()


def main(argv=None) -> int:
    options = arguments(sys.argv[1:] if argv is None else argv)
    os.makedirs(options.folder, exist_ok=True)
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)  # Ctrl-C ends the run, and its processes with it
    node = Node("animateBehaviourSoak")
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, name="executor", daemon=True)
    spinner.start()
    driver = Ros2Driver(node, options.folder)
    try:
        driver.start()
        return soak(driver, options, "2")
    finally:
        driver.stop()
        executor.shutdown()
        spinner.join(5.0)  # rclpy's threads end before the interpreter does
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
