"""The 3-minute soak on ROS 2 (soak_check.py; doc/soak.md), on a ROS 2 domain claimed for it (test/ros2/domains.py);
skipped where no Python suits the ROS 2 wheels."""
import sys
from pathlib import Path

import pytest

from soak_check import check, check_race, run_race, run_soak

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "ros2"))
from domains import claim_domain  # noqa: E402

NO_ROS2 = 3  # tools/soak.sh's status where no Python suits the ROS 2 wheels


def test_three_minutes_of_churn_leave_the_ros2_node_as_it_started(tmp_path):
    finished = run_soak("2", tmp_path, SOAK_DOMAIN_ID=str(claim_domain()))
    if finished.returncode == NO_ROS2:
        pytest.skip(finished.stdout.strip().splitlines()[-1])
    check(finished, tmp_path)


def test_gestures_at_random_moments_on_every_part_find_the_ros2_node_yielding(tmp_path):
    finished = run_race("2", tmp_path, "random", RACE_DOMAIN_ID=str(claim_domain()))
    if finished.returncode == NO_ROS2:
        pytest.skip(finished.stdout.strip().splitlines()[-1])
    check_race(finished, tmp_path)
