"""The README's demo command (tools/demo.sh, i.e. `make demo`) with short durations: a plain run, a run with
GESTURE=1 and CONVERSATION=1 (the gesture while the robot speaks) and a run stopped with Ctrl-C. Each leaves a valid
PNG and recording, a completed one Pepper's figure (an animated GIF) beside them, and no process it started
survives."""
import os
import re
import signal
import socket
import subprocess
import sys
import time

import numpy
import pytest

REPO_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
DEMO_DURATION = 4
GESTURE_STATES = ("SUCCEEDED", "PREEMPTED", "ABORTED", "REJECTED", "RECALLED", "LOST")
# The conversation (src/cssr_system/demo/speech.py): from 2 s after the enable, listening 6 s, speaking 8 s; 1 s of
# idle motion after it. Its gesture comes half-way, at 8.5 s, while the robot speaks.
CONVERSATION_DURATION = 17


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
           "run `source tools/common.sh && source_workspace` after tools/build.sh, or the test command")


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


def run_demo(output_dir, interrupt_after=None, **options):
    """Run tools/demo.sh in a process group of its own with DEMO_<option> settings; with `interrupt_after`,
    send SIGINT to the group (as Ctrl-C in a terminal does) after the first output line holding that text.
    Returns (exit status, output, seconds from the interrupt to the exit); fails when a process of the run
    survives it (every process of the run inherits its unique ROS_MASTER_URI)."""
    master_uri = "http://localhost:%d" % free_port()
    environment = dict(os.environ, DEMO_OUTPUT_DIR=str(output_dir), DEMO_MASTER_URI=master_uri,
                       **{"DEMO_" + key: str(value) for key, value in options.items()})
    return run_in_process_group(["bash", os.path.join(REPO_DIR, "tools", "demo.sh")], environment, interrupt_after,
                                240, "ROS_MASTER_URI=" + master_uri)


def run_in_process_group(command, environment, interrupt_after, timeout, marker):
    """Runs `command` in a process group of its own, as from a terminal; with `interrupt_after`, SIGINT to the group
    after the first output line holding that text. Returns (exit status, output, seconds from the interrupt to the
    exit); fails when a process holding `marker` in its environment survives the run."""
    # As from a terminal: SIGINT not ignored, even where this test runs in the background of a shell without job
    # control (which starts it with SIGINT ignored, and a shell cannot trap a signal ignored when it starts).
    demo = subprocess.Popen(command, cwd=REPO_DIR, env=environment, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    lines, interrupted_at = [], None
    deadline = time.monotonic() + timeout
    try:
        for line in demo.stdout:
            lines.append(line)
            if interrupt_after is not None and interrupted_at is None and interrupt_after in line:
                os.killpg(demo.pid, signal.SIGINT)
                interrupted_at = time.monotonic()
            if time.monotonic() > deadline:
                break
        status = demo.wait(timeout=max(1.0, deadline - time.monotonic()))
    finally:
        if demo.poll() is None:
            os.killpg(demo.pid, signal.SIGKILL)
    stop_time = time.monotonic() - interrupted_at if interrupted_at is not None else None
    output = "".join(lines)
    sys.stdout.write(output)  # shown by pytest when the test fails
    settle = time.monotonic() + 3.0
    survivors = processes_with(marker)
    while survivors and time.monotonic() < settle:
        time.sleep(0.2)
        survivors = processes_with(marker)
    assert survivors == [], "processes left running by the demo: %s" % survivors
    return status, output, stop_time


def status_lines(output):
    return [line for line in output.splitlines() if " s  enabled " in line or " s  disabled " in line]


def check_figure(lines, gif_path):
    """Pepper's figure, the last step of a completed demo: an animated GIF at `gif_path`, named among `lines`."""
    assert gif_path in lines, "the figure's path is not printed after the plot's:\n" + "\n".join(lines)
    from PIL import Image  # the figure's own dependency (doc/figure.md)
    with Image.open(gif_path) as image:
        assert image.format == "GIF" and image.n_frames > 10


def check_plot_and_recording(output, output_dir, figure=True):
    """The plot, the recording and (`figure`: the demo completed) the figure, printed in that order at the end."""
    png_path = os.path.join(str(output_dir), "animation.png")
    lines = output.splitlines()
    plotted = [index for index, line in enumerate(lines) if "plot      " + png_path in line]
    assert plotted, "the plot's path is not printed:\n" + output
    if figure:
        check_figure(lines[plotted[-1] + 1:], os.path.join(str(output_dir), "animation.gif"))
    else:
        assert plotted[-1] == len(lines) - 1, "the plot's path is not the last line:\n" + output
    with open(png_path, "rb") as image:
        content = image.read()
    assert content.startswith(PNG_SIGNATURE)
    assert len(content) > 30 * 1024
    from cssr_system.recording.recording import read_recording  # after the skip: needs the workspace
    return read_recording(os.path.join(str(output_dir), "animation.json"))


def test_demo_runs_records_plots_and_leaves_nothing_behind(tmp_path):
    status, output, _ = run_demo(tmp_path, DURATION=DEMO_DURATION)
    assert status == 0, output

    lines = status_lines(output)
    assert len(lines) >= DEMO_DURATION + 2, "expected one line a second:\n" + output
    assert any("arm" in line for line in lines if " enabled " in line), output
    # Joints stop within the tail; the base may still be finishing its turn back to the start heading.
    still_moving = lines[-1].split("moving:")[1].split("base heading")[0]
    assert not any(part in still_moving for part in ("arm", "hand", "leg")), \
        "the joints did not stop after disable:\n" + output

    recording = check_plot_and_recording(output, tmp_path)
    assert [state for _, state in recording.activations] == ["enabled", "disabled"]
    enabled_at, disabled_at = [moment for moment, _ in recording.activations]
    assert DEMO_DURATION - 0.5 < disabled_at - enabled_at < DEMO_DURATION + 1.0
    assert recording.bands, "no joint bands found in the node's log"
    assert len(recording.times) > 50 * DEMO_DURATION * 0.8  # /joint_states at 50 Hz
    assert recording.marks == ()  # no other node sent goals
    commanded = recording.commanded
    assert commanded is not None and commanded.source == "/animateBehaviour"
    assert "RShoulderPitch" in commanded.joint_names
    # The log stamps the enable when the node replies, just after it sent its first goals.
    before = commanded.times < enabled_at - 0.5
    assert numpy.any(before) and numpy.all(numpy.isnan(commanded.positions[before]))  # nothing before the enable
    assert numpy.all(numpy.isfinite(commanded.positions[commanded.times > enabled_at + 0.5]))


def check_conversation(output, recording):
    """The stand-in speech node listened, then spoke, then fell silent; the live lines and the recording's modes
    (from the node's status) followed it: listening from 2 s after the enable for about 6 s, then speaking for about 8
    s, then idle."""
    assert "animateBehaviourDemoSpeech: listening for 6 s" in output, output
    assert "animateBehaviourDemoSpeech: silent: the speaking goal ended (SUCCEEDED)" in output, output
    # A line of another node of the launch may run on at the end of a live line: only the mode's word counts.
    said = [re.search(r"mode: (idle|listening|speaking)", line).group(1) for line in status_lines(output)
            if re.search(r"mode: (idle|listening|speaking)", line)]
    assert [mode for index, mode in enumerate(said) if index == 0 or mode != said[index - 1]] == \
        ["idle", "listening", "speaking", "idle"], output
    from cssr_system.recording.recording import mode_spans  # after the skip: needs the workspace
    enabled_at = recording.activations[0][0]
    spans = [(start - enabled_at, end - start, mode) for start, end, mode in mode_spans(recording)]
    assert [mode for _, _, mode in spans] == ["idle", "listening", "speaking", "idle"], spans
    (listening_at, listening, _), (_, speaking, _) = spans[1:3]
    assert 1.5 < listening_at < 3.0 and 5.5 < listening < 7.0 and 7.5 < speaking < 9.0, spans


def test_demo_with_a_gesture_in_a_conversation_marks_it_and_prints_its_result(tmp_path):
    status, output, _ = run_demo(tmp_path, DURATION=CONVERSATION_DURATION, GESTURE=1, CONVERSATION=1)
    assert status == 0, output
    started = [line for line in output.splitlines() if "gesture on the right arm started" in line]
    ended = [line for line in output.splitlines() if "gesture on the right arm ended after" in line]
    assert len(started) == 1 and len(ended) == 1, output
    result = ended[0].split(": ")[2].split()[0]
    assert result in GESTURE_STATES, ended[0]

    recording = check_plot_and_recording(output, tmp_path)
    check_conversation(output, recording)
    enabled_at = recording.activations[0][0]
    assert len(recording.marks) == 1, recording.marks
    mark = recording.marks[0]
    assert mark.part == "RArm" and mark.label == "/animateBehaviourDemoGesture: " + result
    assert CONVERSATION_DURATION / 2.0 - 0.5 < mark.start - enabled_at < CONVERSATION_DURATION / 2.0 + 1.5
    assert mark.start < mark.end <= mark.start + 4.0 + 1.0  # a 4 s gesture, or less when preempted


def test_ctrl_c_disables_the_node_first_stops_everything_and_still_plots(tmp_path):
    status, output, stop_time = run_demo(tmp_path, interrupt_after="   2 s  enabled", DURATION=60)
    assert stop_time is not None, "the demo never printed its second line:\n" + output
    assert status == 130, output
    assert stop_time < 30.0, "the demo took %.0f s to stop after Ctrl-C" % stop_time
    assert "animateBehaviour disabled" in output

    recording = check_plot_and_recording(output, tmp_path, figure=False)  # no figure after Ctrl-C
    assert [state for _, state in recording.activations] == ["enabled", "disabled"]
    assert recording.activations[1][0] - recording.activations[0][0] < 20.0  # long before the 60 s

    from cssr_system.animate_behaviour.event_log import read_log
    events = [(entry.event, entry.fields) for entry in read_log(os.path.join(str(tmp_path),
                                                                             "animateBehaviourLogFile.log"))]
    names = [event for event, _ in events]
    disabled = names.index("activation_request", names.index("activation_request") + 1)
    assert events[disabled][1] == {"state": "disabled", "reply": "1"}
    assert disabled < names.index("node_stopped"), "the node was stopped before it was disabled"
    assert [fields["reason"] for event, fields in events if event == "behaviour_ended"] == ["disabled"]


def test_demo_with_the_joint_angles_actuation_streams_and_returns_every_joint_to_its_centre(tmp_path):
    status, output, _ = run_demo(tmp_path, DURATION=DEMO_DURATION, STYLE="breathing", BEHAVIOUR="body",
                                 ACTUATION="joint_angles")
    assert status == 0, output
    recording = check_plot_and_recording(output, tmp_path)
    enabled_at, disabled_at = [moment for moment, _ in recording.activations]
    commanded = recording.commanded  # the node's /joint_angles calls, as naoqi_driver runs them
    assert commanded is not None and commanded.source == "/animateBehaviour" and recording.marks == ()
    streamed = (commanded.times > enabled_at + 0.5) & (commanded.times < disabled_at)
    assert numpy.all(numpy.isfinite(commanded.positions[streamed]))
    from cssr_system.pepper.joint_table import PARTS  # after the skip: needs the workspace
    last = dict(zip(recording.joint_names, recording.positions[-1]))
    for part in PARTS.values():
        for name, centre in zip(part.joints, part.centre):
            assert abs(last[name] - centre) < 0.01, name
    assert "ACTUATION=joint_angles runs the simulated Pepper as naoqi_driver" in run_demo(
        tmp_path, ACTUATION="joint_angles", DRIVER="naoqi_dcm")[1]


def test_demo_with_two_robots_enables_each_on_its_own_and_plots_both(tmp_path):
    status, output, _ = run_demo(tmp_path, DURATION=DEMO_DURATION, ROBOTS=2)
    assert status == 0, output
    from cssr_system.recording.plot import robots_timeline  # after the skip: needs the workspace
    from cssr_system.recording.recording import read_recording
    recordings = {robot: read_recording(os.path.join(str(tmp_path), robot, "animation.json"))
                  for robot in ("robot1", "robot2")}
    timeline = robots_timeline(recordings)
    (enabled1, disabled1), (enabled2, disabled2) = ([moment for moment, _ in timeline[robot][2]]
                                                    for robot in ("robot1", "robot2"))
    assert enabled1 == pytest.approx(0.0) and 3.0 < enabled2 - enabled1 < 7.0, "robot2 is enabled after robot1"
    assert disabled1 < disabled2, "robot1 is disabled first"
    for robot in recordings:  # each node commanded its own robot only, and wrote its own log file
        commanded = recordings[robot].commanded
        assert commanded is not None and commanded.source == "/%s/animateBehaviour" % robot
        check_figure(output.splitlines(), os.path.join(str(tmp_path), robot, "animation.gif"))  # one per robot
    with open(os.path.join(str(tmp_path), "robots.png"), "rb") as image:
        assert image.read().startswith(PNG_SIGNATURE)


def test_demo_with_an_unknown_number_of_robots_says_so_and_fails(tmp_path):
    status, output, _ = run_demo(tmp_path, ROBOTS=3)
    assert status == 1 and "ROBOTS=3 (expected 1 or 2)" in output, output


def test_demo_with_two_robots_fails_with_status_1_when_a_node_cannot_start(tmp_path):
    status, output, _ = run_demo(tmp_path, DURATION=DEMO_DURATION, ROBOTS=2, NODE_ARGS="_selectedRange:=7")
    assert status == 1, output
    assert "selectedRange" in output and "demo: error:" in output, output
