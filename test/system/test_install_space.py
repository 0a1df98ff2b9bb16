"""The package works from a `catkin_make install` space, as a user who installs it runs it: with only
`<install>/setup.bash` sourced (no devel space, no source tree on the paths), the demo's launch file starts the
simulated Pepper, the node, its recorder and its driver from the install space, the node animates (its goals reach
the controllers: the recording's commanded lines come from them), and plotAnimation.py plots that recording with the
shipped configuration of the install space. Every file is found through cssr_system.package_files."""
import json
import os
import socket
import subprocess

import pytest

REPO_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SHELL_SETUP = "source tools/common.sh && printf %s \"$WORKSPACE_DIR\""


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


@pytest.fixture(scope="module")
def install_space():
    workspace = subprocess.check_output(["bash", "-c", SHELL_SETUP], cwd=REPO_DIR, universal_newlines=True)
    build = subprocess.run(["catkin_make", "-C", workspace, "-DPYTHON_EXECUTABLE=/usr/bin/python3", "install"],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=600)
    assert build.returncode == 0, build.stdout[-3000:]
    return os.path.join(workspace, "install")


def run_installed(install: str, command: str, home: str, timeout: float) -> subprocess.CompletedProcess:
    """`command` in a clean environment where only the install space is sourced, on a master of its own."""
    environment = {"PATH": "/usr/bin:/bin", "HOME": os.environ.get("HOME", "/root"), "PYENV_VERSION": "system",
                   "ROS_HOME": home, "ROS_HOSTNAME": "localhost",
                   "ROS_MASTER_URI": "http://localhost:%d" % free_port()}
    script = "cd %s && source %s/setup.bash && %s" % (home, install, command)
    return subprocess.run(["bash", "-c", script], env=environment, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=timeout)


def test_demo_node_and_plot_run_from_the_install_space(install_space, tmp_path):
    home = str(tmp_path)
    where = run_installed(install_space, "python3 -c 'import cssr_system.package_files as f; print(f.package_dir())'"
                                         " && rospack find cssr_system", home, 30)
    assert where.returncode == 0, where.stdout
    share = os.path.join(install_space, "share", "cssr_system")
    assert where.stdout.split() == [share, share], "the package's files come from the install space"
    assert REPO_DIR not in where.stdout

    output = os.path.join(home, "demo")
    demo = run_installed(install_space, "roslaunch cssr_system animateBehaviourDemo.launch duration:=3 "
                                        "output_dir:=%s log_file:=%s/node.log" % (output, home), home, 120)
    assert demo.returncode == 0, demo.stdout[-3000:]
    assert "Traceback" not in demo.stdout, demo.stdout[-3000:]
    with open(os.path.join(output, "animation.json"), encoding="utf-8") as stream:
        recording = json.load(stream)
    assert recording["commanded"], "the node's goals reached the controllers"
    assert [mark["state"] for mark in recording["activations"]] == ["enabled", "disabled"]
    with open(os.path.join(home, "node.log"), encoding="utf-8") as stream:
        log = stream.read()
    assert "goal_sent" in log and '"reply": "1"' in log

    config = os.path.join(share, "config", "animateBehaviourConfiguration.ini")
    plot = os.path.join(home, "again.png")
    replot = run_installed(install_space, "rosrun cssr_system plotAnimation.py %s/animation.json --config %s -o %s"
                           % (output, config, plot), home, 120)
    assert replot.returncode == 0, replot.stdout
    assert replot.stdout.strip().splitlines()[-1] == plot
    with open(plot, "rb") as stream:
        assert stream.read(8) == b"\x89PNG\r\n\x1a\n"
