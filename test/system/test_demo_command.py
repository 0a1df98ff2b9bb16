"""The README's demo command (tools/demo.sh, i.e. `make demo`) with a short duration: it exits 0,
prints one line a second, leaves a valid PNG and recording, and no process it started survives."""
import os
import socket
import subprocess
import sys
import time

import pytest

REPO_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
DEMO_DURATION = 5


def workspace_sourced():
    """Whether ROS_PACKAGE_PATH holds cssr_system (the workspace's devel/setup.bash was sourced)."""
    for folder in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep):
        if folder and (os.path.isfile(os.path.join(folder, "cssr_system", "package.xml"))
                       or (os.path.basename(os.path.normpath(folder)) == "cssr_system"
                           and os.path.isfile(os.path.join(folder, "package.xml")))):
            return True
    return False


pytestmark = pytest.mark.skipif(
    not workspace_sourced(),
    reason="the catkin workspace is not sourced (ROS_PACKAGE_PATH lacks cssr_system): "
           "run `source .workspace/devel/setup.bash` after tools/build.sh, or the test command")


def free_port():
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


def processes_with(marker):
    """(pid, command line) of every process whose environment holds `marker`, but this one."""
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            with open("/proc/%s/environ" % entry, "rb") as environment:
                if marker.encode() not in environment.read():
                    continue
            with open("/proc/%s/cmdline" % entry, "rb") as command:
                found.append((int(entry), command.read().replace(b"\0", b" ").decode(errors="replace")))
        except OSError:
            continue  # gone meanwhile, or not ours
    return found


def test_demo_command_runs_plots_and_leaves_nothing_behind(tmp_path):
    master_uri = "http://localhost:%d" % free_port()
    environment = dict(os.environ, DEMO_DURATION=str(DEMO_DURATION), DEMO_OUTPUT_DIR=str(tmp_path),
                       DEMO_MASTER_URI=master_uri)
    started = time.monotonic()
    result = subprocess.run(["bash", os.path.join(REPO_DIR, "tools", "demo.sh")], cwd=REPO_DIR, env=environment,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                            timeout=240)
    elapsed = time.monotonic() - started
    output = result.stdout
    sys.stdout.write(output)  # shown by pytest when the test fails
    assert result.returncode == 0, "demo exited %d after %.0f s" % (result.returncode, elapsed)

    # The ROS_MASTER_URI is unique to this run, and every process of it inherits it.
    deadline = time.monotonic() + 3.0
    survivors = processes_with("ROS_MASTER_URI=" + master_uri)
    while survivors and time.monotonic() < deadline:
        time.sleep(0.2)
        survivors = processes_with("ROS_MASTER_URI=" + master_uri)
    assert survivors == [], "processes left running by the demo: %s" % survivors

    status_lines = [line for line in output.splitlines() if " s  enabled " in line or " s  disabled " in line]
    assert len(status_lines) >= DEMO_DURATION, "expected one line a second:\n" + output
    assert any("arm" in line for line in status_lines if " enabled " in line), output
    # Joints stop within the tail; the base may still be finishing its turn back to the start heading.
    still_moving = status_lines[-1].split("moving:")[1].split("base heading")[0]
    assert not any(part in still_moving for part in ("arm", "hand", "leg")), \
        "the joints did not stop after disable:\n" + output

    png_path = os.path.join(str(tmp_path), "animation.png")
    assert "plot      " + png_path in output
    with open(png_path, "rb") as image:
        content = image.read()
    assert content.startswith(PNG_SIGNATURE)
    assert len(content) > 30 * 1024

    from cssr_system.animate_behaviour.recording.recording import read_recording  # after the skip: needs the workspace
    recording = read_recording(os.path.join(str(tmp_path), "animation.json"))
    assert [state for _, state in recording.activations] == ["enabled", "disabled"]
    assert recording.bands, "no joint bands found in the node's log"
    assert len(recording.times) > 50 * DEMO_DURATION * 0.8  # /joint_states at 50 Hz
