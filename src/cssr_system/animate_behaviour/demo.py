"""animateBehaviourDemo: shows animateBehaviour on the simulated Pepper and plots what it did.

rosrun cssr_system animateBehaviourDemo.py [--duration 30] [--platform robot|simulator]
                                           [--behaviour all] [--config FILE] [--output-dir DIR]

Starts a master when none answers on ROS_MASTER_URI, then `roslaunch cssr_system
animateBehaviourDemo.launch` (the simulated Pepper and the node), records /joint_states and the
base heading (odometry), enables the node, prints one line a second (which parts moved in that
second, the base heading), disables it after --duration seconds, records a few seconds more to show
the stop, stops everything it started, and writes into --output-dir:
  animation.json                 the recording (format: cssr_system.animate_behaviour.recording.recording)
  animation.png                  its plot (rosrun cssr_system plotAnimation.py animation.json)
  animateBehaviourLogFile.log    the node's log of this run
  roslaunch.log, roscore.log     the console output of the processes it started
Exit status: 0 when the run completed, 1 when something did not start or answer, 130 on Ctrl-C
(the recording so far is still written and plotted).
"""
import argparse
import ctypes
import math
import os
import re
import signal
import subprocess
import sys
import threading
import time
from typing import Dict, List, Optional, Sequence, Tuple

import numpy

from cssr_system.animate_behaviour.contract import DISABLED, ENABLED, REPLY_SUCCESS, SERVICE_PATH
from cssr_system.animate_behaviour.event_log import LOG_FILE_NAME, ROTATED_SUFFIX
from cssr_system.animate_behaviour.recording.plot import plot_recording
from cssr_system.animate_behaviour.recording.recording import (BASE_LABEL, MOTION_THRESHOLD, Recording,
                                                               bands_from_configuration_file, bands_from_log,
                                                               moving_parts, unwrap_heading, write_recording,
                                                               yaw_from_quaternion)
from cssr_system.pepper.joint_table import PARTS, WHEEL_JOINTS
from cssr_system.pepper.simulated_pepper import PLATFORMS, odometry_topic

PROGRAM = "animateBehaviourDemo"
LAUNCH_FILE = "animateBehaviourDemo.launch"
DEFAULT_DURATION = 30.0  # s enabled
REST_BEFORE = 1.0  # s recorded before enabling: the rest posture
TAIL_AFTER = 3.0  # s recorded after disabling: the return to rest and the stop
STARTUP_TIMEOUT = 40.0  # s for the master, the simulated Pepper and the node to come up
SERVICE_CALL_TIMEOUT = 5.0  # s; the node answers within 100 ms, so this only catches a dead node
SIGINT_GRACE = 10.0  # s for roslaunch to stop its nodes after SIGINT (they stop within 1 s)
SIGTERM_GRACE = 3.0  # s after SIGTERM before SIGKILL
PR_SET_CHILD_SUBREAPER = 36  # linux/prctl.h
MOVING_COLUMN_WIDTH = len(", ".join([part.label for part in PARTS.values()] + [BASE_LABEL]))


class DemoError(Exception):
    """Something did not start or answer: one line for the user, exit status 1."""


class Interrupted(Exception):
    """Ctrl-C or SIGTERM."""


def say(text: str) -> None:
    print(text, flush=True)


# ---------------------------------------------------------------------------------------------------
# Processes: everything started here runs in its own session and is stopped, with its descendants.

def become_subreaper() -> None:
    """Orphans of our children (roslaunch starts each node in a session of its own) become our
    children, so none escapes the final sweep even when roslaunch itself dies."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)
    except (OSError, AttributeError):
        pass  # not Linux: the sweep still finds descendants of living processes


def descendants(root: int) -> List[int]:
    """Process ids below `root`, from /proc."""
    children = {}  # type: Dict[int, List[int]]
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % entry, "r") as stat:
                fields = stat.read().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue
        children.setdefault(int(fields[1]), []).append(int(entry))
    found, pending = [], [root]
    while pending:
        for child in children.get(pending.pop(), []):
            found.append(child)
            pending.append(child)
    return found


def alive(pid: int) -> bool:
    try:
        with open("/proc/%d/stat" % pid, "r") as stat:
            return stat.read().rsplit(")", 1)[1].split()[0] != "Z"
    except (OSError, IndexError):
        return False


def reap_zombies(keep: Sequence[int]) -> None:
    """Collect exited orphans handed to us as subreaper (not the Popen children in `keep`)."""
    for pid in descendants(os.getpid()):
        if pid not in keep and not alive(pid):
            try:
                os.waitpid(pid, os.WNOHANG)
            except ChildProcessError:
                pass


def start_process(command: List[str], output_path: str) -> subprocess.Popen:
    with open(output_path, "wb") as output:
        # A session of its own: Ctrl-C in the terminal reaches only us, and we stop it in order.
        return subprocess.Popen(command, stdout=output, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                start_new_session=True)


def stop_process(process: Optional[subprocess.Popen]) -> None:
    """SIGINT to the process group (roslaunch then stops its nodes), then SIGTERM, then SIGKILL,
    each after a grace period; the same for any descendant still running afterwards."""
    if process is None:
        return
    family = descendants(process.pid)
    for signal_number, grace in ((signal.SIGINT, SIGINT_GRACE), (signal.SIGTERM, SIGTERM_GRACE),
                                 (signal.SIGKILL, 1.0)):
        if process.poll() is not None:
            break
        try:
            os.killpg(process.pid, signal_number)
        except ProcessLookupError:
            break
        try:
            process.wait(grace)
        except subprocess.TimeoutExpired:
            pass
    terminate_all(family)


def terminate_all(pids: Sequence[int]) -> None:
    """SIGTERM, then SIGKILL, to those of `pids` still running below us (as subreaper we inherit
    orphans; checking ancestry each time never signals a stranger that reused a process id)."""
    for signal_number in (signal.SIGTERM, signal.SIGKILL):
        ours = set(descendants(os.getpid()))
        pids = [pid for pid in pids if pid in ours and alive(pid)]
        for pid in pids:
            try:
                os.kill(pid, signal_number)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + SIGTERM_GRACE
        while any(alive(pid) for pid in pids) and time.monotonic() < deadline:
            time.sleep(0.05)


# ---------------------------------------------------------------------------------------------------
# Recording.

class Recorder:
    """Keeps every /joint_states message and every heading, with wall-clock times (callbacks run in
    rospy's threads, the printer in the main thread)."""

    def __init__(self, start_epoch: float) -> None:
        self.start_epoch = start_epoch
        self._lock = threading.Lock()
        self.joint_names = ()  # type: Tuple[str, ...]
        self.times = []  # type: List[float]
        self.rows = []  # type: List[List[float]]
        self.heading_times = []  # type: List[float]
        self.headings = []  # type: List[float]
        self.activations = []  # type: List[Tuple[float, str]]

    @staticmethod
    def _stamp(header_stamp) -> float:
        # The simulated Pepper stamps with wall-clock time; a zero stamp means "now".
        stamp = header_stamp.to_sec()
        return stamp if stamp > 0.0 else time.time()

    def on_joint_states(self, message) -> None:
        with self._lock:
            if not self.joint_names:
                self.joint_names = tuple(name for name in message.name if name not in WHEEL_JOINTS)
            value_of = dict(zip(message.name, message.position))
            self.times.append(self._stamp(message.header.stamp) - self.start_epoch)
            self.rows.append([float(value_of.get(name, math.nan)) for name in self.joint_names])

    def on_odometry(self, message) -> None:
        orientation = message.pose.pose.orientation
        yaw = yaw_from_quaternion(orientation.x, orientation.y, orientation.z, orientation.w)
        with self._lock:
            previous = self.headings[-1] if self.headings else None
            self.heading_times.append(self._stamp(message.header.stamp) - self.start_epoch)
            self.headings.append(unwrap_heading(previous, yaw))

    def mark(self, state: str) -> None:
        with self._lock:
            self.activations.append((time.time() - self.start_epoch, state))

    def has_joint_states(self) -> bool:
        with self._lock:
            return bool(self.rows)

    def window(self, seconds: float) -> Tuple[Tuple[str, ...], numpy.ndarray, numpy.ndarray]:
        """(joint names, positions, headings) of the last `seconds`."""
        since = time.time() - self.start_epoch - seconds
        with self._lock:
            rows = [row for moment, row in zip(self.times, self.rows) if moment >= since]
            headings = [value for moment, value in zip(self.heading_times, self.headings) if moment >= since]
            return self.joint_names, numpy.array(rows, dtype=float).reshape(-1, len(self.joint_names)), \
                numpy.array(headings, dtype=float)

    def latest_heading(self) -> Optional[float]:
        with self._lock:
            return self.headings[-1] if self.headings else None

    def recording(self, **extra) -> Recording:
        """What was recorded, time 0 moved to the first sample (the wait for start-up is not shown)."""
        with self._lock:
            times = numpy.array(self.times, dtype=float)
            heading_times = numpy.array(self.heading_times, dtype=float)
            first = min(numpy.min(times) if len(times) else 0.0,
                        numpy.min(heading_times) if len(heading_times) else 0.0)
            order = numpy.argsort(times, kind="stable")
            heading_order = numpy.argsort(heading_times, kind="stable")
            return Recording(
                start_epoch=self.start_epoch + first,
                joint_names=self.joint_names,
                times=times[order] - first,
                positions=numpy.array(self.rows, dtype=float).reshape(-1, len(self.joint_names))[order],
                heading_times=heading_times[heading_order] - first,
                headings=numpy.array(self.headings, dtype=float)[heading_order],
                activations=tuple((moment - first, state) for moment, state in self.activations),
                **extra)


def status_line(seconds: int, state: str, recorder: Recorder) -> str:
    """`  7 s  enabled   moving: right arm, leg, base        base heading +0.12 rad`"""
    names, positions, headings = recorder.window(1.0)
    moving = moving_parts(names, positions)
    if len(headings) >= 2 and numpy.ptp(headings) > MOTION_THRESHOLD:
        moving.append(BASE_LABEL)
    heading = recorder.latest_heading()
    heading_text = "base heading %+.2f rad" % heading if heading is not None else "base heading: no odometry"
    return "%4d s  %-8s  moving: %-*s  %s" % (seconds, state, MOVING_COLUMN_WIDTH,
                                              ", ".join(moving) if moving else "nothing", heading_text)


# ---------------------------------------------------------------------------------------------------
# The run.

def call_activation(state: str) -> None:
    import rospy
    from cssr_system.srv import setActivation
    try:
        rospy.wait_for_service(SERVICE_PATH, timeout=SERVICE_CALL_TIMEOUT)
        reply = rospy.ServiceProxy(SERVICE_PATH, setActivation)(state).success
    except (rospy.ServiceException, rospy.ROSException) as error:
        raise DemoError("%s %s failed: %s" % (SERVICE_PATH, state, error)) from None
    if reply != REPLY_SUCCESS:
        raise DemoError("animateBehaviour refused %r (reply %r); see its log" % (state, reply))


ANSI_ESCAPE = re.compile(r"\x1b(?:\[[0-9;]*[A-Za-z]|\][^\x07]*\x07)")
DIED = re.compile(r"\[(\w+)-\d+\] process has died \[pid \d+, exit code (-?\d+)")


def launch_failure(launch: subprocess.Popen, launch_output: str) -> Optional[str]:
    """Why the launch is broken (a node died, or roslaunch exited), or None while all runs."""
    try:
        with open(launch_output, "r", errors="replace") as output:
            lines = [ANSI_ESCAPE.sub("", line).strip() for line in output]
    except OSError:
        lines = []
    for index, line in enumerate(lines):
        died = DIED.search(line)
        if died:
            node = died.group(1)
            # The node's own last word: its console lines start with its name, rospy's with [ERROR].
            said = [earlier for earlier in lines[:index]
                    if earlier.startswith(node + ":") or earlier.startswith(("[ERROR]", "[FATAL]"))
                    or "Error" in earlier]
            last = said[-1] if said else ""
            detail = " (%s)" % (last if len(last) <= 240 else last[:240] + "...") if last else ""
            return "%s exited with status %s%s" % (node, died.group(2), detail)
    if launch.poll() is not None:
        return "roslaunch exited with status %s" % launch.returncode
    return None


def wait_until(condition, timeout: float, launch: subprocess.Popen, launch_output: str, what: str) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        failure = launch_failure(launch, launch_output)
        if failure is not None:
            raise DemoError("%s did not start: %s; full output: %s" % (what, failure, launch_output))
        if time.monotonic() > deadline:
            raise DemoError("%s did not start within %.0f s (output: %s)" % (what, timeout, launch_output))
        time.sleep(0.1)


def service_available() -> bool:
    import rospy
    try:
        rospy.wait_for_service(SERVICE_PATH, timeout=0.2)
        return True
    except rospy.ROSException:
        return False


def master_online(master_uri: str) -> bool:
    import rosgraph
    return rosgraph.is_master_online(master_uri)


def master_port(master_uri: str) -> int:
    from urllib.parse import urlparse
    return urlparse(master_uri).port or 11311


def run(arguments: argparse.Namespace, processes: Dict[str, subprocess.Popen], recorder_box: List[Recorder]) -> None:
    """Everything up to the end of the recording; `processes` and `recorder_box` let the caller stop
    and save whatever was reached when this raises."""
    output_dir = arguments.output_dir
    master_uri = os.environ.get("ROS_MASTER_URI", "http://localhost:11311")
    if not master_online(master_uri):
        say("%s: starting a master on %s" % (PROGRAM, master_uri))
        processes["roscore"] = start_process(["roscore", "-p", str(master_port(master_uri))],
                                             os.path.join(output_dir, "roscore.log"))
        deadline = time.monotonic() + STARTUP_TIMEOUT
        while not master_online(master_uri):
            if processes["roscore"].poll() is not None or time.monotonic() > deadline:
                raise DemoError("the ROS master did not start on %s (output: %s)"
                                % (master_uri, os.path.join(output_dir, "roscore.log")))
            time.sleep(0.1)
    else:
        say("%s: using the master already running on %s" % (PROGRAM, master_uri))

    log_file = node_log_path(output_dir)
    for stale in (log_file, log_file + ROTATED_SUFFIX):
        if os.path.exists(stale):
            os.remove(stale)  # the plot's bands come from this run's entries only
    command = ["roslaunch", "cssr_system", LAUNCH_FILE, "platform:=" + arguments.platform,
               "behaviour:=" + arguments.behaviour, "log_file:=" + log_file]
    if arguments.config:
        command.append("config_file:=" + arguments.config)
    launch_output = os.path.join(output_dir, "roslaunch.log")
    say("%s: starting the simulated Pepper (%s interface) and animateBehaviour (behaviour %s)"
        % (PROGRAM, arguments.platform, arguments.behaviour))
    processes["roslaunch"] = start_process(command, launch_output)

    import rospy
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import JointState
    rospy.init_node(PROGRAM, anonymous=True, disable_signals=True)
    recorder = Recorder(time.time())
    recorder_box.append(recorder)
    heading_topic = odometry_topic(PLATFORMS[arguments.platform])
    rospy.Subscriber("/joint_states", JointState, recorder.on_joint_states, queue_size=100)
    rospy.Subscriber(heading_topic, Odometry, recorder.on_odometry, queue_size=100)
    wait_until(recorder.has_joint_states, STARTUP_TIMEOUT, processes["roslaunch"], launch_output,
               "the simulated Pepper")
    wait_until(service_available, STARTUP_TIMEOUT, processes["roslaunch"], launch_output,
               "the animateBehaviour node")

    time.sleep(REST_BEFORE)  # a moment at rest first, so the plot shows the start
    say("%s: enabling animateBehaviour for %g s (Ctrl-C stops early)" % (PROGRAM, arguments.duration))
    call_activation(ENABLED)
    recorder.mark(ENABLED)
    enabled_at = time.monotonic()
    # One line a second (its second's motion), the disable at the duration (after that second's line).
    schedule = [(float(second), "line") for second in range(1, int(arguments.duration + TAIL_AFTER) + 1)]
    schedule = sorted(schedule + [(arguments.duration, "disable")], key=lambda item: (item[0], item[1] == "disable"))
    state = ENABLED
    for moment, what in schedule:
        time.sleep(max(0.0, enabled_at + moment - time.monotonic()))
        failure = launch_failure(processes["roslaunch"], launch_output)
        if failure is not None:
            raise DemoError("a node stopped during the demo: %s (output: %s)" % (failure, launch_output))
        if what == "disable":
            call_activation(DISABLED)
            recorder.mark(DISABLED)
            state = DISABLED
            say("%s: disabled after %g s; recording %g s more to show the stop"
                % (PROGRAM, arguments.duration, TAIL_AFTER))
        else:
            say(status_line(int(moment), state, recorder))
    rospy.signal_shutdown("demo finished")


def save(recorder: Recorder, arguments: argparse.Namespace) -> Tuple[str, str]:
    """Write the recording and its plot; bands from the node's log, else from the configuration."""
    from cssr_system.animate_behaviour.event_log import read_log
    log_file = node_log_path(arguments.output_dir)
    bands, heading_bound = {}, None
    if os.path.exists(log_file):
        try:
            bands, heading_bound = bands_from_log(read_log(log_file), since=recorder.start_epoch - 1.0)
        except (OSError, ValueError) as error:
            say("%s: cannot read the node's log (%s); bands from the configuration" % (PROGRAM, error))
    if not bands:
        bands, heading_bound = configured_bands(arguments)
    recording = recorder.recording(
        bands=bands, heading_bound=heading_bound,
        info={"platform": arguments.platform, "behaviour": arguments.behaviour,
              "log_file": log_file, "config_file": arguments.config or "(package default)"},
        heading_topic=odometry_topic(PLATFORMS[arguments.platform]))
    recording_path = write_recording(os.path.join(arguments.output_dir, "animation.json"), recording)
    png_path = plot_recording(recording, os.path.join(arguments.output_dir, "animation.png"))
    return recording_path, png_path


def configured_bands(arguments: argparse.Namespace):
    """Bands and heading bound of the demo's configuration, for the plot; none when it is invalid."""
    from cssr_system.animate_behaviour.configuration import shipped_configuration_path
    try:
        return bands_from_configuration_file(arguments.config or shipped_configuration_path(),
                                             {"platform": arguments.platform, "behaviour": arguments.behaviour})
    except ValueError as error:
        say("%s: no bands in the plot: %s" % (PROGRAM, error))
        return {}, None


def parse_arguments(argv: Sequence[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="animateBehaviourDemo.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("--duration", type=float,
                        default=float(os.environ.get("DEMO_DURATION") or DEFAULT_DURATION),
                        help="seconds the node stays enabled (default $DEMO_DURATION or %g)" % DEFAULT_DURATION)
    parser.add_argument("--platform", choices=sorted(PLATFORMS), default=os.environ.get("DEMO_PLATFORM") or "robot",
                        help="interface of the simulated Pepper: robot (/pepper_dcm, with hands; default "
                             "$DEMO_PLATFORM or robot) or simulator (/pepper, no hands)")
    parser.add_argument("--behaviour", default="all", help="body, hands, rotation, all or a comma list")
    parser.add_argument("--config", help="configuration file of the node (default: the package's)")
    parser.add_argument("--output-dir", default=None,
                        help="where the recording, plot and logs go (default $ROS_HOME/animateBehaviourDemo)")
    arguments = parser.parse_args([argument for argument in argv if not argument.startswith("__")])
    if not arguments.duration > 0:
        parser.error("--duration must be a positive number of seconds")
    if arguments.output_dir is None:
        ros_home = os.environ.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
        arguments.output_dir = os.path.join(ros_home, PROGRAM)
    arguments.output_dir = os.path.abspath(arguments.output_dir)
    if arguments.config:
        arguments.config = os.path.abspath(arguments.config)
    return arguments


def node_log_path(output_dir: str) -> str:
    return os.path.join(output_dir, LOG_FILE_NAME)


def main(argv: Sequence[str]) -> int:
    arguments = parse_arguments(argv)
    try:
        os.makedirs(arguments.output_dir, exist_ok=True)
    except OSError as error:
        say("%s: error: cannot create the output folder %s: %s" % (PROGRAM, arguments.output_dir,
                                                                   error.strerror or error))
        return 1
    become_subreaper()

    def interrupt(signal_number, frame):
        raise Interrupted()
    signal.signal(signal.SIGINT, interrupt)
    signal.signal(signal.SIGTERM, interrupt)

    processes = {}  # type: Dict[str, subprocess.Popen]
    recorder_box = []  # type: List[Recorder]
    status = 0
    try:
        run(arguments, processes, recorder_box)
    except DemoError as error:
        say("%s: error: %s" % (PROGRAM, error))
        status = 1
    except OSError as error:  # a file of the run could not be written or removed
        say("%s: error: %s" % (PROGRAM, error))
        status = 1
    except Interrupted:
        say("%s: interrupted; disabling and stopping" % PROGRAM)
        status = 130
    finally:
        # A second Ctrl-C must not cut the clean-up short: it is bounded by the grace periods.
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        if status == 130 and "rospy" in sys.modules and sys.modules["rospy"].core.is_initialized():
            try:
                call_activation(DISABLED)  # leave the robot as `disabled` does before stopping
                if recorder_box:
                    recorder_box[0].mark(DISABLED)
            except Exception:  # noqa: BLE001 - the node may be gone; stopping it is what matters
                pass
        shutdown_rospy()
        stop_process(processes.get("roslaunch"))
        stop_process(processes.get("roscore"))
        terminate_all(descendants(os.getpid()))
        reap_zombies([])
    if recorder_box and recorder_box[0].has_joint_states() and status != 1:
        try:
            recording_path, png_path = save(recorder_box[0], arguments)
        except OSError as error:
            say("%s: error: cannot write the recording or the plot: %s" % (PROGRAM, error))
            return 1
        say("%s: recording %s" % (PROGRAM, recording_path))
        say("%s: node log  %s" % (PROGRAM, node_log_path(arguments.output_dir)))
        say("%s: plot      %s" % (PROGRAM, png_path))
    return status


def shutdown_rospy() -> None:
    if "rospy" in sys.modules:
        import rospy
        if not rospy.is_shutdown():
            rospy.signal_shutdown("demo finished")
