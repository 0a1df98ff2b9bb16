"""Unit tests of the motion report's figures (motion/report.py) on signals whose figures are known."""
import math

import numpy
import pytest

from cssr_system.animate_behaviour.configuration import shipped_configuration_path
from cssr_system.motion.report import (SAMPLE_RATE, arm_beats, band_entry_times, figures, mode_targets, modes_report,
                                       report)
from cssr_system.pepper.joint_table import DRIVER_JOINT_PRECISION

TIMES = numpy.arange(0.0, 60.0, 1.0 / SAMPLE_RATE)


def figures_of(**columns):
    names = tuple(columns)
    return {row.joint: row for row in figures(TIMES, names, numpy.column_stack([columns[n] for n in names]))}


def test_a_sine_has_its_amplitude_period_rhythm_and_speeds():
    amplitude, period = 0.1, 5.0
    omega = 2 * math.pi / period
    row = figures_of(RShoulderPitch=1.5 + amplitude * numpy.sin(omega * TIMES))["RShoulderPitch"]
    assert row.peak_to_peak == pytest.approx(2 * amplitude, rel=1e-3)
    assert row.period == pytest.approx(period, rel=0.02)
    assert row.autocorrelation == pytest.approx(1.0, abs=0.01)
    assert row.rms_speed == pytest.approx(amplitude * omega / math.sqrt(2), rel=0.01)
    assert row.rms_jerk == pytest.approx(amplitude * omega ** 3 / math.sqrt(2), rel=0.02)
    assert row.visible == (2 * amplitude >= DRIVER_JOINT_PRECISION)
    assert row.moving > 0.9


def test_a_still_joint_neither_moves_nor_shows():
    row = figures_of(HipPitch=numpy.full(len(TIMES), -0.11))["HipPitch"]
    assert row.peak_to_peak == 0.0 and row.moving == 0.0 and not row.visible
    assert math.isnan(row.period)


def test_white_noise_has_no_rhythm():
    noise = numpy.random.default_rng(1).normal(0.0, 0.05, len(TIMES))
    assert abs(figures_of(LElbowYaw=noise)["LElbowYaw"].autocorrelation) < 0.2


def test_sides_correlate_with_mirroring_where_the_limits_mirror():
    wave = 0.05 * numpy.sin(2 * math.pi * TIMES / 4.0)
    rows = figures_of(LShoulderPitch=1.5 + wave, RShoulderPitch=1.5 + wave, LShoulderRoll=0.1 + wave,
                      RShoulderRoll=-0.1 - wave)
    assert rows["LShoulderPitch"].side_correlation == pytest.approx(1.0)
    assert rows["RShoulderRoll"].side_correlation == pytest.approx(1.0)


def test_through_joint_angles_the_breathing_moves_as_planned_where_the_driver_steps():
    tables = report(shipped_configuration_path(), 20.0, 1)
    ideal, dcm, angles = ({row.joint: row for row in tables[("breathing", driver)]}
                          for driver in ("ideal", "naoqi_dcm", "joint_angles"))
    for joint in ("RShoulderPitch", "LElbowYaw", "RHand", "HipPitch"):
        assert angles[joint].peak_to_peak == pytest.approx(ideal[joint].peak_to_peak, abs=0.005)
        assert angles[joint].moving >= ideal[joint].moving - 0.05 and dcm[joint].moving < 0.2
        assert angles[joint].visible


def test_a_joint_enters_its_band_when_it_stays_in_it():
    times = numpy.arange(0.0, 1.0, 0.1)
    positions = numpy.array([[0.5, 0.0], [0.3, 0.0], [0.1, 0.0], [-0.3, 0.0], [0.0, 0.0]] + [[0.0, 0.0]] * 4
                            + [[0.0, 0.5]])
    numpy.testing.assert_allclose(band_entry_times(times, positions, [-0.2, -0.2], [0.2, 0.2]), [0.4, numpy.inf])


def test_each_mode_meets_its_targets_in_the_default_configuration():
    """README: "Modes": listening's arms and hands at most 35 % of idle's amplitude, speaking's arms at least 1.5 times
    idle's with 40 beats a minute or more, neither turning the base; both styles."""
    tables = modes_report(shipped_configuration_path(), 30.0, 1)
    for style in ("random", "breathing"):
        by_mode = {mode: tables[(style, mode)] for mode in ("idle", "listening", "speaking")}
        assert all(met for _, met in mode_targets(by_mode)), (style, mode_targets(by_mode))
        idle = {row.part: row for row in by_mode["idle"]}
        assert idle["base"].beats > 0, "idle turns the base: the table's base figures are measured"


def test_arm_beats_count_a_stroke_and_its_return_as_one_beat():
    times = numpy.arange(0.0, 60.0, 1.0 / SAMPLE_RATE)
    swing = 0.3 * numpy.sin(2 * numpy.pi * 0.75 * times)  # 45 swings back and forth a minute
    assert arm_beats(times, numpy.column_stack([swing, swing])) == pytest.approx(45.0, abs=1.0)
