"""Unit tests of the recording format and its plot: recording file round trip, bands, motion summary, plot."""
import json
import math
import os

import numpy
import pytest

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.configuration import load_configuration, topic_file_path
from cssr_system.animate_behaviour.contract import DISABLED, ENABLED
from cssr_system.animate_behaviour.event_log import EventLog, read_log
from cssr_system.animate_behaviour.motion.waypoints import joint_bounds
from cssr_system.animate_behaviour.recording.plot import plot_recording
from cssr_system.animate_behaviour.recording.recording import (RECORDING_FORMAT, plotted_parts, JointBand,
                                                               Recording, band_excess,
                                                               bands_from_configuration, bands_from_log,
                                                               heading_excess, moving_parts, read_recording,
                                                               unwrap_heading, write_recording,
                                                               yaw_from_quaternion)
from cssr_system.animate_behaviour.topics import load_topic_map
from cssr_system.pepper.joint_table import JOINTS, PARTS

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
