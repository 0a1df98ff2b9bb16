"""The 3-minute soak on ROS 1 (soak_check.py; doc/soak.md)."""
from soak_check import check, check_race, run_race, run_soak


def test_three_minutes_of_churn_leave_the_ros1_node_as_it_started(tmp_path):
    check(run_soak("1", tmp_path), tmp_path)


def test_gestures_at_random_moments_on_every_part_find_the_ros1_node_yielding(tmp_path):
    check_race(run_race("1", tmp_path, "breathing"), tmp_path)
