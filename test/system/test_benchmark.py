"""`make benchmark` runs and reports every figure: a short ROS 1 run on one platform, with a short soak (the real one
takes minutes and is not a test). Checks the JSON, the printed table and the markdown table (doc/benchmark-latest.md
under `make benchmark`), not the figures, which depend on the machine; the ROS 2 run's test is
test/ros2/test_benchmark_ros2.py."""
import os
import subprocess
import sys

REPO_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(REPO_DIR, "test", "benchmark"))
from report import FRONT_ENDS, Target, markdown, target_text, targets, verdict  # noqa: E402
from run_check import check_run  # noqa: E402


def test_a_short_benchmark_reports_every_figure_beside_the_reference_and_its_target(tmp_path):
    output = str(tmp_path / "benchmark.json")
    table_file = str(tmp_path / "benchmark-latest.md")
    run = subprocess.run([sys.executable, os.path.join(REPO_DIR, "test", "benchmark", "benchmark.py"),
                          "--platform", "robot", "--cycles", "2", "--cpu-window", "1", "--exit-runs", "1",
                          "--soak", "2", "--growth-cycles", "2", "--json", output, "--markdown", table_file],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=300)
    assert run.returncode == 0, run.stdout[-3000:]
    section = check_run(run.stdout, output, table_file, "robot", 1)
    soak = section["soak"]
    for state in ("start", "after soak", "after cycles"):
        assert set(soak[state]) == {"resident memory", "threads", "open files", "log bytes"}
    assert soak["growth cycles"] == 2 and "soak growth" in soak and "cycles growth" in soak
    assert "soak: 2 s of short goals" in run.stdout
    with open(table_file) as stream:
        assert "soak: 2 s of short goals" in stream.read()


def test_make_benchmark_writes_the_latest_table_into_the_repository():
    with open(os.path.join(REPO_DIR, "tools", "benchmark.sh")) as stream:
        script = stream.read()
    assert '--markdown "$REPO_DIR/doc/benchmark-latest.md"' in script
    with open(os.path.join(REPO_DIR, "doc", "benchmark-latest.md")) as stream:
        written = stream.read()
    for ros, name in FRONT_ENDS.items():
        assert "<!-- %s section begin -->" % name in written, ros
    assert written.count("| figure | target |") == 2


def test_a_run_rewrites_its_own_front_ends_section_and_keeps_the_others():
    other = markdown({}, 2, "")  # no ROS 2 figures: its section says so
    assert "Not run yet." in other
    kept = other.replace("Not run yet.", "the ROS 2 figures")
    rewritten = markdown({}, 1, kept)
    assert "the ROS 2 figures" in rewritten and rewritten.count("<!-- ROS 1 section begin -->") == 1


def figure(mean):
    return {"p50": mean, "p90": mean, "max": mean, "mean": mean, "samples": 4}


def test_a_target_set_against_the_reference_is_met_within_its_margin_of_the_references_mean():
    target = Target("CPU while disabled", "% of a core", above_reference=0.2)
    assert target_text(target) == "mean<=ref+0.2"
    assert verdict(target, figure(0.75), figure(0.6)) is True
    assert verdict(target, figure(0.85), figure(0.6)) is False
    assert verdict(target, figure(0.1), None) is False  # no reference measured: not met
    assert verdict(Target("open files", ""), figure(80.0), figure(70.0)) is None  # no target


def test_a_target_as_a_multiple_of_the_reference_and_one_on_the_maximum():
    animating = next(target for target in targets(1) if target.name == "CPU while animating")
    assert target_text(animating) == "mean<=1.5xref"
    assert verdict(animating, figure(1.5), figure(1.0)) is True
    assert verdict(animating, figure(1.6), figure(1.0)) is False
    memory = next(target for target in targets(2) if target.name == "resident memory")
    assert target_text(memory) == "max<=ref+15"
    assert verdict(memory, dict(figure(60.0), max=79.0), dict(figure(60.0), max=65.0)) is True
    assert verdict(memory, dict(figure(60.0), max=81.0), dict(figure(60.0), max=65.0)) is False


def test_first_goals_are_judged_on_their_p90_as_documented():
    for ros, bound in ((1, 20.0), (2, 40.0)):
        target = next(target for target in targets(ros) if target.name == "first goal of every part after enabled")
        spread = {"p50": bound - 5, "p90": bound - 1, "max": 2 * bound, "mean": bound - 3, "samples": 20}
        assert verdict(target, spread, None) is True
        assert verdict(target, dict(spread, p90=bound + 1), None) is False
