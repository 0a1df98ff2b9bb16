"""What `make benchmark` does to each subject (the node, then the reference), on either front-end. Pure Python: the
ROS I/O is a rig's (benchmark.py: rospy, benchmark_ros2.py: rclpy), which gives:

  rig.parts: the part keys of the platform; rig.quiet_time: the node's yieldQuietTime
  rig.node_command(settings), rig.reference_command(settings): the subject's command line, with `settings` (the
      configuration keys the busy configuration changes, or none)
  rig.start(label, command) -> a subject: .pid (its process, as the subject itself gives it or as started),
      .activate(state) (setActivation, returns on the reply), .set_enabled(data) (the SetBool service),
      .stop(signal_number) -> (seconds to the exit, status)
  rig.clear(): forgets what the wire carried; rig.goals(since), rig.stops(since): part key -> arrival of the
      subject's first goal (goal or cancel, for stops) since `since` (monotonic seconds); rig.zero_twists(since)
  rig.connected(): the subject's goals and cancels would be seen (waited for after a start)
  rig.at_rest(): the node's status says disabled, every part idle
  rig.foreign_goal(seconds) -> when another client's goal of `seconds` on the right arm ended (None: no result)
"""
import argparse
import functools
import os
import signal
import socket
import subprocess
import sys
import time

from report import BUSY, CPU_ANIMATING, CPU_BUSY, CPU_DISABLED, COLD_FIRST_GOAL, EXITS, RESUME, ZERO_TWIST
from report import floor_line, met_line, met_of, results_of, soak_table, table, targets, write_outputs

from cssr_system.core.joint_states import REST_DELAY
from cssr_system.soak import processes
from cssr_system.soak.process_figures import cpu_seconds, log_bytes, process_figures

PLATFORMS = ("robot", "simulator")
wait_until = functools.partial(processes.wait_until, period=0.01)


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


def stop_process(process: subprocess.Popen, signal_number: int, timeout: float = 10.0):
    """Seconds from sending `signal_number` to the process's exit (killed after `timeout` s), and its exit status."""
    started = time.monotonic()
    process.send_signal(signal_number)
    try:
        process.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
    return time.monotonic() - started, process.returncode


def stop_left(subjects) -> None:
    """Stops every subject still running (after a failure of the run: nothing the run started outlives it)."""
    for subject in subjects:
        if subject.process.poll() is None:
            stop_process(subject.process, signal.SIGINT)


def sample_process(pid: int, figures: dict) -> None:
    for name, value in process_figures(pid).items():
        figures[name].append(value)


class Measurement:
    def __init__(self, rig, ros: int, cycles: int, cpu_window: float, exit_runs: int) -> None:
        self.rig, self.ros, self.cycles, self.cpu_window, self.exit_runs = rig, ros, cycles, cpu_window, exit_runs

    def _record_every_part(self, arrivals, sent: float, samples: list, timeout: float) -> None:
        """Waits up to `timeout` for `arrivals()` (part key -> arrival) to hold every part, then records the
        last one's delay after `sent`; records nothing when a part never came."""
        wait_until(lambda: set(arrivals()) >= self.rig.parts, timeout)
        found = arrivals()
        if set(found) >= self.rig.parts:
            samples.append(max(found.values()) - sent)

    def _timed(self, call, samples: list) -> float:
        """Calls `call`, records its reply time in `samples`; returns when it was sent."""
        sent = time.monotonic()
        call()
        samples.append(time.monotonic() - sent)
        return sent

    def cycles_of(self, subject, figures: dict) -> None:
        rig = self.rig
        subject.activate("enabled")
        time.sleep(1.0)
        subject.activate("disabled")
        time.sleep(1.0)
        for _ in range(self.cycles):
            rig.clear()
            sent = self._timed(lambda: subject.activate("enabled"), figures["setActivation enabled reply"])
            self._record_every_part(lambda: rig.goals(sent), sent, figures["first goal of every part after enabled"],
                                    2)
            time.sleep(0.4)
            sample_process(subject.pid, figures)
            sent = self._timed(lambda: subject.activate("disabled"), figures["setActivation disabled reply"])
            self._record_every_part(lambda: rig.stops(sent), sent, figures["stop of every part after disabled"], 2)
            zeros = rig.zero_twists(sent)
            if zeros:
                figures[ZERO_TWIST].append(zeros[0] - sent)
            time.sleep(0.4)
            # The next enable starts from rest, as after any disabled spell longer than the return home (the
            # reference has no status: the sleep above is its rest).
            if wait_until(rig.at_rest, 3.0):
                time.sleep(0.2)

    def set_enabled_cycles(self, subject, figures: dict) -> None:
        for _ in range(self.cycles):
            for data, name in ((True, "set_enabled true reply"), (False, "set_enabled false reply")):
                self._timed(lambda: subject.set_enabled(data), figures[name])
                time.sleep(0.3)

    def resume_delay(self, subject, figures: dict) -> None:
        """Another node's 2 s goal on the right arm while the node animates: from its result to the node's next
        goal on that arm, less the quiet time the node waits by design."""
        rig = self.rig
        for _ in range(max(1, self.cycles // 10)):
            subject.activate("enabled")
            time.sleep(1.5)
            ended = rig.foreign_goal(2.0)
            if ended is not None:
                wait_until(lambda: "RArm" in rig.goals(ended), rig.quiet_time + 3)
                resumed = rig.goals(ended).get("RArm")
                if resumed is not None:
                    figures[RESUME].append(resumed - ended - rig.quiet_time)
            subject.activate("disabled")
            time.sleep(0.5)

    def _cold_start(self, label: str, command, figures: dict):
        """The subject started, then enabled 2 s later (its controllers have connected): its first goals."""
        self.rig.clear()
        subject = self.rig.start(label, command)
        wait_until(self.rig.connected, 5)  # its cancels, too, are seen
        time.sleep(2.0)
        sent = time.monotonic()
        subject.activate("enabled")
        self._record_every_part(lambda: self.rig.goals(sent), sent, figures[COLD_FIRST_GOAL], 5)
        time.sleep(0.5)
        return subject

    def exits(self, subject, label: str, command, figures: dict, stopped: dict, statuses: dict) -> None:
        """`exit_runs` times each signal while animating: seconds to the exit, and whether every part that had a
        goal of the subject got it replaced or cancelled on the wire first (a message that arrives at all left
        before the exit). The signal waits, up to 5 s, for every part to have a goal: a part whose controller
        the subject has not connected yet moves nothing and needs no stop."""
        for _ in range(self.exit_runs):
            for signal_number, name in zip((signal.SIGINT, signal.SIGTERM), EXITS):
                if subject is None:
                    subject = self._cold_start(label, command, figures)
                moving = set(self.rig.goals(0.0))
                sent = time.monotonic()
                seconds, status = subject.stop(signal_number)
                subject = None
                figures[name].append(seconds)
                wait_until(lambda: set(self.rig.stops(sent)) >= moving, 1)
                stopped[name].append(bool(moving) and set(self.rig.stops(sent)) >= moving)
                statuses[name].append(status)

    def busy(self, label: str, command, figures: dict) -> None:
        """The CPU while animating in the busy configuration, with the process figures."""
        subject = self.rig.start(label + "-busy", command)
        wait_until(self.rig.connected, 5)
        time.sleep(1.0)
        subject.activate("enabled")
        time.sleep(2.0)
        figures[CPU_BUSY] = cpu_shares(subject.pid, self.cpu_window, figures)
        subject.stop(signal.SIGINT)

    def measure(self, label: str, node: bool) -> dict:
        """Every figure that applies to the subject: lists of raw samples (seconds, %, MB, counts), and per exit
        figure whether the robot was stopped first and the exit status."""
        rig = self.rig
        command = rig.node_command({}) if node else rig.reference_command({})
        figures = {target.name: [] for target in targets(self.ros)}
        stopped = {name: [] for name in EXITS}
        statuses = {name: [] for name in EXITS}
        subject = rig.start(label, command)
        sample_process(subject.pid, figures)
        self.cycles_of(subject, figures)
        self.set_enabled_cycles(subject, figures)
        if node:  # the reference has no yielding; disabled means at rest: the parts are home
            self.resume_delay(subject, figures)
            wait_until(rig.at_rest, 10)
            time.sleep(REST_DELAY)
        time.sleep(1.0)
        figures[CPU_DISABLED] = cpu_shares(subject.pid, self.cpu_window, figures)
        subject.activate("enabled")
        time.sleep(1.0)
        figures[CPU_ANIMATING] = cpu_shares(subject.pid, self.cpu_window, figures)
        self.exits(subject, label, command, figures, stopped, statuses)
        self.busy(label, rig.node_command(BUSY) if node else rig.reference_command(BUSY), figures)
        return {"figures": figures, "stopped first": stopped, "exit status": statuses}


def soak(rig, folder: str, seconds: float, growth_cycles: int) -> dict:
    """The node with short goals, enabled for 4 s and disabled for 1 s in turn for `seconds`, then
    `growth_cycles` quick enable/disable cycles: process figures and log size at the start, after the soak and
    after the cycles, and their growth."""
    log = os.path.join(folder, "soak.log")
    short_goals = {"numPoints": 2, "gestureDuration": 0.5, "legRepeatFactor": 1, "numPointsLeg": 1, "logFile": log}
    subject = rig.start("soak", rig.node_command(short_goals))

    def state():
        return dict(process_figures(subject.pid), **{"log bytes": log_bytes(log)})
    subject.activate("enabled")  # the start is taken once the node has connected to every controller
    time.sleep(1.0)
    subject.activate("disabled")
    time.sleep(1.0)
    start = state()
    deadline = time.monotonic() + seconds
    cycles = 0
    while time.monotonic() < deadline:
        subject.activate("enabled")
        time.sleep(min(4.0, max(0.0, deadline - time.monotonic())))
        subject.activate("disabled")
        time.sleep(1.0)
        cycles += 1
    after_soak = state()
    for _ in range(growth_cycles):
        subject.activate("enabled")
        subject.activate("disabled")
    after_cycles = state()
    subject.stop(signal.SIGINT)
    return {"soak seconds": seconds, "soak cycles": cycles, "growth cycles": growth_cycles, "start": start,
            "after soak": after_soak, "soak growth": {key: after_soak[key] - start[key] for key in start},
            "after cycles": after_cycles,
            "cycles growth": {key: after_cycles[key] - after_soak[key] for key in start}}


def arguments(argv, description: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--platform", choices=PLATFORMS, default="robot")
    parser.add_argument("--cycles", type=int, default=30, help="enable/disable cycles per subject")
    parser.add_argument("--cpu-window", type=float, default=20.0, help="seconds of each CPU window")
    parser.add_argument("--exit-runs", type=int, default=3, help="exits measured per signal and subject")
    parser.add_argument("--json", default=None, help="file the figures are added to (one section per platform)")
    parser.add_argument("--markdown", default=None,
                        help="file whose section of this front-end gets the table of every platform in the JSON")
    parser.add_argument("--soak", type=float, default=0.0, help="seconds of soak with short goals (0: none)")
    parser.add_argument("--growth-cycles", type=int, default=0, help="quick enable/disable cycles after the soak")
    parser.add_argument("--node-python", default=None,
                        help="the interpreter that runs the node (default: the script's own)")
    return parser.parse_args(argv)


def run(rig, ros: int, options: argparse.Namespace, folder: str, node_python: str) -> None:
    """Both subjects measured on `rig`, the table printed, the JSON and the markdown written."""
    measurement = Measurement(rig, ros, options.cycles, options.cpu_window, options.exit_runs)
    raw = {}
    for label in ("node", "reference"):
        try:
            raw[label] = measurement.measure(label, node=label == "node")
        except Exception as error:  # noqa: BLE001 - a subject that stops answering ends the run, with the reason
            raise SystemExit("benchmark: the %s stopped answering (%s: %s); its output, and its log: %s"
                             % (label, type(error).__name__, error, folder)) from error
    results = results_of(raw, ros)
    met = met_of(results, ros)
    print(table(options.platform, results, ros))
    print(met_line(met))
    print(floor_line(results, ros))
    section = {"figures": results, "targets": {target.name: target.as_dict() for target in targets(ros)},
               "met": met, "ros": ros, "busy configuration": BUSY,
               "cycles": options.cycles, "cpu window": options.cpu_window, "exit runs": options.exit_runs,
               "quiet time": rig.quiet_time, "node python": node_python,
               "cores": os.cpu_count(), "host": socket.gethostname(),
               "python": "%d.%d.%d" % sys.version_info[:3], "time": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    if options.soak or options.growth_cycles:
        section["soak"] = soak(rig, folder, options.soak, options.growth_cycles)
        print(soak_table(section["soak"]))
    write_outputs(section, options.platform, ros, options.json, options.markdown)
