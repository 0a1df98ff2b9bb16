#!/usr/bin/env python3
"""`make benchmark ROS=2`: animateBehaviour's figures on ROS 2 beside its targets and beside a minimal rclpy node's
(`reference_node_ros2.py`), measured in the same run on the same machine (doc/performance.md). Runs inside the ROS 2
environment (tools/ros2/run.sh) on this process's ROS_DOMAIN_ID; what is measured, and how, is measurement.py's,
shared with the ROS 1 benchmark (benchmark.py); this file is the rclpy rig.

One run per platform interface: the ROS 2 simulated Pepper, then each subject (the node, the reference) started as a
process of this run (its pid is the process's own: each runs `python3` directly). On ROS 2 an action's goals and
cancels are service calls between client and server that no third node sees; what the controller accepted shows
on the action's status topic (`<action>/_action/status`), which the server publishes as each goal is accepted and as
each is being cancelled. So times run from this process sending a request to the status naming a new goal (or a
goal being cancelled) arriving here: a goal's way to the simulated Pepper, its acceptance there and the status's way
back. A goal of this process (the other node's goal of the resume figure) is told apart by its id.

usage: benchmark_ros2.py --platform robot|simulator [--cycles N] [--cpu-window S] [--exit-runs N] [--json FILE]
                         [--markdown FILE] [--soak S] [--growth-cycles N]
"""
import os
import subprocess
import sys
import tempfile
import threading
import time
import uuid

import rclpy
from action_msgs.msg import GoalStatus, GoalStatusArray
from builtin_interfaces.msg import Duration
from control_msgs.action import FollowJointTrajectory
from cssr_system_interfaces.msg import AnimateBehaviourStatus
from cssr_system_interfaces.srv import SetActivation
from geometry_msgs.msg import Twist
from rclpy.action import ActionClient, get_action_client_names_and_types_by_node
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, qos_profile_action_status_default
from rclpy.signals import SignalHandlerOptions
from std_srvs.srv import SetBool
from trajectory_msgs.msg import JointTrajectoryPoint
from unique_identifier_msgs.msg import UUID

HERE = os.path.dirname(os.path.abspath(__file__))
from measurement import arguments, run, stop_left, stop_process, wait_until  # noqa: E402
from reference_motion import configuration_of  # noqa: E402

from cssr_system.animate_behaviour import contract  # noqa: E402
from cssr_system.animate_behaviour.topics import WHEELS_KEY  # noqa: E402
from cssr_system.pepper.joint_table import PARTS  # noqa: E402
from cssr_system.ros2.program import call  # noqa: E402
from cssr_system.soak.processes import Program  # noqa: E402

NODE = "/" + contract.NODE_NAME
CALL_TIMEOUT = 5.0  # s
START_TIMEOUT = 30.0  # s
CANCELLING = (GoalStatus.STATUS_CANCELING, GoalStatus.STATUS_CANCELED)


def ros_arguments(parameters: dict) -> list:
    return ["--ros-args"] + [word for item in parameters.items() for word in ("-p", "%s:=%s" % item)]


class Subject:
    """A node under measurement (animateBehaviour or the reference), started as a process of this run."""

    def __init__(self, rig: "Rig", label: str, command) -> None:
        self.rig = rig
        self.output = open(os.path.join(rig.folder, label + ".out"), "a")
        self.process = subprocess.Popen(command, stdout=self.output, stderr=subprocess.STDOUT)
        self.pid = self.process.pid
        if not wait_until(lambda: self.process.poll() is not None or rig.activation.service_is_ready(),
                          START_TIMEOUT, period=0.05):
            self.process.kill()
            raise SystemExit("benchmark: %s did not offer its setActivation within %g s (see %s)"
                             % (label, START_TIMEOUT, self.output.name))
        if self.process.poll() is not None:
            raise SystemExit("benchmark: %s exited with status %d before offering its setActivation (see %s)"
                             % (label, self.process.returncode, self.output.name))
        # A service seen in the graph may not answer yet (the reply's way back not yet discovered): a `disabled`,
        # which changes nothing at start, is asked until both services answer.
        for client, request in ((rig.activation, SetActivation.Request(state="disabled")),
                                (rig.enabling, SetBool.Request(data=False))):
            if not wait_until(lambda: self._answers(client, request), START_TIMEOUT, period=0.0):
                self.process.kill()
                raise SystemExit("benchmark: %s does not answer on %s (see %s)"
                                 % (label, client.srv_name, self.output.name))

    @staticmethod
    def _answers(client, request) -> bool:
        try:
            call(client, request, 1.0)
        except TimeoutError:
            return False
        return True

    def activate(self, state: str) -> None:
        call(self.rig.activation, SetActivation.Request(state=state), CALL_TIMEOUT)

    def set_enabled(self, data: bool) -> None:
        call(self.rig.enabling, SetBool.Request(data=data), CALL_TIMEOUT)

    def stop(self, signal_number):
        """Seconds from sending the signal to the process's exit, and its exit status."""
        seconds, status = stop_process(self.process, signal_number)
        self.output.close()
        wait_until(lambda: not self.rig.activation.service_is_ready(), 5)
        return seconds, status


class Rig:
    """The rclpy side of measurement.py's rig: each controller's accepted and cancelled goals as its action's status
    shows them, the base's Twists, the node's status, the subjects' processes and another client's goal."""

    def __init__(self, node: Node, platform: str, folder: str) -> None:
        self.node, self.platform, self.folder = node, platform, folder
        self.started = []  # every subject started, so that none outlives the run
        configuration, topics = configuration_of(platform, {})
        self.quiet_time = configuration.yield_quiet_time
        self.actions = {key: node.resolve_topic_name(name) for key, name in topics.items() if key in PARTS}
        self.parts = set(self.actions)
        self._lock = threading.Lock()
        self._goals, self._cancels, self._twists = [], [], []  # (arrival, part key, goal id or Twist)
        self._seen, self._seen_cancelling = set(), set()
        self._foreign = set()  # ids of this process's own goals
        for key, action in self.actions.items():
            node.create_subscription(GoalStatusArray, action + "/_action/status",
                                     lambda message, key=key: self._on_goal_status(key, message),
                                     qos_profile_action_status_default)
        if WHEELS_KEY in topics:
            node.create_subscription(Twist, node.resolve_topic_name(topics[WHEELS_KEY]), self._on_twist, 10)
        self.status = None
        latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
        node.create_subscription(AnimateBehaviourStatus, NODE + "/" + contract.STATUS, self._on_status, latched)
        self.activation = node.create_client(SetActivation, NODE + "/" + contract.SET_ACTIVATION)
        self.enabling = node.create_client(SetBool, NODE + "/" + contract.SET_ENABLED)
        self._arm = ActionClient(node, FollowJointTrajectory, self.actions["RArm"])

    def _on_goal_status(self, key: str, message) -> None:
        now = time.monotonic()
        with self._lock:
            for status in message.status_list:
                goal = bytes(status.goal_info.goal_id.uuid)
                if goal not in self._seen:
                    self._seen.add(goal)
                    if goal not in self._foreign:
                        self._goals.append((now, key, goal))
                if status.status in CANCELLING and goal not in self._seen_cancelling:
                    self._seen_cancelling.add(goal)
                    self._cancels.append((now, key, goal))

    def _on_twist(self, message) -> None:
        with self._lock:
            self._twists.append((time.monotonic(), WHEELS_KEY, message))

    def _on_status(self, message) -> None:
        self.status = message

    def node_command(self, settings: dict):
        parameters = dict({"platform": self.platform, "behaviour": "all",
                           "logFile": os.path.join(self.folder, "node.log")}, **settings)
        return [sys.executable, "-m", "cssr_system.ros2.animate_behaviour_main"] + ros_arguments(parameters)

    def reference_command(self, settings: dict):
        return [sys.executable, os.path.join(HERE, "reference_node_ros2.py")] + ros_arguments(
            dict({"platform": self.platform}, **settings))

    def start(self, label: str, command) -> Subject:
        subject = Subject(self, label, command)
        self.started.append(subject)
        return subject

    def clear(self) -> None:
        with self._lock:
            del self._goals[:], self._cancels[:], self._twists[:]

    def connected(self) -> bool:
        """The graph shows the subject as a client of every part's action."""
        try:
            clients = {name for name, _ in
                       get_action_client_names_and_types_by_node(self.node, contract.NODE_NAME, "/")}
        except Exception:  # rclpy's RCLError: the subject is not in this node's graph yet
            return False
        return clients >= set(self.actions.values())

    def _firsts(self, store, since: float) -> dict:
        firsts = {}
        with self._lock:
            for at, key, _ in store:
                if at >= since:
                    firsts.setdefault(key, at)
        return firsts

    def goals(self, since: float) -> dict:
        return self._firsts(self._goals, since)

    def stops(self, since: float) -> dict:
        """Part key -> arrival of the subject's first new goal or cancelling since `since`."""
        found = self._firsts(self._goals, since)
        for key, at in self._firsts(self._cancels, since).items():
            found[key] = min(at, found.get(key, at))
        return found

    def zero_twists(self, since: float) -> list:
        with self._lock:
            return [at for at, _, message in self._twists if at >= since and message.angular.z == 0.0
                    and message.linear.x == 0.0 and message.linear.y == 0.0]

    def at_rest(self) -> bool:
        """The node reports itself disabled with every part idle (back at its centre)."""
        return self.status is not None and not self.status.enabled and all(
            part.state == "idle" for part in self.status.parts)

    def controllers_ready(self, timeout: float) -> bool:
        return self._arm.wait_for_server(timeout_sec=timeout)

    def foreign_goal(self, seconds: float):
        if not self.controllers_ready(5.0):
            return None
        goal = FollowJointTrajectory.Goal()
        goal.trajectory.joint_names = list(PARTS["RArm"].joints)
        goal.trajectory.points = [JointTrajectoryPoint(positions=list(PARTS["RArm"].centre), velocities=[0.0] * 5,
                                                       time_from_start=Duration(sec=int(seconds)))]
        goal_id = uuid.uuid4().bytes
        with self._lock:
            self._foreign.add(goal_id)
        ended = threading.Event()

        def send() -> None:  # on the executor's thread: rclpy's action client is not thread-safe (ros2/rclpy#1123)
            accepted = self._arm.send_goal_async(goal, goal_uuid=UUID(uuid=list(goal_id)))
            accepted.add_done_callback(lambda future: future.result().get_result_async().add_done_callback(
                lambda _: ended.set()))
        self.node.executor.create_task(send)
        return time.monotonic() if ended.wait(seconds + 3.0) else None


def main(argv) -> int:
    options = arguments(argv, __doc__.split("\n\n")[0])
    folder = tempfile.mkdtemp(prefix="benchmark-ros2-")
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = Node("benchmark")
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    spinner = threading.Thread(target=executor.spin, name="executor", daemon=True)
    simulator = Program([sys.executable, "-m", "cssr_system.ros2.simulated_pepper_node"]
                        + ros_arguments({"platform": options.platform}), os.path.join(folder, "simulatedPepper.out"))
    rig = None
    try:
        simulator.start()
        spinner.start()
        rig = Rig(node, options.platform, folder)
        if not rig.controllers_ready(START_TIMEOUT):
            raise SystemExit("benchmark: the simulated Pepper's controllers did not come within %g s (see %s)"
                             % (START_TIMEOUT, folder))
        run(rig, 2, options, folder, "the same")
    finally:
        if rig is not None:
            stop_left(rig.started)
        simulator.stop()
        executor.shutdown()
        spinner.join(5.0)
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
