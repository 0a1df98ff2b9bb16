"""The ROS 2 packages as their users build them (doc/ros2.md: "Build in a colcon workspace"): `colcon build
--base-paths <repository>/ros2` in a workspace of its own (tools/ros2/colcon_build.sh), then the simulated Pepper and
the node started from that install's programs, in the environment that the venv's activate and the install's
setup.bash make from an empty one: nothing of tools/ros2/setup.sh's cmake install, nothing of src/. The node starts,
finds its controllers, answers setActivation as on ROS 1, moves the arm, and exits 0 at SIGINT.

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2/test_colcon_install_ros2.py -q
"""
import os
import subprocess
import threading
from pathlib import Path

import pytest

rclpy = pytest.importorskip("rclpy")
pytest.importorskip("cssr_system_interfaces.srv")

from cssr_system_interfaces.srv import SetActivation  # noqa: E402 (after the skips)
from rclpy.context import Context  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402

from cssr_system.animate_behaviour import contract  # noqa: E402
from cssr_system.animate_behaviour.event_log import read_log  # noqa: E402

from domains import claim_domain  # noqa: E402
from processes import stop_program, wait_until  # noqa: E402

REPO_DIR = Path(__file__).resolve().parents[2]
BUILD_TIMEOUT = 1200  # s: a first build of the packages takes about a minute on 2 idle cores
START_TIMEOUT = 20.0  # s; a node starts in 1-2 s, but the machine may be busy
SIMULATOR_PARTS = {"RArm", "LArm", "Leg"}  # the simulator platform has no hand controllers


@pytest.fixture(scope="module")
def colcon_install():
    """The colcon workspace's install/, built (or brought up to date) now."""
    try:
        build = subprocess.run(["bash", str(REPO_DIR / "tools" / "ros2" / "colcon_build.sh")], cwd=str(REPO_DIR),
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                               timeout=BUILD_TIMEOUT)
    except subprocess.TimeoutExpired:
        pytest.fail("colcon build did not finish within %d s" % BUILD_TIMEOUT)
    assert build.returncode == 0, "colcon build failed:\n" + "\n".join(build.stdout.splitlines()[-40:])
    return Path(os.environ["ROS2_DIR"]) / "colcon" / "install"


@pytest.fixture(scope="module")
def install_environment(colcon_install):
    """The environment of a user's shell after doc/ros2.md's lines (tools/ros2/colcon_build.sh's): the venv activated,
    with what /opt/ros/<distribution>/setup.bash would set (the ament prefix, ROS_VERSION, ROS_DISTRO), then the
    install's setup.bash sourced."""
    lines = ('source "$1/bin/activate" && export AMENT_PREFIX_PATH="$VIRTUAL_ENV" ROS_VERSION=2 ROS_DISTRO="$3" && '
             'source "$2/setup.bash" && env -0')
    listing = subprocess.run(["env", "-i", "HOME=%s" % os.environ["HOME"], "PATH=/usr/local/bin:/usr/bin:/bin",
                              "bash", "-c", lines, "_", os.environ["ROS2_VENV"], str(colcon_install),
                              os.environ["CSSR_ROS2_DISTRO"]], stdout=subprocess.PIPE, check=True).stdout
    return dict(entry.split("=", 1) for entry in listing.decode().split("\0") if "=" in entry)


def test_the_install_environment_finds_every_package_in_the_colcon_install(colcon_install, install_environment):
    # Every package of ros2/ (the program's and the interface packages) is a Python package of the same name.
    modules = sorted(folder.name for folder in (REPO_DIR / "ros2").iterdir() if (folder / "package.xml").is_file())
    assert {"cssr_system", "cssr_system_interfaces", "control_msgs", "naoqi_bridge_msgs"} <= set(modules)
    found = subprocess.run(["python3", "-c", "import importlib, sys\nfor name in sys.argv[1:]: "
                            "print(importlib.import_module(name).__path__[0])", *modules],
                           env=install_environment, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert found.returncode == 0, found.stderr
    for module, path in zip(modules, found.stdout.split()):
        assert path.startswith("%s/%s/" % (colcon_install, module)), (module, path)
    share = colcon_install / "cssr_system" / "share" / "cssr_system"
    for installed in ("launch/animate_behaviour.launch.py", "config/animateBehaviourConfiguration.ini",
                      "data/simulatorTopics.dat", "package.xml"):
        assert (share / installed).is_file(), "%s: `ros2 launch` and the node find it there" % installed
    prefixes = install_environment["AMENT_PREFIX_PATH"].split(":")
    assert sorted(prefixes) == sorted(["%s/%s" % (colcon_install, module) for module in modules]
                                      + [os.environ["ROS2_VENV"]]), "the install's packages and the venv"


class Client:
    """A test node of its own context, spun on a thread: setActivation and /joint_states."""

    def __init__(self, domain: int) -> None:
        self.context = Context()
        rclpy.init(context=self.context, domain_id=domain)
        self.node = Node("colcon_install_test_client", context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.joint_states = []
        self.node.create_subscription(JointState, "/joint_states", self.joint_states.append, 10)
        self.set_activation = self.node.create_client(SetActivation, "/animateBehaviour/setActivation")
        self.thread = threading.Thread(target=self.executor.spin, daemon=True)
        self.thread.start()

    def activate(self, state: str) -> str:
        future = self.set_activation.call_async(SetActivation.Request(state=state))
        assert wait_until(future.done, 5.0), "no reply from setActivation"
        return future.result().success

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.shutdown(context=self.context)


def start_installed(install: Path, environment: dict, program: str, *parameters: str) -> subprocess.Popen:
    """`ros2 run cssr_system <program>` as the install holds it (there is no `ros2` command here)."""
    arguments = [word for parameter in parameters for word in ("-p", parameter)]
    return subprocess.Popen([str(install / "cssr_system" / "lib" / "cssr_system" / program), "--ros-args",
                             *arguments], env=environment, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_the_node_of_the_colcon_install_answers_set_activation_moves_and_exits_0_at_sigint(
        colcon_install, install_environment, tmp_path):
    domain = claim_domain()
    environment = dict(install_environment, ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
                       PYTHONUNBUFFERED="1", ROS_LOG_DIR=str(tmp_path / "ros_log"))
    log_file = tmp_path / "animateBehaviour.log"
    simulator = start_installed(colcon_install, environment, "simulated_pepper", "platform:=simulator")
    node = start_installed(colcon_install, environment, "animate_behaviour", "platform:=simulator",
                           "logFile:=%s" % log_file)
    client = Client(domain)
    try:
        def connected():
            entries = read_log(str(log_file)) if log_file.exists() else []
            return {entry.fields["part"] for entry in entries if entry.event == contract.CONTROLLER_CONNECTED}

        assert client.set_activation.wait_for_service(timeout_sec=START_TIMEOUT), \
            "the node did not start: %s" % ("still running" if node.poll() is None else node.communicate()[1])
        assert wait_until(lambda: connected() >= SIMULATOR_PARTS, START_TIMEOUT), "its controllers are found"
        assert client.activate("enabled") == contract.REPLY_SUCCESS
        moved_from = len(client.joint_states)
        assert wait_until(lambda: len(client.joint_states) > moved_from + 100, 10.0), "/joint_states flows"
        arm = [dict(zip(message.name, message.position))["RShoulderPitch"]
               for message in client.joint_states[moved_from:]]
        assert max(arm) - min(arm) > 0.01, "the arm moves"
    finally:
        client.close()
        status = stop_program(node)
        stop_program(simulator)
    assert status == 0, "SIGINT: the node stops the robot and exits 0:\n" + node.communicate()[1][-2000:]
    assert any(entry.event == contract.NODE_STOPPED for entry in read_log(str(log_file))), "node_stopped in the log"
