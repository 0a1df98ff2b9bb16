"""The ROS 2 tests' programs, each a process of its own on the test's domain, found on this machine only."""
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Sequence

SRC = Path(__file__).resolve().parents[2] / "src"


def environment(domain: int) -> dict:
    values = dict(os.environ, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
                  PYTHONUNBUFFERED="1")
    values["PYTHONPATH"] = os.pathsep.join(filter(None, (str(SRC), os.environ.get("PYTHONPATH"))))
    return values


def start_program(module: str, domain: int, ros_arguments: Sequence[str]) -> subprocess.Popen:
    """`python -m module --ros-args <ros_arguments>` (e.g. "-r", "__ns:=/robot1", "-p", "platform:=robot")."""
    return subprocess.Popen([sys.executable, "-m", module, "--ros-args", *ros_arguments], env=environment(domain),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def stop_program(process: subprocess.Popen) -> int:
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
    try:
        return process.wait(15.0)
    except subprocess.TimeoutExpired:
        process.kill()
        return process.wait()


def wait_until(condition, timeout: float, period: float = 0.02) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(period)
    return bool(condition())


def fail_on_error(where: str, error: Exception) -> None:
    """An ExecutorThread's report of an error in the work handed to it: in a test, the error itself, which ends the
    executor (the tests check that it still runs)."""
    raise error


def on_executor(node, request, timeout: float = 5.0):
    """The future of an action client's request (`request()`: a send_goal_async, get_result_async or cancel_goal_async
    call) made on the thread that spins `node`. rclpy's action client records a request only after sending it, so an
    answer that the spinning thread takes first would be dropped and the future never done (ros2/rclpy#1123)."""
    task = node.executor.create_task(request)
    assert wait_until(task.done, timeout), "the executor did not run the request"
    return task.result()
