"""The 3-minute soak on ROS 1 (soak_check.py; doc/soak.md)."""
from soak_check import check, run_soak


def test_three_minutes_of_churn_leave_the_ros1_node_as_it_started(tmp_path):
    check(run_soak("1", tmp_path), tmp_path)
