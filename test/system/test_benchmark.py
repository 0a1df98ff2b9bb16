"""`make benchmark` runs and reports every figure: a short run on one platform (the real one takes minutes and is
not a test). Checks the JSON and the printed table, not the figures, which depend on the machine."""
import json
import os
import subprocess
import sys

REPO_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(REPO_DIR, "test", "benchmark"))
from benchmark import TARGETS  # noqa: E402

ALWAYS_MEASURED = [name for name, _, _, _ in TARGETS if name != "zero twist after disabled"]


def test_a_short_benchmark_reports_every_figure_beside_the_reference_and_its_target(tmp_path):
    output = str(tmp_path / "benchmark.json")
    run = subprocess.run([sys.executable, os.path.join(REPO_DIR, "test", "benchmark", "benchmark.py"),
                          "--platform", "robot", "--cycles", "2", "--cpu-window", "1", "--json", output],
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True, timeout=240)
    assert run.returncode == 0, run.stdout[-3000:]
    for name in ALWAYS_MEASURED:
        assert name in run.stdout, name
    with open(output) as stream:
        section = json.load(stream)["robot"]
    for name in ALWAYS_MEASURED:
        figure = section["figures"]["node"][name]
        assert figure["p50"] <= figure["p90"] <= figure["max"], name
        assert name in section["targets"]
    for name in ("setActivation enabled reply", "CPU while disabled", "threads", "exit after SIGINT"):
        assert name in section["figures"]["reference"], name
