#!/usr/bin/env python3
"""`make benchmark`: animateBehaviour's figures beside its targets and beside a minimal rospy node's
(`reference_node.py`), measured in the same run on the same machine, so the ratios hold anywhere (README: "Tests").

One run per platform interface of the simulated Pepper: a master of its own, the simulated Pepper, then each
subject (the node, the reference) started as a process of this run. Times run from this process sending a request
to the message arriving here, where the controllers are (test/wire_recorder.py). CPU, memory, threads and open
files come from /proc for the subject's process (its pid from the master, never from a process name).

usage: benchmark.py --platform robot|simulator [--cycles N] [--cpu-window S] [--json FILE] [--soak S]
                    [--growth-cycles N]
"""
import argparse
import json
import os
import signal
import socket
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

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from wire_recorder import WireRecorder, wait_until  # noqa: E402

from cssr_system.animate_behaviour.contract import NODE_NAME, SERVICE_PATH, SET_ENABLED_SERVICE_NAME  # noqa: E402
from cssr_system.animate_behaviour.topics import load_topic_map  # noqa: E402
from cssr_system.package_files import data_dir  # noqa: E402
from cssr_system.pepper.joint_table import PARTS  # noqa: E402
from cssr_system.srv import setActivation  # noqa: E402

NODE = "/" + NODE_NAME
HERE = os.path.dirname(os.path.abspath(__file__))
QUIET_TIME = 1.0  # the node's default yieldQuietTime: the resume delay is reported beyond it
# (figure, unit, target p90, target max); None: no target of that kind
TARGETS = [
    ("setActivation enabled reply", "ms", 10, 20), ("setActivation disabled reply", "ms", 10, 20),
    ("set_enabled true reply", "ms", 10, 20), ("set_enabled false reply", "ms", 10, 20),
    ("first goal of every part after enabled", "ms", None, 20), ("stop of every part after disabled", "ms", 10, 20),
    ("zero twist after disabled", "ms", None, 5), ("resume after another node's goal, beyond the quiet time", "ms",
                                                   None, 500),
    ("exit after SIGINT", "ms", None, 500), ("exit after SIGTERM", "ms", None, 500),
    ("CPU while disabled", "% of a core", None, 0.5), ("CPU while animating", "% of a core", None, 1.5),
    ("resident memory", "MB", None, 60), ("threads", "", None, 30), ("open files", "", None, None),
]


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


def process_figures(pid: int) -> dict:
    with open("/proc/%d/status" % pid) as stream:
        rss = next(int(line.split()[1]) for line in stream if line.startswith("VmRSS:")) / 1024.0
    return {"resident memory": rss, "threads": len(os.listdir("/proc/%d/task" % pid)),
            "open files": len(os.listdir("/proc/%d/fd" % pid))}


def cpu_seconds(pid: int) -> float:
    with open("/proc/%d/stat" % pid) as stream:
        fields = stream.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def cpu_share(pid: int, seconds: float) -> float:
    start, started = cpu_seconds(pid), time.monotonic()
    time.sleep(seconds)
    return 100.0 * (cpu_seconds(pid) - start) / (time.monotonic() - started)


class Subject:
    """A node under measurement: animateBehaviour or the reference."""

    def __init__(self, label: str, command, folder: str) -> None:
        self.label = label
        if rospy.has_param(NODE):
            rospy.delete_param(NODE)
        self.output = open(os.path.join(folder, label + ".out"), "w")
        self.process = subprocess.Popen(command, stdout=self.output, stderr=subprocess.STDOUT)
        rospy.wait_for_service(SERVICE_PATH, timeout=30)
        self.call = rospy.ServiceProxy(SERVICE_PATH, setActivation, persistent=True)
        uri = rosgraph.Master("/benchmark").lookupNode(NODE)
        self.pid = xmlrpc.client.ServerProxy(uri).getPid("/benchmark")[2]

    def stop(self, signal_number) -> float:
        started = time.monotonic()
        self.process.send_signal(signal_number)
        self.process.wait(timeout=10)
        seconds = time.monotonic() - started
        self.output.close()
        wait_until(lambda: not any(name == SERVICE_PATH for name, _ in
                                   rosgraph.Master("/benchmark").getSystemState()[2]), 5)
        return seconds


class Benchmark:
    def __init__(self, platform: str, cycles: int, cpu_window: float, folder: str) -> None:
        self.platform, self.cycles, self.cpu_window, self.folder = platform, cycles, cpu_window, folder
        topic_file = "pepperTopics.dat" if platform == "robot" else "simulatorTopics.dat"
        self.topics = dict(load_topic_map(os.path.join(data_dir(), topic_file)).topics)
        self.parts = {key for key in self.topics if key in PARTS}
        self.wire = WireRecorder(self.topics)
        wait_until(self.wire.connected, 10)

    def node_command(self, *extra):
        return (["rosrun", "cssr_system", "animateBehaviour.py", "_platform:=" + self.platform, "_behaviour:=all",
                 "_logFile:=" + os.path.join(self.folder, "node.log")] + list(extra))

    def reference_command(self):
        return [sys.executable, os.path.join(HERE, "reference_node.py"), "_platform:=" + self.platform]

    def _from(self, store, since, who=NODE):
        firsts = {}
        for at, key, message in self.wire.snapshot(store):
            if at >= since and message._connection_header.get("callerid") == who and key in self.parts:
                firsts.setdefault(key, at)
        return firsts

    def cycles_of(self, subject: Subject, figures: dict) -> None:
        subject.call("enabled")
        time.sleep(1.0)
        subject.call("disabled")
        time.sleep(1.0)
        for _ in range(self.cycles):
            self.wire.clear()
            sent = time.monotonic()
            subject.call("enabled")
            figures["setActivation enabled reply"].append(time.monotonic() - sent)
            wait_until(lambda: set(self._from(self.wire.goals, sent)) >= self.parts, 2)
            firsts = self._from(self.wire.goals, sent)
            if set(firsts) >= self.parts:
                figures["first goal of every part after enabled"].append(max(firsts.values()) - sent)
            time.sleep(0.4)
            sent = time.monotonic()
            subject.call("disabled")
            figures["setActivation disabled reply"].append(time.monotonic() - sent)

            def stops():
                found = self._from(self.wire.goals, sent)
                for key, at in self._from(self.wire.cancels, sent).items():
                    found[key] = min(at, found.get(key, at))
                return found
            wait_until(lambda: set(stops()) >= self.parts, 2)
            if set(stops()) >= self.parts:
                figures["stop of every part after disabled"].append(max(stops().values()) - sent)
            zeros = [at for at, key, message in self.wire.snapshot(self.wire.twists)
                     if at >= sent and message.angular.z == 0.0]
            if zeros:
                figures["zero twist after disabled"].append(zeros[0] - sent)
            time.sleep(0.4)

    def set_enabled_cycles(self, figures: dict) -> None:
        call = rospy.ServiceProxy("/" + SET_ENABLED_SERVICE_NAME, SetBool, persistent=True)
        for _ in range(self.cycles):
            for data, name in ((True, "set_enabled true reply"), (False, "set_enabled false reply")):
                sent = time.monotonic()
                call(data)
                figures[name].append(time.monotonic() - sent)
                time.sleep(0.3)

    def resume_delay(self, subject: Subject, figures: dict) -> None:
        client = actionlib.SimpleActionClient(self.topics["RArm"], FollowJointTrajectoryAction)
        client.wait_for_server(rospy.Duration(5))
        for _ in range(max(1, self.cycles // 10)):
            subject.call("enabled")
            time.sleep(1.5)
            goal = FollowJointTrajectoryGoal()
            goal.trajectory.joint_names = list(PARTS["RArm"].joints)
            goal.trajectory.points.append(JointTrajectoryPoint(positions=list(PARTS["RArm"].centre),
                                                               time_from_start=rospy.Duration(2.0)))
            client.send_goal(goal)
            client.wait_for_result(rospy.Duration(5))
            ended = time.monotonic()
            wait_until(lambda: "RArm" in self._from(self.wire.goals, ended), QUIET_TIME + 3)
            resumed = self._from(self.wire.goals, ended).get("RArm")
            if resumed is not None:
                figures["resume after another node's goal, beyond the quiet time"].append(
                    resumed - ended - QUIET_TIME)
            subject.call("disabled")
            time.sleep(0.5)

    def measure(self, label: str, command, node: bool) -> dict:
        figures = {name: [] for name, _, _, _ in TARGETS}
        subject = Subject(label, command, self.folder)
        self.cycles_of(subject, figures)
        if node:
            self.set_enabled_cycles(figures)
            self.resume_delay(subject, figures)
        time.sleep(1.0)
        figures["CPU while disabled"].append(cpu_share(subject.pid, self.cpu_window))
        subject.call("enabled")
        time.sleep(1.0)
        figures["CPU while animating"].append(cpu_share(subject.pid, self.cpu_window))
        for name, value in process_figures(subject.pid).items():
            figures[name].append(value)
        for signal_number, name in ((signal.SIGINT, "exit after SIGINT"), (signal.SIGTERM, "exit after SIGTERM")):
            if subject is None:
                subject = Subject(label, command, self.folder)
                subject.call("enabled")
                time.sleep(1.0)
            figures[name].append(subject.stop(signal_number))
            subject = None
        return figures


def summary(values, unit):
    if not values:
        return None
    scale = 1000.0 if unit == "ms" else 1.0
    ordered = sorted(value * scale for value in values)

    def rank(fraction):  # nearest rank, the same rule for every percentile
        return ordered[int(round(fraction * (len(ordered) - 1)))]
    return {"p50": rank(0.5), "p90": rank(0.9), "max": ordered[-1], "samples": len(ordered)}


def table(platform: str, results: dict) -> str:
    lines = ["animateBehaviour benchmark, platform %s (node beside a minimal rospy reference node)" % platform,
             "%-56s %-22s %-22s %-14s %s" % ("figure", "node p50/p90/max", "reference p50/p90/max", "target",
                                             "met")]
    for name, unit, p90_target, max_target in TARGETS:
        cells = []
        for subject in ("node", "reference"):
            figure = results[subject].get(name)
            cells.append("-" if figure is None else "%.1f/%.1f/%.1f" % (figure["p50"], figure["p90"], figure["max"]))
        node = results["node"].get(name)
        target = " ".join(part for part in (("p90<=%g" % p90_target) if p90_target is not None else "",
                                            ("max<=%g" % max_target) if max_target is not None else "") if part)
        met = "-" if node is None or not target else ("yes" if (p90_target is None or node["p90"] <= p90_target)
                                                      and (max_target is None or node["max"] <= max_target)
                                                      else "NO")
        lines.append("%-56s %-22s %-22s %-14s %s" % (name + (" (%s)" % unit if unit else ""), cells[0], cells[1],
                                                     target or "-", met))
    return "\n".join(lines)


def soak(benchmark: Benchmark, seconds: float, growth_cycles: int) -> dict:
    """The node with short goals, enabled and disabled every few seconds, then `growth_cycles` quick cycles."""
    log = os.path.join(benchmark.folder, "soak.log")
    subject = Subject("soak", benchmark.node_command("_numPoints:=2", "_gestureDuration:=0.5", "_legRepeatFactor:=1",
                                                     "_numPointsLeg:=1", "_logFile:=" + log), benchmark.folder)
    start = dict(process_figures(subject.pid), log_bytes=os.path.getsize(log))
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        subject.call("enabled")
        time.sleep(4.0)
        subject.call("disabled")
        time.sleep(1.0)
    middle = dict(process_figures(subject.pid), log_bytes=os.path.getsize(log))
    for _ in range(growth_cycles):
        subject.call("enabled")
        subject.call("disabled")
    end = dict(process_figures(subject.pid), log_bytes=os.path.getsize(log) + os.path.getsize(log + ".1")
               if os.path.exists(log + ".1") else os.path.getsize(log))
    subject.stop(signal.SIGINT)
    return {"soak seconds": seconds, "growth cycles": growth_cycles, "start": start, "after soak": middle,
            "after cycles": end}


def main(argv) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--platform", choices=("robot", "simulator"), default="robot")
    parser.add_argument("--cycles", type=int, default=30)
    parser.add_argument("--cpu-window", type=float, default=10.0)
    parser.add_argument("--json", default=None, help="file the figures are added to (one section per platform)")
    parser.add_argument("--soak", type=float, default=0.0, help="seconds of soak with short goals (0: none)")
    parser.add_argument("--growth-cycles", type=int, default=0, help="quick enable/disable cycles after the soak")
    arguments = parser.parse_args(argv)
    folder = tempfile.mkdtemp(prefix="benchmark-")
    os.environ["ROS_MASTER_URI"] = "http://localhost:%d" % free_port()
    os.environ.setdefault("ROS_HOME", folder)
    processes = [subprocess.Popen(["roscore", "-p", os.environ["ROS_MASTER_URI"].rsplit(":", 1)[1]],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        wait_until(lambda: rosgraph.is_master_online(), 20, period=0.1)
        processes.append(subprocess.Popen(["rosrun", "cssr_system", "simulatedPepper.py",
                                           "_platform:=" + arguments.platform],
                                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        rospy.init_node("benchmark", disable_signals=True)
        benchmark = Benchmark(arguments.platform, arguments.cycles, arguments.cpu_window, folder)
        raw = {"node": benchmark.measure("node", benchmark.node_command(), node=True),
               "reference": benchmark.measure("reference", benchmark.reference_command(), node=False)}
        units = {name: unit for name, unit, _, _ in TARGETS}
        results = {subject: {name: summary(values, units[name]) for name, values in figures.items() if values}
                   for subject, figures in raw.items()}
        print(table(arguments.platform, results))
        section = {"figures": results, "targets": {name: {"unit": unit, "p90": p90, "max": top}
                                                   for name, unit, p90, top in TARGETS},
                   "cycles": arguments.cycles, "cpu_window": arguments.cpu_window}
        if arguments.soak or arguments.growth_cycles:
            section["soak"] = soak(benchmark, arguments.soak, arguments.growth_cycles)
            print("soak:", json.dumps(section["soak"]))
        if arguments.json:
            document = {}
            if os.path.exists(arguments.json):
                with open(arguments.json) as stream:
                    document = json.load(stream)
            document[arguments.platform] = section
            with open(arguments.json, "w") as stream:
                json.dump(document, stream, indent=1)
            print("figures written to %s" % arguments.json)
    finally:
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
