#!/usr/bin/env python3
"""`make benchmark`: animateBehaviour's figures on ROS 1 beside its targets and beside a minimal rospy node's
(`reference_node.py`), measured in the same run on the same machine, so the ratios hold anywhere (doc/performance.md).

One run per platform interface of the simulated Pepper: a master of its own, the simulated Pepper, then each
subject (the node, the reference) started as a process of this run. Times run from this process sending a request
to the message arriving here, where the controllers are (test/wire_recorder.py). CPU, memory, threads and open
files come from /proc for the subject's process (its pid from the master, never from a process name). What is
measured, and how, is measurement.py's, shared with the ROS 2 benchmark (benchmark_ros2.py); this file is the rospy
rig.

usage: benchmark.py --platform robot|simulator [--cycles N] [--cpu-window S] [--exit-runs N] [--json FILE]
                    [--markdown FILE] [--soak S] [--growth-cycles N] [--node-python PYTHON]
"""
import os
import signal
import subprocess
import sys
import tempfile
import time
import xmlrpc.client

import actionlib
import rosgraph
import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from std_srvs.srv import SetBool
from trajectory_msgs.msg import JointTrajectoryPoint

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, ".."))
from measurement import arguments, run, stop_left, stop_process  # noqa: E402
from reference_motion import configuration_of  # noqa: E402
from wire_recorder import WireRecorder, wait_until  # noqa: E402

from cssr_system.animate_behaviour.contract import (NODE_NAME, SERVICE_PATH, SET_ENABLED_SERVICE_NAME,  # noqa: E402
                                                    STATUS_TOPIC)
from cssr_system.msg import AnimateBehaviourStatus  # noqa: E402
from cssr_system.pepper.joint_table import PARTS  # noqa: E402
from cssr_system.soak.processes import free_port  # noqa: E402
from cssr_system.srv import setActivation  # noqa: E402

NODE = "/" + NODE_NAME
REPO_DIR = os.path.dirname(os.path.dirname(HERE))


def services() -> set:
    return {name for name, _ in rosgraph.Master("/benchmark").getSystemState()[2]}


def private_parameters(settings: dict) -> list:
    return ["_%s:=%s" % item for item in settings.items()]


class Subject:
    """A node under measurement (animateBehaviour or the reference), started as a process of this run."""

    def __init__(self, label: str, command, folder: str) -> None:
        self.label = label
        if rospy.has_param(NODE):
            rospy.delete_param(NODE)
        self.output = open(os.path.join(folder, label + ".out"), "a")
        self.process = subprocess.Popen(command, stdout=self.output, stderr=subprocess.STDOUT)
        if not wait_until(lambda: self.process.poll() is not None or SERVICE_PATH in services(), 30, period=0.05):
            self.process.kill()
            raise SystemExit("benchmark: %s did not offer %s within 30 s (see %s)"
                             % (label, SERVICE_PATH, self.output.name))
        if self.process.poll() is not None:
            raise SystemExit("benchmark: %s exited with status %d before offering %s (see %s)"
                             % (label, self.process.returncode, SERVICE_PATH, self.output.name))
        self.call = rospy.ServiceProxy(SERVICE_PATH, setActivation, persistent=True)
        self._set_enabled = rospy.ServiceProxy("/" + SET_ENABLED_SERVICE_NAME, SetBool, persistent=True)
        uri = rosgraph.Master("/benchmark").lookupNode(NODE)
        self.pid = xmlrpc.client.ServerProxy(uri).getPid("/benchmark")[2]  # the node's own word, not a name

    def activate(self, state: str) -> None:
        self.call(state)

    def set_enabled(self, data: bool) -> None:
        self._set_enabled(data)

    def stop(self, signal_number):
        """Seconds from sending the signal to the process's exit, and its exit status."""
        seconds, status = stop_process(self.process, signal_number)
        self.output.close()
        self.call.close()
        self._set_enabled.close()
        wait_until(lambda: SERVICE_PATH not in services(), 5)
        return seconds, status


class Rig:
    """The rospy side of measurement.py's rig: the wire as the controllers see it, the node's status, the subjects'
    processes and another client's goal."""

    def __init__(self, platform: str, folder: str, node_python=None) -> None:
        self.platform, self.folder, self.node_python = platform, folder, node_python
        self.started = []  # every subject started, so that none outlives the run
        configuration, topics = configuration_of(platform, {})
        self.quiet_time = configuration.yield_quiet_time
        self.topics = dict(topics)
        self.parts = {key for key in self.topics if key in PARTS}
        self.wire = WireRecorder(self.topics)
        self.status = None
        self._status_subscriber = rospy.Subscriber("/" + STATUS_TOPIC, AnimateBehaviourStatus, self._on_status)
        self._foreign = actionlib.SimpleActionClient(self.topics["RArm"], FollowJointTrajectoryAction)
        wait_until(self.wire.connected, 10)

    def node_command(self, settings: dict):
        start = ([self.node_python, os.path.join(REPO_DIR, "scripts", "animateBehaviour.py")] if self.node_python
                 else ["rosrun", "cssr_system", "animateBehaviour.py"])
        return start + ["_platform:=" + self.platform, "_behaviour:=all",
                        "_logFile:=" + os.path.join(self.folder, "node.log")] + private_parameters(settings)

    def reference_command(self, settings: dict):
        return [sys.executable, os.path.join(HERE, "reference_node.py"),
                "_platform:=" + self.platform] + private_parameters(settings)

    def start(self, label: str, command) -> Subject:
        subject = Subject(label, command, self.folder)
        self.started.append(subject)
        return subject

    def clear(self) -> None:
        self.wire.clear()

    def connected(self) -> bool:
        return self.wire.connected_to(NODE)

    def _from(self, store, since):
        """Part key -> arrival of the subject's first message in `store` since `since`."""
        firsts = {}
        for at, key, message in self.wire.snapshot(store):
            if at >= since and message._connection_header.get("callerid") == NODE and key in self.parts:
                firsts.setdefault(key, at)
        return firsts

    def goals(self, since: float) -> dict:
        return self._from(self.wire.goals, since)

    def stops(self, since: float) -> dict:
        """Part key -> arrival of the subject's first goal or cancel since `since`: the part's goal replaced or
        cancelled."""
        found = self._from(self.wire.goals, since)
        for key, at in self._from(self.wire.cancels, since).items():
            found[key] = min(at, found.get(key, at))
        return found

    def zero_twists(self, since: float) -> list:
        return [at for at, key, message in self.wire.snapshot(self.wire.twists)
                if at >= since and message.angular.z == 0.0 and message.linear.x == 0.0 and message.linear.y == 0.0]

    def _on_status(self, message) -> None:
        self.status = message

    def at_rest(self) -> bool:
        """The node reports itself disabled with every part idle (back at its centre)."""
        return self.status is not None and not self.status.enabled and all(
            part.state == "idle" for part in self.status.parts)

    def foreign_goal(self, seconds: float):
        self._foreign.wait_for_server(rospy.Duration(5))
        goal = FollowJointTrajectoryGoal()
        goal.trajectory.joint_names = list(PARTS["RArm"].joints)
        goal.trajectory.points.append(JointTrajectoryPoint(positions=list(PARTS["RArm"].centre),
                                                           time_from_start=rospy.Duration(seconds)))
        self._foreign.send_goal(goal)
        return time.monotonic() if self._foreign.wait_for_result(rospy.Duration(seconds + 3)) else None


def main(argv) -> int:
    options = arguments(argv, __doc__.split("\n\n")[0])
    folder = tempfile.mkdtemp(prefix="benchmark-")
    os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % free_port()
    os.environ.setdefault("ROS_HOME", folder)
    rig = None
    processes = [subprocess.Popen(["roscore", "-p", os.environ["ROS_MASTER_URI"].rsplit(":", 1)[1]],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        wait_until(lambda: rosgraph.is_master_online(), 20, period=0.1)
        processes.append(subprocess.Popen(["rosrun", "cssr_system", "simulatedPepper.py",
                                           "_platform:=" + options.platform],
                                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        rospy.init_node("benchmark", disable_signals=True)
        rig = Rig(options.platform, folder, options.node_python)
        run(rig, 1, options, folder, options.node_python or "the same")
    finally:
        if rig is not None:
            stop_left(rig.started)
        rospy.signal_shutdown("done")
        for process in reversed(processes):
            process.send_signal(signal.SIGINT)
            try:
                process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                process.kill()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
