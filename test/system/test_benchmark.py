"""`make benchmark` runs and reports every figure: a short run on one platform, with a short soak (the real one
takes minutes and is not a test). Checks the JSON, the printed table and the markdown table (doc/benchmark-latest.md
under `make benchmark`), not the figures, which depend on the machine."""
import json
import os
import subprocess
import sys

REPO_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(REPO_DIR, "test", "benchmark"))
from benchmark import COLD_FIRST_GOAL, EXITS, TARGETS, Target, target_text, verdict  # noqa: E402

ALWAYS_MEASURED = [target.name for target in TARGETS if target.name != "zero twist after disabled"]
REFERENCE_MEASURED = ["setActivation enabled reply", "setActivation disabled reply",
                      "first goal of every part after enabled", "stop of every part after disabled",
                      "CPU while disabled", "CPU while animating", "resident memory", "threads", "open files",
                      COLD_FIRST_GOAL] + list(EXITS)


def test_a_short_benchmark_reports_every_figure_beside_the_reference_and_its_target(tmp_path):
    output = str(tmp_path / "benchmark.json")
    table_file = str(tmp_path / "benchmark-latest.md")
    run = subprocess.run([sys.executable, os.path.join(REPO_DIR, "test", "benchmark", "benchmark.py"),
                          "--platform", "robot", "--cycles", "2", "--cpu-window", "1", "--exit-runs", "1",
                          "--soak", "2", "--growth-cycles", "2", "--json", output, "--markdown", table_file],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=240)
    assert run.returncode == 0, run.stdout[-3000:]
    lines = run.stdout.splitlines()
    table = lines[:next(index for index, line in enumerate(lines) if line.startswith("soak:"))]
    assert table[1].split() == ["figure", "node", "p50", "/", "p90", "/", "max", "reference", "p50", "/", "p90", "/",
                                "max", "target", "met?"]
    for target in TARGETS:
        rows = [line for line in table if line.startswith(target.name + " (") or line.startswith(target.name + " ")]
        assert len(rows) == 1, target.name
        if target.name in ALWAYS_MEASURED:
            assert rows[0].rstrip().endswith(("yes", "NO", "-")) or "(mean " in rows[0], rows[0]
    assert "figures written to %s" % output in run.stdout
    with open(output) as stream:
        section = json.load(stream)["robot"]
    for target in TARGETS:
        assert section["targets"][target.name] == target.as_dict()
    for subject, names in (("node", ALWAYS_MEASURED), ("reference", REFERENCE_MEASURED)):
        for name in names:
            figure = section["figures"][subject][name]
            assert 0 <= figure["p50"] <= figure["p90"] <= figure["max"], (subject, name)
            assert figure["samples"] >= 1
    for name in EXITS:
        figure = section["figures"]["node"][name]
        assert figure["stopped first"] <= figure["samples"] and figure["exit status"]
    assert set(section["met"]) == {target.name for target in TARGETS}
    soak = section["soak"]
    for state in ("start", "after soak", "after cycles"):
        assert set(soak[state]) == {"resident memory", "threads", "open files", "log bytes"}
    assert soak["growth cycles"] == 2 and "soak growth" in soak and "cycles growth" in soak
    assert "soak: 2 s of short goals" in run.stdout
    assert "table written to %s" % table_file in run.stdout
    with open(table_file) as stream:
        written = stream.read()
    assert "| figure | target | robot | met |" in written
    assert "robot interface: %s, %d cores, Python %d.%d" % ((section["time"], os.cpu_count()) + sys.version_info[:2]) \
        in written
    for target in TARGETS:
        rows = [line for line in written.splitlines() if line.startswith("| %s " % target.name)]
        assert len(rows) == 1 and rows[0].count("|") == 5, (target.name, rows)
    assert "soak: 2 s of short goals" in written


def test_make_benchmark_writes_the_latest_table_into_the_repository():
    with open(os.path.join(REPO_DIR, "tools", "benchmark.sh")) as stream:
        script = stream.read()
    assert '--markdown "$REPO_DIR/doc/benchmark-latest.md"' in script
    with open(os.path.join(REPO_DIR, "doc", "benchmark-latest.md")) as stream:
        assert "| figure | target |" in stream.read()


def test_a_target_set_against_the_reference_is_met_within_its_margin_of_the_references_mean():
    target = Target("CPU while disabled", "% of a core", above_reference=0.2)
    assert target_text(target) == "mean<=ref+0.2"

    def figure(mean):
        return {"p50": mean, "p90": mean, "max": mean, "mean": mean, "samples": 4}
    assert verdict(target, figure(0.75), figure(0.6)) is True
    assert verdict(target, figure(0.85), figure(0.6)) is False
    assert verdict(target, figure(0.1), None) is False  # no reference measured: not met
    assert verdict(Target("open files", ""), figure(80.0), figure(70.0)) is None  # no target


def test_first_goals_are_judged_on_their_p90_as_documented():
    target = next(target for target in TARGETS if target.name == "first goal of every part after enabled")
    spread = {"p50": 15.0, "p90": 19.0, "max": 40.0, "mean": 17.0, "samples": 20}
    assert verdict(target, spread, None) is True
    assert verdict(target, dict(spread, p90=21.0), None) is False
