"""`make benchmark ROS=2` runs and reports every figure: a short run on the simulator's interface (the real one
takes minutes and is not a test), on a domain of its own. Checks the JSON, the printed table and the markdown table,
not the figures, which depend on the machine (test/benchmark/run_check.py, as for ROS 1).

Run inside the ROS 2 environment: bash tools/ros2/run.sh python3 -m pytest test/ros2/test_benchmark_ros2.py -q
"""
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("rclpy")
pytest.importorskip("cssr_system_interfaces.srv")

REPO_DIR = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO_DIR / "test" / "benchmark"))
from run_check import check_run  # noqa: E402

from domains import claim_domain  # noqa: E402
from processes import environment  # noqa: E402

DOMAIN = claim_domain()


def test_a_short_ros_2_benchmark_reports_every_figure_beside_the_reference_and_its_target(tmp_path):
    output, table_file = str(tmp_path / "benchmark.json"), str(tmp_path / "benchmark-latest.md")
    run = subprocess.run([sys.executable, str(REPO_DIR / "test" / "benchmark" / "benchmark_ros2.py"),
                          "--platform", "simulator", "--cycles", "2", "--cpu-window", "1", "--exit-runs", "1",
                          "--json", output, "--markdown", table_file], env=environment(DOMAIN),
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=300)
    assert run.returncode == 0, run.stdout[-3000:]
    check_run(run.stdout, output, table_file, "simulator", 2)
    with open(table_file) as stream:
        assert "## ROS 1 (`make benchmark`)\n\nNot run yet." in stream.read(), "the other front-end's section"
    assert os.path.getsize(output) > 0
