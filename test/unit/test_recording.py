"""Unit tests of the recording format and its plot: recording file round trip (with its optional fields),
bands, activations, motion summary, plot; and of what a node commanded, rebuilt from its goals."""
import json
import math
import os

import numpy
import pytest

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import load_configuration, topic_file_path
from cssr_system.animate_behaviour.contract import DISABLED, ENABLED
from cssr_system.animate_behaviour.event_log import EventLog, read_log
from cssr_system.animate_behaviour.topics import load_topic_map
from cssr_system.motion.waypoints import joint_bounds
from cssr_system.pepper.joint_table import JOINTS, PARTS
from cssr_system.pepper.trajectory_interpolation import JointTrajectorySpline, TrajectoryPoint
from cssr_system.recording.commanded import (CancelRequest, GoalResult, SentGoal, commanded_by,
                                             controller_pieces, goal_marks)
from cssr_system.recording.plot import plot_recording
from cssr_system.recording.recording import (RECORDING_FORMAT, plotted_parts, Commanded, JointBand,
                                             Mark, Recording, activations_from_log, band_excess,
                                             bands_from_configuration, bands_from_log,
                                             heading_excess, mode_spans, moving_parts, read_recording,
                                             unwrap_heading, write_recording,
                                             yaw_from_quaternion)

PACKAGE_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CONFIG_FILE = os.path.join(PACKAGE_DIR, "config", "animateBehaviourConfiguration.ini")
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def synthetic_run(duration=12.0, enable_at=1.0, disable_at=9.0, rate=50.0):
    """A run like the demo's: every animated joint rests at its centre, moves smoothly inside its
    band while enabled, returns to the centre after disable; the base turns within 0.3 rad."""
    config = load_configuration(CONFIG_FILE)
    bands = bands_from_configuration(config, PARTS)
    names = tuple(JOINTS)  # every joint, as /joint_states carries them
    times = numpy.arange(0.0, duration, 1.0 / rate)
    # Smooth envelope: 0 before enable, 1 while enabled, fading to 0 within 1 s after disable.
    envelope = numpy.clip(numpy.minimum(times - enable_at, 1.0), 0.0, 1.0) * \
        numpy.clip(1.0 - (times - disable_at), 0.0, 1.0)
    positions = numpy.zeros((len(times), len(names)))
    for column, name in enumerate(names):
        band = bands.get(name)
        if band is None:
            continue
        half = (band.upper - band.lower) / 2.0
        middle = (band.upper + band.lower) / 2.0
        positions[:, column] = band.centre + envelope * \
            ((middle - band.centre) + 0.9 * half * numpy.sin(2.0 * math.pi * (0.3 + 0.05 * column) * times))
    heading_times = times.copy()
    headings = 0.25 * envelope * numpy.sin(2.0 * math.pi * 0.1 * times)
    return Recording(
        start_epoch=1763740984.125,
        joint_names=names,
        times=times,
        positions=positions,
        heading_times=heading_times,
        headings=headings,
        activations=((enable_at, ENABLED), (disable_at, DISABLED)),
        bands=bands,
        heading_bound=0.3,
        info={"platform": "robot", "behaviour": "all"},
        heading_topic="/pepper_dcm/odom",
    )


def assert_same(first, second):
    assert first.start_epoch == second.start_epoch
    assert first.joint_names == second.joint_names
    numpy.testing.assert_array_equal(first.times, second.times)
    numpy.testing.assert_array_equal(first.positions, second.positions)
    numpy.testing.assert_array_equal(first.heading_times, second.heading_times)
    numpy.testing.assert_array_equal(first.headings, second.headings)
    assert tuple(first.activations) == tuple(second.activations)
    assert dict(first.bands) == dict(second.bands)
    assert first.heading_bound == second.heading_bound
    assert dict(first.info) == dict(second.info)
    assert first.heading_topic == second.heading_topic


def test_recording_round_trip_is_exact(tmp_path):
    recording = synthetic_run()
    path = write_recording(str(tmp_path / "run.json"), recording)
    assert_same(recording, read_recording(path))
    with open(path, encoding="utf-8") as written:
        data = json.load(written)
    assert data["format"] == RECORDING_FORMAT and data["version"] == 1


def test_missing_samples_survive_as_nan(tmp_path):
    recording = synthetic_run(duration=1.0)
    recording.positions[3, 2] = numpy.nan
    back = read_recording(write_recording(str(tmp_path / "gap.json"), recording._replace(bands={},
                                                                                         heading_bound=None)))
    assert math.isnan(back.positions[3, 2])
    assert back.bands == {} and back.heading_bound is None


@pytest.mark.parametrize("content, message", [
    ("{\"format\": \"other\"}", "not an animation recording"),
    ("not json", "not JSON"),
    (json.dumps({"format": RECORDING_FORMAT, "version": 99}), "unsupported recording version"),
    (json.dumps({"format": RECORDING_FORMAT, "version": 1, "start_epoch": 0}),
     "missing field"),
])
def test_invalid_recordings_are_named(tmp_path, content, message):
    path = tmp_path / "bad.json"
    path.write_text(content)
    with pytest.raises(ValueError, match=message):
        read_recording(str(path))


def test_bands_from_configuration_follow_the_waypoint_planner():
    config = load_configuration(CONFIG_FILE, {"behaviour": "hands"})
    bands = bands_from_configuration(config, PARTS)
    assert bands["RHand"] == JointBand(*joint_bounds(config, "RHand")[2:4], joint_bounds(config, "RHand").centre,
                                       True)
    held = bands["RShoulderPitch"]
    assert not held.moving and held.lower == held.upper == held.centre
    assert "HipPitch" not in bands  # hands do not move the leg
    simulator = load_configuration(CONFIG_FILE, {"platform": "simulator"})
    simulator_parts = load_topic_map(topic_file_path(simulator)).topics
    assert "LHand" not in bands_from_configuration(simulator, simulator_parts)


def test_bands_from_log_reads_animating_goals_of_the_run(tmp_path):
    log_path = str(tmp_path / "animateBehaviourLogFile.log")
    clock = [1000.0]
    with EventLog(log_path, clock=lambda: clock[0]) as log:
        log.write(contract.CONFIGURATION_LOADED, file="x", items={"headingBound": "0.25"})
        log.write(contract.GOAL_SENT, part="Leg", purpose="animate", joints=["HipPitch"], centre=[0.0],
                  lower=[-9.0], upper=[9.0], moving=[True])  # before the run: ignored
        clock[0] = 1010.0
        log.write(contract.BEHAVIOUR_STARTED, behaviour=["all"], wheels="/pepper_dcm/cmd_moveto")
        log.write(contract.GOAL_SENT, part="Leg", purpose="animate", joints=["HipPitch", "HipRoll"],
                  centre=[-0.11, 0.0], lower=[-0.2, -0.05], upper=[0.0, 0.05], moving=[True, False])
        log.write(contract.GOAL_SENT, part="Leg", purpose="animate", joints=["HipPitch", "HipRoll"],
                  centre=[-0.11, 0.0], lower=[-0.25, -0.05], upper=[-0.01, 0.05], moving=[True, False])
        log.write(contract.GOAL_SENT, part="Leg", purpose="home", joints=["HipPitch", "HipRoll"],
                  centre=[-0.11, 0.0], lower=[-5.0, -5.0], upper=[5.0, 5.0], moving=[True, True])
    bands, heading_bound = bands_from_log(read_log(log_path), since=1005.0)
    assert bands["HipPitch"] == JointBand(-0.25, 0.0, -0.11, True)  # the hull of both bands
    assert bands["HipRoll"] == JointBand(-0.05, 0.05, 0.0, False)
    assert heading_bound == 0.25
    no_base, bound = bands_from_log(read_log(log_path), since=1005.0, until=1009.0)
    assert no_base == {} and bound is None


def test_moving_parts_names_parts_that_moved_beyond_the_threshold():
    names = ("RShoulderPitch", "LHand", "HipPitch", "HeadYaw")
    window = numpy.array([[1.0, 0.5, 0.0, 0.0], [1.05, 0.505, 0.0, 0.5], [1.02, 0.5, 0.0, -0.5]])
    assert moving_parts(names, window) == ["right arm"]  # the head is not an animated part
    assert moving_parts(names, window[:1]) == []


def test_heading_helpers():
    assert yaw_from_quaternion(0.0, 0.0, math.sin(0.4), math.cos(0.4)) == pytest.approx(0.8)
    assert unwrap_heading(3.1, -3.1) == pytest.approx(2.0 * math.pi - 3.1)
    assert unwrap_heading(None, -3.1) == -3.1


def test_excess_is_measured_against_the_band():
    recording = synthetic_run()
    assert all(band_excess(recording, name) == 0.0 for name in recording.bands)
    assert heading_excess(recording) == 0.0
    column = recording.joint_names.index("LElbowYaw")
    recording.positions[100, column] = recording.bands["LElbowYaw"].upper + 0.05
    assert band_excess(recording, "LElbowYaw") == pytest.approx(0.05)


def test_plot_of_a_synthetic_run_is_a_png(tmp_path):
    output = plot_recording(synthetic_run(), str(tmp_path / "plots" / "run.png"))
    with open(output, "rb") as image:
        content = image.read()
    assert content.startswith(PNG_SIGNATURE)
    assert len(content) > 30 * 1024  # six panels of lines, not an empty canvas
    width, height = int.from_bytes(content[16:20], "big"), int.from_bytes(content[20:24], "big")
    assert width >= 1200 and height >= 800


def test_plot_without_bands_shows_the_parts_that_moved(tmp_path):
    recording = synthetic_run()._replace(bands={}, heading_bound=None, activations=())
    assert [label for label, _ in plotted_parts(recording)] == \
        [part.label for part in PARTS.values()]
    output = plot_recording(recording, str(tmp_path / "bare.png"))
    with open(output, "rb") as image:
        assert image.read(8) == PNG_SIGNATURE


# ---------------------------------------------------------------------------------------------------
# Optional fields: commanded positions and marks.

def with_optional_fields(recording):
    names = ("RShoulderPitch", "RHand")
    positions = numpy.column_stack([1.5 + 0.1 * numpy.sin(recording.times), numpy.full(len(recording.times), 0.6)])
    positions[:10] = numpy.nan  # nothing commanded before the first goal
    return recording._replace(
        commanded=Commanded(names, recording.times.copy(), positions, "/animateBehaviour"),
        marks=(Mark(4.0, 6.5, "/someNode: PREEMPTED", "RArm"), Mark(7.0, 7.5, "everywhere")))


def test_optional_fields_round_trip_exactly(tmp_path):
    recording = with_optional_fields(synthetic_run())
    back = read_recording(write_recording(str(tmp_path / "run.json"), recording))
    assert_same(recording, back)
    assert back.commanded.joint_names == recording.commanded.joint_names
    assert back.commanded.source == "/animateBehaviour"
    numpy.testing.assert_array_equal(back.commanded.times, recording.commanded.times)
    numpy.testing.assert_array_equal(back.commanded.positions, recording.commanded.positions)  # NaN kept
    assert back.marks == recording.marks


def test_the_modes_round_trip_and_make_spans_to_the_end_of_the_recording(tmp_path):
    recording = synthetic_run()._replace(modes=((0.5, "idle"), (2.0, "listening"), (8.0, "speaking"),
                                                (10.0, "idle")))
    back = read_recording(write_recording(str(tmp_path / "modes.json"), recording))
    assert back.modes == recording.modes
    end = float(recording.times[-1])
    assert mode_spans(back) == [(0.5, 2.0, "idle"), (2.0, 8.0, "listening"), (8.0, 10.0, "speaking"),
                                (10.0, end, "idle")]
    assert mode_spans(synthetic_run()) == []
    output = plot_recording(back, str(tmp_path / "modes.png"))  # shaded spans and their key
    with open(output, "rb") as image:
        assert image.read(8) == PNG_SIGNATURE


def test_recordings_without_optional_fields_stay_readable(tmp_path):
    path = write_recording(str(tmp_path / "old.json"), synthetic_run())
    with open(path, encoding="utf-8") as written:
        data = json.load(written)
    assert "commanded" not in data and "marks" not in data and "modes" not in data  # as in files written before
    back = read_recording(path)
    assert back.commanded is None and back.marks == () and back.modes == ()


def test_a_malformed_commanded_field_is_named(tmp_path):
    recording = with_optional_fields(synthetic_run(duration=1.0))
    path = write_recording(str(tmp_path / "bad.json"), recording)
    with open(path, encoding="utf-8") as written:
        data = json.load(written)
    data["commanded"]["positions"][3] = [1.0]
    (tmp_path / "bad.json").write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"commanded.positions\[3\] has 1 values for 2 joints"):
        read_recording(str(tmp_path / "bad.json"))


def test_activations_come_from_accepted_requests_of_the_run(tmp_path):
    log_path = str(tmp_path / "animateBehaviourLogFile.log")
    clock = [1000.0]
    with EventLog(log_path, clock=lambda: clock[0]) as log:
        log.write(contract.ACTIVATION_REQUEST, state="enabled", reply="1")  # before the run
        clock[0] = 1010.0
        log.write(contract.ACTIVATION_REQUEST, state=" Enabled ", reply="1")
        log.write(contract.ACTIVATION_REQUEST, state="dance", reply="0")
        clock[0] = 1012.5
        log.write(contract.ACTIVATION_REQUEST, state="enabled", reply="0")  # refused: no change
        log.write(contract.ACTIVATION_REQUEST, state="disabled", reply="1")
    assert activations_from_log(read_log(log_path), since=1005.0) == [(1010.0, ENABLED), (1012.5, DISABLED)]
    assert activations_from_log(read_log(log_path), since=1005.0, until=1011.0) == [(1010.0, ENABLED)]


def test_another_nodes_goal_excuses_the_excursion_it_causes():
    recording = synthetic_run()
    column = recording.joint_names.index("RShoulderPitch")
    band = recording.bands["RShoulderPitch"]
    away = (recording.times >= 4.0) & (recording.times < 7.0)  # moved out by the goal, back in at 7 s
    recording.positions[away, column] = band.lower - 1.0
    assert band_excess(recording, "RShoulderPitch") == pytest.approx(1.0)
    marked = recording._replace(marks=(Mark(4.0, 6.0, "/someNode: SUCCEEDED", "RArm"),))
    assert band_excess(marked, "RShoulderPitch") == 0.0
    elsewhere = recording._replace(marks=(Mark(4.0, 6.0, "/someNode: SUCCEEDED", "LArm"),))
    assert band_excess(elsewhere, "RShoulderPitch") == pytest.approx(1.0)
    recording.positions[recording.times >= 9.5, column] = band.upper + 0.2  # later, by the node itself
    assert band_excess(marked, "RShoulderPitch") == pytest.approx(0.2)


def test_plot_with_commanded_lines_and_marks_is_a_png(tmp_path):
    output = plot_recording(with_optional_fields(synthetic_run()), str(tmp_path / "full.png"))
    with open(output, "rb") as image:
        assert image.read(8) == PNG_SIGNATURE


# ---------------------------------------------------------------------------------------------------
# What a node commanded, rebuilt from the goals a controller received.

ARM = PARTS["RArm"]
NODE = "/animateBehaviour"


def goal(time, caller, points, goal_id=None, joints=ARM.joints, part="RArm"):
    return SentGoal(time, part, caller, goal_id or "%s-%g" % (caller, time), tuple(joints),
                    tuple(TrajectoryPoint(t, tuple(p), (0.0,) * len(p), (0.0,) * len(p)) for t, p in points))


def arm_pose(offset):
    return tuple(centre + offset for centre in ARM.centre)


def measured_rest(duration=10.0):
    times = numpy.arange(0.0, duration, 0.02)
    return ARM.joints, times, numpy.tile(ARM.centre, (len(times), 1))


def sample(source, goals, cancels=(), times=None):
    times = numpy.arange(0.0, 10.0, 0.01) if times is None else times
    return times, commanded_by(source, controller_pieces(goals, cancels, measured_rest()), times)


def test_a_goal_is_sampled_with_the_controllers_interpolation_from_the_measured_joints():
    first = goal(1.0, NODE, [(1.0, arm_pose(0.1)), (2.0, arm_pose(-0.1))])
    times, commanded = sample(NODE, [first])
    assert commanded.joint_names == ARM.joints and commanded.source == NODE
    assert numpy.all(numpy.isnan(commanded.positions[times < 1.0]))  # nothing commanded yet
    expected = JointTrajectorySpline(ARM.centre, None, None, first.points, start_time=1.0)
    during = (times >= 1.0) & (times <= 3.0)
    for row in numpy.nonzero(during)[0][::20]:
        numpy.testing.assert_allclose(commanded.positions[row], expected.sample(times[row])[0], atol=1e-12)
    numpy.testing.assert_allclose(commanded.positions[-1], arm_pose(-0.1))  # held after the last point


def test_a_new_goal_is_spliced_onto_the_motion_in_progress():
    goals = [goal(1.0, NODE, [(2.0, arm_pose(0.3))]), goal(2.0, NODE, [(1.0, arm_pose(-0.2))])]
    times, commanded = sample(NODE, goals)
    column = ARM.joints.index("RShoulderPitch")
    before, after = commanded.positions[times < 2.0][-1, column], commanded.positions[times >= 2.0][0, column]
    assert abs(after - before) < 0.01  # continuous: the second starts where the first was
    assert before > ARM.centre[column] + 0.05  # and the first was under way
    numpy.testing.assert_allclose(commanded.positions[-1], arm_pose(-0.2))


def test_another_nodes_goal_leaves_a_gap_and_the_next_goal_starts_from_it():
    goals = [goal(1.0, NODE, [(1.0, arm_pose(0.1))]), goal(3.0, "/gesture", [(1.0, arm_pose(-0.5))]),
             goal(5.0, NODE, [(1.0, arm_pose(0.1))])]
    times, commanded = sample(NODE, goals)
    gap = (times >= 3.0) & (times < 5.0)
    assert numpy.all(numpy.isnan(commanded.positions[gap]))
    assert numpy.all(numpy.isfinite(commanded.positions[times >= 5.0]))
    numpy.testing.assert_allclose(commanded.positions[times >= 5.0][0], arm_pose(-0.5), atol=1e-9)
    gesture = sample("/gesture", goals)[1]
    assert numpy.all(numpy.isfinite(gesture.positions[gap])) and numpy.all(numpy.isnan(gesture.positions[times < 3.0]))


def test_a_cancel_holds_the_position_reached():
    first = goal(1.0, NODE, [(2.0, arm_pose(0.4))], goal_id="g1")
    times, commanded = sample(NODE, [first], [CancelRequest(2.0, "RArm", "g1")])
    reached = JointTrajectorySpline(ARM.centre, None, None, first.points, start_time=1.0).sample(2.0)[0]
    numpy.testing.assert_allclose(commanded.positions[-1], reached)
    assert not numpy.allclose(reached, arm_pose(0.4))
    unrelated = sample(NODE, [first], [CancelRequest(2.0, "RArm", "other")])[1]
    numpy.testing.assert_allclose(unrelated.positions[-1], arm_pose(0.4))


def test_goals_the_controller_rejects_are_skipped():
    wrong_joints = goal(1.0, NODE, [(1.0, arm_pose(0.1)[:4])], joints=ARM.joints[:4])
    backwards = goal(2.0, NODE, [(1.0, arm_pose(0.1)), (0.5, arm_pose(0.2))])
    assert commanded_by(NODE, controller_pieces([wrong_joints, backwards]), [0.0, 5.0]) is None


def test_other_nodes_goals_become_marks_from_receipt_to_result():
    goals = [goal(1.0, NODE, [(1.0, arm_pose(0.1))]), goal(3.0, "/gesture", [(4.0, arm_pose(0.2))], "g"),
             goal(8.0, "/other", [(4.0, arm_pose(0.2))], "h", part="LArm")]
    results = [GoalResult(2.0, "RArm", "/animateBehaviour-1", "SUCCEEDED"), GoalResult(5.0, "RArm", "g", "PREEMPTED")]
    expected = (Mark(3.0, 5.0, "/gesture: PREEMPTED", "RArm"), Mark(8.0, 9.0, "/other: no result", "LArm"))
    assert goal_marks(goals, results, NODE, end=9.0) == expected


def test_changes_of_live_settings_become_one_mark_each(tmp_path):
    from cssr_system.animate_behaviour import contract
    from cssr_system.animate_behaviour.event_log import EventLog, read_log
    from cssr_system.recording.recording import setting_changes_from_log
    path = str(tmp_path / "node.log")
    log = EventLog(path)
    log.write(contract.SETTING_CHANGED, key="intensity", old="1.0", new="0.5", by="/tree")
    log.write(contract.SETTING_CHANGED, key="turnBase", old="true", new="false", by="/tree")
    log.write(contract.GOAL_SENT, part="RArm")
    log.close()
    changes = setting_changes_from_log(read_log(path))
    assert [text for _, text in changes] == ["intensity 1.0 -> 0.5, turnBase true -> false"]


def test_a_change_of_bands_is_recorded_plotted_and_read_back(tmp_path):
    from cssr_system.animate_behaviour import contract
    from cssr_system.animate_behaviour.event_log import EventLog, read_log
    from cssr_system.recording.plot import changing_bands
    from cssr_system.recording.recording import (BandChange, band_changes_from_log, read_recording,
                                                 write_recording)
    path = str(tmp_path / "node.log")
    log = EventLog(path)
    for upper in (1.7, 1.7, 1.6):  # the same band twice, then a narrower one
        log.write(contract.GOAL_SENT, part="RArm", purpose=contract.PURPOSE_ANIMATE, joints=["RShoulderPitch"],
                  lower=[1.4], upper=[upper], centre=[1.54], moving=[True])
    log.close()
    changes = band_changes_from_log(read_log(path))
    assert [(name, band.upper) for _, name, band in changes] == [("RShoulderPitch", 1.7), ("RShoulderPitch", 1.6)]
    bands = (BandChange(0.5, "RShoulderPitch", 1.4, 1.7), BandChange(2.0, "RShoulderPitch", 1.45, 1.6))
    recording = synthetic_run()._replace(band_changes=bands)
    assert list(changing_bands(recording)) == ["RShoulderPitch"]
    saved = write_recording(str(tmp_path / "run.json"), recording)
    assert read_recording(saved).band_changes == recording.band_changes
