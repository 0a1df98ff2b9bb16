"""What the tests of `make benchmark` check of a short run, on either front-end (test/system/test_benchmark.py,
test/ros2/test_benchmark_ros2.py): every figure reported beside its target in the printed table, the JSON and the
markdown, the JSON well formed. Not the figures themselves, which depend on the machine. Pure Python."""
import json
import os
import sys

from report import COLD_FIRST_GOAL, CPU_BUSY, EXITS, FRONT_ENDS, ZERO_TWIST, targets

# What a short run measures of each subject (the reference has no yielding; on the robot's interface no zero twist).
ALWAYS_MEASURED = [target.name for target in targets(1) if target.name != ZERO_TWIST]
REFERENCE_MEASURED = ["setActivation enabled reply", "setActivation disabled reply", "set_enabled true reply",
                      "set_enabled false reply", "first goal of every part after enabled",
                      "stop of every part after disabled", "CPU while disabled", "CPU while animating", CPU_BUSY,
                      "resident memory", "threads", "open files", COLD_FIRST_GOAL] + list(EXITS)


def check_table(stdout: str, ros: int) -> None:
    lines = stdout.splitlines()
    start = next(index for index, line in enumerate(lines) if line.startswith("animateBehaviour benchmark, "))
    table = lines[start:next(index for index, line in enumerate(lines) if line.startswith("targets met: "))]
    assert table[1].split() == ["figure", "node", "p50", "/", "p90", "/", "max", "reference", "p50", "/", "p90", "/",
                                "max", "target", "met?"]
    for target in targets(ros):
        rows = [line for line in table if line.startswith(target.name + " (") or line.startswith(target.name + " ")]
        assert len(rows) == 1, target.name
        if target.name in ALWAYS_MEASURED:
            assert rows[0].rstrip().endswith(("yes", "NO", "-", ")")), rows[0]
    assert any(line.startswith("p90 at or under the reference's: ") for line in lines)


def check_json(json_file: str, platform: str, ros: int) -> dict:
    with open(json_file) as stream:
        section = json.load(stream)[platform]
    assert section["ros"] == ros
    for target in targets(ros):
        assert section["targets"][target.name] == target.as_dict()
    for subject, names in (("node", ALWAYS_MEASURED), ("reference", REFERENCE_MEASURED)):
        for name in names:
            figure = section["figures"][subject][name]
            assert 0 <= figure["p50"] <= figure["p90"] <= figure["max"], (subject, name)
            assert figure["samples"] >= 1
    for name in EXITS:
        figure = section["figures"]["node"][name]
        assert figure["stopped first"] <= figure["samples"] and figure["exit status"]
    assert set(section["met"]) == {target.name for target in targets(ros)}
    return section


def check_markdown(markdown_file: str, section: dict, platform: str, ros: int) -> str:
    with open(markdown_file) as stream:
        written = stream.read()
    begin, end = ("<!-- %s section %s -->" % (FRONT_ENDS[ros], where) for where in ("begin", "end"))
    own = written[written.index(begin):written.index(end)]
    assert "| figure | target | %s | met |" % platform in own
    assert "%s interface: %s, %d cores, Python %d.%d" % ((platform, section["time"], os.cpu_count())
                                                         + sys.version_info[:2]) in own
    for target in targets(ros):
        rows = [line for line in own.splitlines() if line.startswith("| %s " % target.name)]
        assert len(rows) == 1 and rows[0].count("|") == 5, (target.name, rows)
    assert "- %s interface: p90 at or under the reference's: " % platform in own
    return written


def check_run(stdout: str, json_file: str, markdown_file: str, platform: str, ros: int) -> dict:
    check_table(stdout, ros)
    assert "figures written to %s" % json_file in stdout
    assert "table written to %s" % markdown_file in stdout
    section = check_json(json_file, platform, ros)
    check_markdown(markdown_file, section, platform, ros)
    return section
