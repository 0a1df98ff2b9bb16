#!/usr/bin/env python3
"""`make benchmark`: animateBehaviour's figures beside its targets and beside a minimal rospy node's
(`reference_node.py`), measured in the same run on the same machine, so the ratios hold anywhere (doc/performance.md).

One run per platform interface of the simulated Pepper: a master of its own, the simulated Pepper, then each
subject (the node, the reference) started as a process of this run. Times run from this process sending a request
to the message arriving here, where the controllers are (test/wire_recorder.py). CPU, memory, threads and open
files come from /proc for the subject's process (its pid from the master, never from a process name).

usage: benchmark.py --platform robot|simulator [--cycles N] [--cpu-window S] [--exit-runs N] [--json FILE]
                    [--markdown FILE] [--soak S] [--growth-cycles N]
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
from typing import NamedTuple, Optional

import actionlib
import rosgraph
import rospy
from control_msgs.msg import FollowJointTrajectoryAction, FollowJointTrajectoryGoal
from std_srvs.srv import SetBool
from trajectory_msgs.msg import JointTrajectoryPoint

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from wire_recorder import WireRecorder, wait_until  # noqa: E402

from cssr_system.animate_behaviour.configuration import ALL_BEHAVIOURS, load_configuration  # noqa: E402
from cssr_system.animate_behaviour.configuration import shipped_configuration_path, topic_file_path  # noqa: E402
from cssr_system.animate_behaviour.contract import (NODE_NAME, SERVICE_PATH, SET_ENABLED_SERVICE_NAME,  # noqa: E402
                                                    STATUS_TOPIC)
from cssr_system.animate_behaviour.topics import load_topic_map  # noqa: E402
from cssr_system.core.joint_states import REST_DELAY  # noqa: E402
from cssr_system.msg import AnimateBehaviourStatus  # noqa: E402
from cssr_system.pepper.joint_table import PARTS  # noqa: E402
from cssr_system.soak.process_figures import cpu_seconds, log_bytes, process_figures  # noqa: E402
from cssr_system.srv import setActivation  # noqa: E402

NODE = "/" + NODE_NAME
HERE = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(os.path.dirname(HERE))
PLATFORMS = ("robot", "simulator")


class Target(NamedTuple):
    """A figure and its targets; None: no target of that kind. `mean` applies to the mean over the samples;
    `above_reference`: the node's mean at most the reference node's mean (measured in the same run) plus this."""
    name: str
    unit: str
    p90: Optional[float] = None
    max: Optional[float] = None
    mean: Optional[float] = None
    above_reference: Optional[float] = None

    def as_dict(self) -> dict:
        """The targets as the JSON gives them."""
        return {"unit": self.unit, "p90": self.p90, "max": self.max, "mean": self.mean,
                "mean above reference": self.above_reference}


RESUME = "resume after another node's goal, beyond the quiet time"
EXITS = ("exit after SIGINT", "exit after SIGTERM")
COLD_FIRST_GOAL = "first goal of every part, first enable since start-up"
TARGETS = [
    Target("setActivation enabled reply", "ms", 10, 20), Target("setActivation disabled reply", "ms", 10, 20),
    Target("set_enabled true reply", "ms", 10, 20), Target("set_enabled false reply", "ms", 10, 20),
    Target("first goal of every part after enabled", "ms", p90=20),
    Target(COLD_FIRST_GOAL, "ms", p90=20),
    Target("stop of every part after disabled", "ms", 10, 20),
    Target("zero twist after disabled", "ms", max=5),
    Target(RESUME, "ms", max=500),
    Target(EXITS[0], "ms", max=500), Target(EXITS[1], "ms", max=500),
    Target("CPU while disabled", "% of a core", above_reference=0.2),
    Target("CPU while animating", "% of a core", mean=1.5),
    Target("resident memory", "MB", max=60), Target("threads", "", max=30), Target("open files", ""),
]
PROCESS_FIGURES = ("resident memory", "threads", "open files")


def platform_configuration(platform: str):
    """The shipped configuration as the node reads it in this benchmark (platform and behaviour `all`)."""
    return load_configuration(shipped_configuration_path(), {"platform": platform, "behaviour": ALL_BEHAVIOURS})


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


def cpu_shares(pid: int, seconds: float, figures: dict, slices: int = 4) -> list:
    """Shares of one core over `slices` equal parts of `seconds` (their mean is the window's share); the
    process figures are sampled at the end of each part."""
    shares = []
    for _ in range(slices):
        start, started = cpu_seconds(pid), time.monotonic()
        time.sleep(seconds / slices)
        shares.append(100.0 * (cpu_seconds(pid) - start) / (time.monotonic() - started))
        sample_process(pid, figures)
    return shares


def sample_process(pid: int, figures: dict) -> None:
    for name, value in process_figures(pid).items():
        figures[name].append(value)


def services() -> set:
    return {name for name, _ in rosgraph.Master("/benchmark").getSystemState()[2]}


class Subject:
    """A node under measurement (animateBehaviour or the reference), started as a process of this run."""

    def __init__(self, label: str, command, folder: str) -> None:
        self.label = label
        if rospy.has_param(NODE):
            rospy.delete_param(NODE)
        self.output = open(os.path.join(folder, label + ".out"), "a")
        self.process = subprocess.Popen(command, stdout=self.output, stderr=subprocess.STDOUT)
        if not wait_until(lambda: self.process.poll() is not None or SERVICE_PATH in services(), 30, period=0.05):
            raise SystemExit("benchmark: %s did not offer %s within 30 s (see %s)"
                             % (label, SERVICE_PATH, self.output.name))
        if self.process.poll() is not None:
            raise SystemExit("benchmark: %s exited with status %d before offering %s (see %s)"
                             % (label, self.process.returncode, SERVICE_PATH, self.output.name))
        self.call = rospy.ServiceProxy(SERVICE_PATH, setActivation, persistent=True)
        uri = rosgraph.Master("/benchmark").lookupNode(NODE)
        self.pid = xmlrpc.client.ServerProxy(uri).getPid("/benchmark")[2]  # the node's own word, not a name

    def stop(self, signal_number):
        """Seconds from sending the signal to the process's exit, and its exit status."""
        started = time.monotonic()
        self.process.send_signal(signal_number)
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        seconds = time.monotonic() - started
        self.output.close()
        wait_until(lambda: SERVICE_PATH not in services(), 5)
        return seconds, self.process.returncode


class Benchmark:
    def __init__(self, platform: str, cycles: int, cpu_window: float, exit_runs: int, folder: str) -> None:
        self.platform, self.cycles, self.cpu_window, self.folder = platform, cycles, cpu_window, folder
        self.exit_runs = exit_runs
        self.node_python = None  # the node's interpreter when not the script's own
        configuration = platform_configuration(platform)
        self.quiet_time = configuration.yield_quiet_time
        self.topics = dict(load_topic_map(topic_file_path(configuration)).topics)
        self.parts = {key for key in self.topics if key in PARTS}
        self.wire = WireRecorder(self.topics)
        self.status = None
        self._status_subscriber = rospy.Subscriber("/" + STATUS_TOPIC, AnimateBehaviourStatus, self._on_status)
        wait_until(self.wire.connected, 10)

    def node_command(self, *extra):
        start = ([self.node_python, os.path.join(REPO_DIR, "scripts", "animateBehaviour.py")] if self.node_python
                 else ["rosrun", "cssr_system", "animateBehaviour.py"])
        return start + ["_platform:=" + self.platform, "_behaviour:=" + ALL_BEHAVIOURS,
                        "_logFile:=" + os.path.join(self.folder, "node.log")] + list(extra)

    def reference_command(self):
        return [sys.executable, os.path.join(HERE, "reference_node.py"), "_platform:=" + self.platform]

    def _from(self, store, since, who=NODE):
        """Part key -> arrival of the subject's first message in `store` since `since`."""
        firsts = {}
        for at, key, message in self.wire.snapshot(store):
            if at >= since and message._connection_header.get("callerid") == who and key in self.parts:
                firsts.setdefault(key, at)
        return firsts

    def _stops(self, since):
        """Part key -> arrival of the subject's first goal or cancel since `since`: the part's goal replaced or
        cancelled."""
        found = self._from(self.wire.goals, since)
        for key, at in self._from(self.wire.cancels, since).items():
            found[key] = min(at, found.get(key, at))
        return found

    def _record_every_part(self, arrivals, sent: float, samples: list, timeout: float) -> None:
        """Waits up to `timeout` for `arrivals()` (part key -> arrival) to hold every part, then records the
        last one's delay after `sent`; records nothing when a part never came."""
        wait_until(lambda: set(arrivals()) >= self.parts, timeout)
        found = arrivals()
        if set(found) >= self.parts:
            samples.append(max(found.values()) - sent)

    def _on_status(self, message) -> None:
        self.status = message

    def at_rest(self) -> bool:
        """The node reports itself disabled with every part idle (back at its centre)."""
        return self.status is not None and not self.status.enabled and all(
            part.state == "idle" for part in self.status.parts)

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
            self._record_every_part(lambda: self._from(self.wire.goals, sent), sent,
                                    figures["first goal of every part after enabled"], 2)
            time.sleep(0.4)
            sample_process(subject.pid, figures)
            sent = time.monotonic()
            subject.call("disabled")
            figures["setActivation disabled reply"].append(time.monotonic() - sent)
            self._record_every_part(lambda: self._stops(sent), sent, figures["stop of every part after disabled"], 2)
            zeros = [at for at, key, message in self.wire.snapshot(self.wire.twists)
                     if at >= sent and message.angular.z == 0.0 and message.linear.x == 0.0
                     and message.linear.y == 0.0]
            if zeros:
                figures["zero twist after disabled"].append(zeros[0] - sent)
            time.sleep(0.4)
            # The next enable starts from rest, as after any disabled spell longer than the return home (the
            # reference has no status: the sleep above is its rest).
            if wait_until(self.at_rest, 3.0):
                time.sleep(0.2)

    def set_enabled_cycles(self, figures: dict) -> None:
        call = rospy.ServiceProxy("/" + SET_ENABLED_SERVICE_NAME, SetBool, persistent=True)
        for _ in range(self.cycles):
            for data, name in ((True, "set_enabled true reply"), (False, "set_enabled false reply")):
                sent = time.monotonic()
                call(data)
                figures[name].append(time.monotonic() - sent)
                time.sleep(0.3)

    def resume_delay(self, subject: Subject, figures: dict) -> None:
        """Another node's 2 s goal on the right arm while the node animates: from its result to the node's next
        goal on that arm, less the quiet time the node waits by design."""
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
            wait_until(lambda: "RArm" in self._from(self.wire.goals, ended), self.quiet_time + 3)
            resumed = self._from(self.wire.goals, ended).get("RArm")
            if resumed is not None:
                figures[RESUME].append(resumed - ended - self.quiet_time)
            subject.call("disabled")
            time.sleep(0.5)

    def exits(self, subject: Subject, label: str, command, figures: dict, stopped: dict, statuses: dict) -> None:
        """`exit_runs` times each signal while animating: seconds to the exit, and whether every part that had a
        goal of the subject got it replaced or cancelled on the wire first (a message that arrives at all left
        before the exit). The signal waits, up to 5 s, for every part to have a goal: a part whose controller
        the subject has not connected yet moves nothing and needs no stop."""
        for _ in range(self.exit_runs):
            for signal_number, name in zip((signal.SIGINT, signal.SIGTERM), EXITS):
                if subject is None:
                    self.wire.clear()
                    subject = Subject(label, command, self.folder)
                    wait_until(lambda: self.wire.connected_to(NODE), 5)  # its cancels, too, are seen
                    time.sleep(2.0)  # started, then enabled later (its controllers have connected)
                    sent = time.monotonic()
                    subject.call("enabled")
                    self._record_every_part(lambda: self._from(self.wire.goals, sent), sent,
                                            figures[COLD_FIRST_GOAL], 5)
                    time.sleep(0.5)
                moving = set(self._from(self.wire.goals, 0.0))
                sent = time.monotonic()
                seconds, status = subject.stop(signal_number)
                subject = None
                figures[name].append(seconds)
                wait_until(lambda: set(self._stops(sent)) >= moving, 1)
                stopped[name].append(bool(moving) and set(self._stops(sent)) >= moving)
                statuses[name].append(status)

    def measure(self, label: str, command, node: bool) -> dict:
        """Every figure that applies to the subject: lists of raw samples (seconds, %, MB, counts), and per exit
        figure whether the robot was stopped first and the exit status."""
        figures = {target.name: [] for target in TARGETS}
        stopped = {name: [] for name in EXITS}
        statuses = {name: [] for name in EXITS}
        subject = Subject(label, command, self.folder)
        sample_process(subject.pid, figures)
        self.cycles_of(subject, figures)
        if node:  # the reference has neither the SetBool service nor the yielding
            self.set_enabled_cycles(figures)
            self.resume_delay(subject, figures)
        if node:  # disabled means at rest: the parts are home and the node no longer listens to /joint_states
            wait_until(self.at_rest, 10)
            time.sleep(REST_DELAY)
        time.sleep(1.0)
        figures["CPU while disabled"] = cpu_shares(subject.pid, self.cpu_window, figures)
        subject.call("enabled")
        time.sleep(1.0)
        figures["CPU while animating"] = cpu_shares(subject.pid, self.cpu_window, figures)
        self.exits(subject, label, command, figures, stopped, statuses)
        return {"figures": figures, "stopped first": stopped, "exit status": statuses}


def summary(values, unit):
    """p50, p90 (nearest rank, the same rule for both), max, mean and the number of samples, in `unit`."""
    if not values:
        return None
    scale = 1000.0 if unit == "ms" else 1.0
    ordered = sorted(value * scale for value in values)

    def rank(fraction):
        return ordered[int(round(fraction * (len(ordered) - 1)))]
    return {"p50": rank(0.5), "p90": rank(0.9), "max": ordered[-1], "mean": sum(ordered) / len(ordered),
            "samples": len(ordered)}


def verdict(target: Target, figure: Optional[dict], reference: Optional[dict]) -> Optional[bool]:
    """Whether the node's figure meets every target it has (None: no target, or not measured; a target relative to
    the reference is not met without the reference's figure)."""
    if figure is None or (target.p90, target.max, target.mean, target.above_reference) == (None, None, None, None):
        return None
    met = ((target.p90 is None or figure["p90"] <= target.p90) and (target.max is None or figure["max"] <= target.max)
           and (target.mean is None or figure["mean"] <= target.mean))
    if target.above_reference is not None:
        met = met and reference is not None and figure["mean"] <= reference["mean"] + target.above_reference
    if "stopped first" in figure:
        met = met and figure["stopped first"] == figure["samples"] and set(figure["exit status"]) == {0}
    return met


def target_text(target: Target) -> str:
    kinds = (("p90", "", target.p90), ("max", "", target.max), ("mean", "", target.mean),
             ("mean", "ref+", target.above_reference))
    parts = ["%s<=%s%g" % (kind, base, value) for kind, base, value in kinds if value is not None]
    if target.name in EXITS:
        parts.append("stopped first")
    return " ".join(parts) or "-"


def cell(figure: Optional[dict]) -> str:
    if figure is None:
        return "-"
    text = "%.1f / %.1f / %.1f" % (figure["p50"], figure["p90"], figure["max"])
    if "stopped first" in figure:
        text += " (stopped %d/%d)" % (figure["stopped first"], figure["samples"])
    return text


def rows_of(results: dict) -> list:
    """Per target: (figure and unit, the node's p50 / p90 / max, the reference's, target, met)."""
    rows = []
    for target in TARGETS:
        node = results["node"].get(target.name)
        met = verdict(target, node, results["reference"].get(target.name))
        met_text = "-" if met is None else ("yes" if met else "NO")
        if (target.mean, target.above_reference) != (None, None) and node is not None:
            met_text += " (mean %.2f)" % node["mean"]
        rows.append((target.name + (" (%s)" % target.unit if target.unit else ""), cell(node),
                     cell(results["reference"].get(target.name)), target_text(target), met_text))
    return rows


def table(platform: str, results: dict) -> str:
    rows = [("figure", "node p50 / p90 / max", "reference p50 / p90 / max", "target", "met?")] + rows_of(results)
    widths = [max(len(row[column]) for row in rows) for column in range(4)]
    lines = ["animateBehaviour benchmark, platform %s: the node beside a minimal rospy reference node" % platform]
    lines += ["  ".join(text.ljust(width) for text, width in zip(row, widths)) + "  " + row[4] for row in rows]
    return "\n".join(lines)


def results_of(raw: dict) -> dict:
    units = {target.name: target.unit for target in TARGETS}
    results = {}
    for subject, measured in raw.items():
        figures = {}
        for name, values in measured["figures"].items():
            figure = summary(values, units[name])
            if figure is None:
                continue
            if name in EXITS:
                figure["stopped first"] = sum(measured["stopped first"][name])
                figure["exit status"] = measured["exit status"][name]
            figures[name] = figure
        results[subject] = figures
    return results


def soak(benchmark: Benchmark, seconds: float, growth_cycles: int) -> dict:
    """The node with short goals, enabled for 4 s and disabled for 1 s in turn for `seconds`, then
    `growth_cycles` quick enable/disable cycles: process figures and log size at the start, after the soak and
    after the cycles, and their growth."""
    log = os.path.join(benchmark.folder, "soak.log")
    short_goals = ("_numPoints:=2", "_gestureDuration:=0.5", "_legRepeatFactor:=1", "_numPointsLeg:=1")
    subject = Subject("soak", benchmark.node_command(*short_goals, "_logFile:=" + log), benchmark.folder)

    def state():
        return dict(process_figures(subject.pid), **{"log bytes": log_bytes(log)})
    subject.call("enabled")  # the start is taken once the node has connected to every controller
    time.sleep(1.0)
    subject.call("disabled")
    time.sleep(1.0)
    start = state()
    deadline = time.monotonic() + seconds
    cycles = 0
    while time.monotonic() < deadline:
        subject.call("enabled")
        time.sleep(min(4.0, max(0.0, deadline - time.monotonic())))
        subject.call("disabled")
        time.sleep(1.0)
        cycles += 1
    after_soak = state()
    for _ in range(growth_cycles):
        subject.call("enabled")
        subject.call("disabled")
    after_cycles = state()
    subject.stop(signal.SIGINT)
    return {"soak seconds": seconds, "soak cycles": cycles, "growth cycles": growth_cycles, "start": start,
            "after soak": after_soak, "soak growth": {key: after_soak[key] - start[key] for key in start},
            "after cycles": after_cycles,
            "cycles growth": {key: after_cycles[key] - after_soak[key] for key in start}}


def soak_table(result: dict) -> str:
    lines = ["soak: %g s of short goals (%d enable/disable cycles), then %d quick enable/disable cycles"
             % (result["soak seconds"], result["soak cycles"], result["growth cycles"]),
             "%-20s %12s %12s %12s %14s %14s" % ("figure", "start", "after soak", "soak growth", "after cycles",
                                                 "cycles growth")]
    for key in result["start"]:
        lines.append("%-20s %12.1f %12.1f %+12.1f %14.1f %+14.1f" % (
            key + (" (MB)" if key == "resident memory" else ""), result["start"][key], result["after soak"][key],
            result["soak growth"][key], result["after cycles"][key], result["cycles growth"][key]))
    return "\n".join(lines)


def markdown(document: dict) -> str:
    """doc/benchmark-latest.md: the figures of every platform in `document` (the JSON's sections), side by side."""
    platforms = list(document)
    rows = {platform: rows_of(document[platform]["figures"]) for platform in platforms}
    lines = ["<!-- Written by `make benchmark` (test/benchmark/benchmark.py). Do not edit: run it again. -->", "",
             "# Latest benchmark", ""]
    for platform in platforms:
        section = document[platform]
        node_python = "the same" if section["node python"] == "rosrun" else section["node python"]
        lines.append("- %s interface: %s, %s cores, Python %s (the node's: %s), %d cycles, %g s CPU windows, %d "
                     "exits per signal" % (platform, section["time"], section["cores"], section.get("python", "?"),
                                           node_python, section["cycles"], section["cpu window"], section["exit runs"]))
    lines += ["", "Each cell: the node's p50 / p90 / max, then the reference node's (ref); met: whether the node "
              "meets the target.", "",
              "| figure | target | " + " | ".join("%s | met" % platform for platform in platforms) + " |",
              "|---|---|" + "---|---|" * len(platforms)]
    for index in range(len(TARGETS)):
        name, _, _, target_cell, _ = rows[platforms[0]][index]
        cells = ["%s%s | %s" % (row[1], "" if row[2] == "-" else "; ref %s" % row[2], row[4])
                 for row in (rows[platform][index] for platform in platforms)]
        lines.append("| %s | %s | %s |" % (name, target_cell, " | ".join(cells)))
    for platform in platforms:
        if "soak" in document[platform]:
            lines += ["", "Growth, %s interface:" % platform, "", "```", soak_table(document[platform]["soak"]), "```"]
    return "\n".join(lines) + "\n"


def main(argv) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--platform", choices=PLATFORMS, default="robot")
    parser.add_argument("--cycles", type=int, default=30, help="enable/disable cycles per subject")
    parser.add_argument("--cpu-window", type=float, default=20.0, help="seconds of each CPU window")
    parser.add_argument("--exit-runs", type=int, default=3, help="exits measured per signal and subject")
    parser.add_argument("--json", default=None, help="file the figures are added to (one section per platform)")
    parser.add_argument("--markdown", default=None,
                        help="file the table of every platform in the JSON (or of this one) is written to")
    parser.add_argument("--soak", type=float, default=0.0, help="seconds of soak with short goals (0: none)")
    parser.add_argument("--growth-cycles", type=int, default=0, help="quick enable/disable cycles after the soak")
    parser.add_argument("--node-python", default=None,
                        help="the interpreter that runs the node (default: the script's own, through rosrun)")
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
        benchmark = Benchmark(arguments.platform, arguments.cycles, arguments.cpu_window, arguments.exit_runs, folder)
        benchmark.node_python = arguments.node_python
        raw = {"node": benchmark.measure("node", benchmark.node_command(), node=True),
               "reference": benchmark.measure("reference", benchmark.reference_command(), node=False)}
        results = results_of(raw)
        print(table(arguments.platform, results))
        section = {"figures": results,
                   "targets": {target.name: target.as_dict() for target in TARGETS},
                   "met": {target.name: verdict(target, results["node"].get(target.name),
                                                results["reference"].get(target.name)) for target in TARGETS},
                   "cycles": arguments.cycles, "cpu window": arguments.cpu_window, "exit runs": arguments.exit_runs,
                   "quiet time": benchmark.quiet_time, "node python": arguments.node_python or "rosrun",
                   "cores": os.cpu_count(), "host": socket.gethostname(),
                   "python": "%d.%d.%d" % sys.version_info[:3],
                   "time": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
        if arguments.soak or arguments.growth_cycles:
            section["soak"] = soak(benchmark, arguments.soak, arguments.growth_cycles)
            print(soak_table(section["soak"]))
        document = {}
        if arguments.json and os.path.exists(arguments.json):
            with open(arguments.json) as stream:
                document = json.load(stream)
        document[arguments.platform] = section
        if arguments.json:
            with open(arguments.json, "w") as stream:
                json.dump(document, stream, indent=1)
            print("figures written to %s" % arguments.json)
        if arguments.markdown:
            with open(arguments.markdown, "w") as stream:
                stream.write(markdown(document))
            print("table written to %s" % arguments.markdown)
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
