"""The processes of a soak (the simulated Pepper, the node), each with its output in a file of the run's folder, and
what the front-ends' drivers share: the node's busy configuration, the command line and the run's JSON. Pure
Python: no ROS."""
import argparse
import os
import signal
import subprocess
import sys
import time
from socket import socket as tcp_socket
from typing import Callable, List, Optional, Sequence

from cssr_system.animate_behaviour.configuration import load_configuration, shipped_configuration_path
from cssr_system.animate_behaviour.configuration import topic_file_path
from cssr_system.animate_behaviour.topics import WHEELS_KEY, load_topic_map
from cssr_system.soak.report import text
from cssr_system.soak.run import SoakRun, write_json
from cssr_system.soak.schedule import RESTART_PERIOD, churn_schedule

# The busy configuration: a new goal on every part about every second, on the robot's interfaces (hands included).
PLATFORM = "robot"
# The simulated Pepper reports the commanded state (as in `make demo`): another node's gesture, which ends at rest,
# succeeds, so every goal has one expected end.
SIMULATOR = {"platform": PLATFORM, "velocity_report": "commanded"}
BUSY = {"behaviour": "all", "gestureDuration": 0.5, "numPoints": 2, "legRepeatFactor": 1, "numPointsLeg": 1}
STOP_TIMEOUT = 10.0  # s for a process to exit after SIGINT before it is killed
PROBE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "tools", "soak_probe")
UNHEARD_BASE = "soak_unheard_base"  # where the simulated Pepper listens instead of the base's topic
HEAP_FILE = "heap.json"  # in the run's folder: what the node's allocators hold (tools/soak_probe)


def heap_file(folder: str) -> str:
    return os.path.join(folder, HEAP_FILE)


def robot_topics() -> dict:
    """The robot's topics as the node names them (relative: in its namespace), by key of the topic file."""
    configuration = load_configuration(shipped_configuration_path(), {"platform": PLATFORM})
    return dict(load_topic_map(topic_file_path(configuration)).topics)


def base_remapping() -> str:
    """Keeps the simulated Pepper's listener off the base's topic (a remapping, relative to its namespace): the
    run's own listener (driver.base_listener) leaves and comes back on its own."""
    return "%s:=%s" % (robot_topics()[WHEELS_KEY], UNHEARD_BASE)


def node_environment(folder: str) -> dict:
    """The node's environment: this process's, with the soak's probe (tools/soak_probe) writing what its allocators
    hold to heap_file(folder), and with CSSR_TRACEMALLOC=1 its allocations traced and snapshots written to
    `folder`."""
    python_path = os.pathsep.join(filter(None, (os.path.abspath(PROBE), os.environ.get("PYTHONPATH"))))
    environment = dict(os.environ, PYTHONPATH=python_path, CSSR_SOAK_HEAP_FILE=heap_file(folder))
    if os.environ.get("CSSR_TRACEMALLOC", "0") == "1":
        environment["CSSR_TRACEMALLOC_DIR"] = folder
    return environment


class Program:
    """A process of the run, its output (stdout and stderr) appended to `output_file`."""

    def __init__(self, command: Sequence[str], output_file: str, environment: Optional[dict] = None) -> None:
        self.command, self.output_file, self.environment = list(command), output_file, environment
        self.process: Optional[subprocess.Popen] = None

    def start(self) -> "Program":
        with open(self.output_file, "a") as output:
            self.process = subprocess.Popen(self.command, stdout=output, stderr=subprocess.STDOUT,
                                            env=self.environment)
        return self

    def running(self) -> bool:
        return self.process is not None and self.process.poll() is None

    def stop(self) -> Optional[int]:
        """SIGINT, then the exit status (killed after STOP_TIMEOUT s: None)."""
        if self.process is None:
            return None
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
        try:
            return self.process.wait(STOP_TIMEOUT)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
            return None


def wait_until(condition: Callable[[], bool], timeout: float, period: float = 0.1) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(period)
    return bool(condition())


def free_port() -> int:
    with tcp_socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


def arguments(argv: List[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description="make soak: the node under compressed use (doc/soak.md)")
    parser.add_argument("--minutes", type=float, default=60.0, help="minutes judged, after the warm-up")
    parser.add_argument("--warm-up", type=float, default=10.0, help="minutes of warm-up, not judged")
    parser.add_argument("--seed", type=int, default=1, help="the churn's random seed")
    parser.add_argument("--restart-minutes", type=float, default=RESTART_PERIOD / 60.0,
                        help="minutes between restarts of the simulated Pepper (the first at half of it)")
    parser.add_argument("--sim-clock", type=int, choices=(0, 1), default=1,
                        help="ROS 1: 1 (default) adds a second robot on a simulated clock from mid-warm-up")
    parser.add_argument("--folder", required=True, help="the run's folder: output of every process, the log")
    parser.add_argument("--json", required=True, help="the run's result")
    return parser.parse_args(argv)


def soak(driver, options: argparse.Namespace, ros: str, start: float = 0.0, json: Optional[str] = None,
         about: str = "") -> int:
    """The run on `driver` (started), from `start` s into the soak to its end, with the soak's warm-up; its result
    in `json` (default options.json), the figures beside their targets printed. `about`: what sets this run apart,
    for its configuration line."""
    seconds, warm_up = 60.0 * (options.minutes + options.warm_up) - start, 60.0 * options.warm_up
    json = json or options.json
    document = {"ros": ros, "configuration": "platform %s, %s%s" % (
        PLATFORM, ", ".join("%s %s" % item for item in BUSY.items()), about), "cores": os.cpu_count(),
        "python": "%d.%d.%d" % sys.version_info[:3]}

    def checkpoint(result: dict) -> None:
        write_json(json, dict(result, **document))
    run = SoakRun(driver, churn_schedule(seconds, options.seed, 60.0 * options.restart_minutes), seconds, warm_up,
                  progress=lambda line: print(("ROS %s: " % ros if about else "") + line, flush=True),
                  checkpoint=checkpoint)
    result = dict(run.run(), **document)
    write_json(json, result)
    print(text(result), flush=True)
    return 0
