"""`make benchmark`'s targets, statistics and tables, for both front-ends (ROS 1: benchmark.py, ROS 2:
benchmark_ros2.py). Pure Python: no ROS.

A figure is a list of raw samples (seconds, % of a core, MB, counts) per subject (`node`, `reference`); `summary`
makes its p50, p90, max and mean in the unit of its target, `verdict` sets the node's beside its target, and a target
relative to the reference beside the reference's figure measured in the same run (doc/performance.md: "Targets")."""
import json
import os
import re
from typing import List, NamedTuple, Optional

FRONT_ENDS = {1: "ROS 1", 2: "ROS 2"}
COMMANDS = {1: "make benchmark", 2: "make benchmark ROS=2"}
# The busy configuration (doc/performance.md): short goals of few points, all parts and the base (with 10 points,
# the shipped legRepeatFactor 8 leaves leg chunks of one point: one random leg point each).
BUSY = {"gestureDuration": 0.5, "numPoints": 10, "numPointsLeg": 1}
BUSY_TEXT = ", ".join("%s %g" % item for item in BUSY.items())

RESUME = "resume after another node's goal, beyond the quiet time"
EXITS = ("exit after SIGINT", "exit after SIGTERM")
COLD_FIRST_GOAL = "first goal of every part, first enable since start-up"
ZERO_TWIST = "zero twist after disabled"
CPU_DISABLED, CPU_ANIMATING = "CPU while disabled", "CPU while animating"
CPU_BUSY = "CPU while animating, busy configuration"
PROCESS_FIGURES = ("resident memory", "threads", "open files")


class Target(NamedTuple):
    """A figure and its targets; None: no target of that kind. `mean` applies to the mean over the samples. Relative
    to the reference's figure measured in the same run: `above_reference`, the node's `statistic` at most the
    reference's plus this; `times_reference`, at most the reference's times this."""
    name: str
    unit: str
    p90: Optional[float] = None
    max: Optional[float] = None
    mean: Optional[float] = None
    above_reference: Optional[float] = None
    times_reference: Optional[float] = None
    statistic: str = "mean"  # of the relative targets

    def as_dict(self) -> dict:
        """The targets as the JSON gives them."""
        return {"unit": self.unit, "p90": self.p90, "max": self.max, "mean": self.mean,
                "above reference": self.above_reference, "times reference": self.times_reference,
                "statistic": self.statistic}

    def relative(self) -> bool:
        return (self.above_reference, self.times_reference) != (None, None)


def targets(ros: int) -> List[Target]:
    """Every figure of a front-end's benchmark and its targets: replies and stops p90 at most 10 ms on ROS 1 and
    15 ms on ROS 2, first goals p90 at most 20 ms and 40 ms; the rest alike."""
    reply, first_goal, zero_twist = (10, 20, 5) if ros == 1 else (15, 40, 15)
    return [
        Target("setActivation enabled reply", "ms", reply), Target("setActivation disabled reply", "ms", reply),
        Target("set_enabled true reply", "ms", reply), Target("set_enabled false reply", "ms", reply),
        Target("first goal of every part after enabled", "ms", first_goal),
        Target(COLD_FIRST_GOAL, "ms", first_goal),
        Target("stop of every part after disabled", "ms", reply),
        Target(ZERO_TWIST, "ms", max=zero_twist),
        Target(RESUME, "ms", max=500),
        Target(EXITS[0], "ms", max=500), Target(EXITS[1], "ms", max=500),
        Target(CPU_DISABLED, "% of a core", above_reference=0.2),
        Target(CPU_ANIMATING, "% of a core", times_reference=1.5),
        Target(CPU_BUSY, "% of a core", times_reference=1.5),
        Target("resident memory", "MB", above_reference=15, statistic="max"),
        Target("threads", "", max=30), Target("open files", ""),
    ]


def summary(values, unit):
    """p50, p90 (nearest rank, the same rule for both), max, mean and the number of samples, in `unit`."""
    if not values:
        return None
    scale = 1000.0 if unit == "ms" else 1.0
    ordered = sorted(value * scale for value in values)

    def rank(fraction):
        return ordered[int(round(fraction * (len(ordered) - 1)))]
    return {"p50": rank(0.5), "p90": rank(0.9), "max": ordered[-1], "mean": sum(ordered) / len(ordered),
            "samples": len(ordered)}


def relative_bound(target: Target, reference: Optional[dict]) -> Optional[float]:
    """The bound a relative target sets on the node's figure, from the reference's (None: not measured)."""
    if reference is None:
        return None
    if target.above_reference is not None:
        return reference[target.statistic] + target.above_reference
    return reference[target.statistic] * target.times_reference


def verdict(target: Target, figure: Optional[dict], reference: Optional[dict]) -> Optional[bool]:
    """Whether the node's figure meets every target it has (None: no target, or not measured; a target relative to
    the reference is not met without the reference's figure)."""
    if figure is None or ((target.p90, target.max, target.mean) == (None, None, None) and not target.relative()):
        return None
    met = ((target.p90 is None or figure["p90"] <= target.p90) and (target.max is None or figure["max"] <= target.max)
           and (target.mean is None or figure["mean"] <= target.mean))
    if target.relative():
        bound = relative_bound(target, reference)
        # The slack: a bound such as 0.3 + 0.2 is not exact in floating point, and CPU shares come in clock ticks.
        met = met and bound is not None and figure[target.statistic] <= bound + 1e-9
    if "stopped first" in figure:
        met = met and figure["stopped first"] == figure["samples"] and set(figure["exit status"]) == {0}
    return met


def target_text(target: Target) -> str:
    kinds = (("p90", "", target.p90), ("max", "", target.max), ("mean", "", target.mean),
             (target.statistic, "ref+", target.above_reference))
    parts = ["%s<=%s%g" % (kind, base, value) for kind, base, value in kinds if value is not None]
    if target.times_reference is not None:
        parts.append("%s<=%gxref" % (target.statistic, target.times_reference))
    if target.name in EXITS:
        parts.append("stopped first")
    return " ".join(parts) or "-"


def cell(figure: Optional[dict]) -> str:
    if figure is None:
        return "-"
    text = "%.1f / %.1f / %.1f" % (figure["p50"], figure["p90"], figure["max"])
    if "stopped first" in figure:
        text += " (stopped %d/%d)" % (figure["stopped first"], figure["samples"])
    return text


def met_text(target: Target, node: Optional[dict], reference: Optional[dict]) -> str:
    """yes, NO or -; for a relative target also the node's statistic and the bound the reference's sets."""
    met = verdict(target, node, reference)
    text = "-" if met is None else ("yes" if met else "NO")
    if node is not None and (target.mean is not None or target.relative()):
        text += " (%s %.2f" % (target.statistic, node[target.statistic])
        bound = relative_bound(target, reference) if target.relative() else None
        text += ", bound %.2f)" % bound if bound is not None else ")"
    return text


def rows_of(results: dict, ros: int) -> list:
    """Per target: (figure and unit, the node's p50 / p90 / max, the reference's, target, met)."""
    rows = []
    for target in targets(ros):
        node, reference = results["node"].get(target.name), results["reference"].get(target.name)
        name = target.name + (" (%s)" % target.unit if target.unit else "")
        rows.append((name, cell(node), cell(reference), target_text(target), met_text(target, node, reference)))
    return rows


def table(platform: str, results: dict, ros: int) -> str:
    rows = [("figure", "node p50 / p90 / max", "reference p50 / p90 / max", "target", "met?")] + rows_of(results, ros)
    widths = [max(len(row[column]) for row in rows) for column in range(4)]
    client = "rospy" if ros == 1 else "rclpy"
    lines = ["animateBehaviour benchmark, %s, platform %s: the node beside a minimal %s reference node"
             % (FRONT_ENDS[ros], platform, client)]
    lines += ["  ".join(text.ljust(width) for text, width in zip(row, widths)) + "  " + row[4] for row in rows]
    return "\n".join(lines)


def results_of(raw: dict, ros: int) -> dict:
    """The raw samples of each subject summarised, per figure; the exits with `stopped first` and `exit status`."""
    units = {target.name: target.unit for target in targets(ros)}
    results = {}
    for subject, measured in raw.items():
        figures = {}
        for name, values in measured["figures"].items():
            figure = summary(values, units[name])
            if figure is None:
                continue
            if name in EXITS:
                figure["stopped first"] = sum(measured["stopped first"][name])
                figure["exit status"] = measured["exit status"][name]
            figures[name] = figure
        results[subject] = figures
    return results


def met_of(results: dict, ros: int) -> dict:
    return {target.name: verdict(target, results["node"].get(target.name), results["reference"].get(target.name))
            for target in targets(ros)}


def met_line(met: dict) -> str:
    """Which targets the node met, in one line."""
    judged = [name for name, value in met.items() if value is not None]
    missed = [name for name in judged if not met[name]]
    return "targets met: %d of %d%s" % (len(judged) - len(missed), len(judged),
                                        "; not met: " + ", ".join(missed) if missed else "")


def floor_line(results: dict, ros: int) -> str:
    """Which timed figures (p90 targets: replies, first goals, stop) the node gives within the reference's own p90 of
    the same run, the client library's floor on the machine at hand, in one line."""
    compared = [target.name for target in targets(ros) if target.p90 is not None
                and target.name in results["node"] and target.name in results["reference"]]
    above = ["%s (%.1f, the reference %.1f)" % (name, results["node"][name]["p90"], results["reference"][name]["p90"])
             for name in compared if results["node"][name]["p90"] > results["reference"][name]["p90"]]
    listed = "; above: " + ", ".join(above) if above else ""
    return "p90 at or under the reference's: %d of %d%s" % (len(compared) - len(above), len(compared), listed)


def soak_table(result: dict) -> str:
    lines = ["soak: %g s of short goals (%d enable/disable cycles), then %d quick enable/disable cycles"
             % (result["soak seconds"], result["soak cycles"], result["growth cycles"]),
             "%-20s %12s %12s %12s %14s %14s" % ("figure", "start", "after soak", "soak growth", "after cycles",
                                                 "cycles growth")]
    for key in result["start"]:
        lines.append("%-20s %12.1f %12.1f %+12.1f %14.1f %+14.1f" % (
            key + (" (MB)" if key == "resident memory" else ""), result["start"][key], result["after soak"][key],
            result["soak growth"][key], result["after cycles"][key], result["cycles growth"][key]))
    return "\n".join(lines)


HEADER = ["<!-- Written by `make benchmark` (test/benchmark/). Do not edit: run it again. Each front-end's run "
          "rewrites its own section only. -->", "", "# Latest benchmark", "",
          "Each cell: the node's p50 / p90 / max, then the reference node's (ref), measured in the same run; met: "
          "whether the node meets the target (for a target relative to the reference, the node's figure and the "
          "bound the reference's sets). The busy configuration: %s, all parts and the base; the other figures: "
          "the shipped configuration. Targets and method: [performance.md](performance.md)." % BUSY_TEXT]


def section_markdown(document: dict, ros: int) -> str:
    """One front-end's section: the figures of every platform in `document` (the JSON's sections), side by side."""
    platforms = list(document)
    rows = {platform: rows_of(document[platform]["figures"], ros) for platform in platforms}
    lines = ["## %s (`%s`)" % (FRONT_ENDS[ros], COMMANDS[ros]), ""]
    if not platforms:
        return "\n".join(lines + ["Not run yet."])
    for platform in platforms:
        section = document[platform]
        node_python = section.get("node python", "the same")
        lines.append("- %s interface: %s, %s cores, Python %s (the node's: %s), %d cycles, %g s CPU windows, %d "
                     "exits per signal" % (platform, section["time"], section["cores"], section.get("python", "?"),
                                           node_python, section["cycles"], section["cpu window"], section["exit runs"]))
    lines += ["", "| figure | target | " + " | ".join("%s | met" % platform for platform in platforms) + " |",
              "|---|---|" + "---|---|" * len(platforms)]
    for index in range(len(targets(ros))):
        name, _, _, target_cell, _ = rows[platforms[0]][index]
        cells = ["%s%s | %s" % (row[1], "" if row[2] == "-" else "; ref %s" % row[2], row[4])
                 for row in (rows[platform][index] for platform in platforms)]
        lines.append("| %s | %s | %s |" % (name, target_cell, " | ".join(cells)))
    lines.append("")
    lines += ["- %s interface: %s." % (platform, floor_line(document[platform]["figures"], ros))
              for platform in platforms]
    for platform in platforms:
        if "soak" in document[platform]:
            lines += ["", "Growth, %s interface:" % platform, "", "```", soak_table(document[platform]["soak"]), "```"]
    return "\n".join(lines)


def _marker(ros: int, where: str) -> str:
    return "<!-- %s section %s -->" % (FRONT_ENDS[ros], where)


def markdown(document: dict, ros: int, existing: str = "") -> str:
    """doc/benchmark-latest.md with the section of front-end `ros` made from `document`, the other front-end's
    section kept as it is in `existing` (the file as it was)."""
    lines = list(HEADER)
    for front_end in FRONT_ENDS:
        if front_end == ros:
            section = section_markdown(document, ros)
        else:
            pattern = re.escape(_marker(front_end, "begin")) + r"\n(.*?)\n" + re.escape(_marker(front_end, "end"))
            found = re.search(pattern, existing, re.DOTALL)
            section = found.group(1) if found else section_markdown({}, front_end)
        lines += ["", _marker(front_end, "begin"), section, _marker(front_end, "end")]
    return "\n".join(lines) + "\n"


def write_outputs(section: dict, platform: str, ros: int, json_file: Optional[str], markdown_file: Optional[str]):
    """Adds the platform's section to the JSON (one section per platform) and rewrites the front-end's section of
    the markdown file from every platform in the JSON."""
    document = {}
    if json_file and os.path.exists(json_file):
        with open(json_file) as stream:
            document = json.load(stream)
    document[platform] = section
    if json_file:
        with open(json_file, "w") as stream:
            json.dump(document, stream, indent=1)
        print("figures written to %s" % json_file)
    if markdown_file:
        existing = ""
        if os.path.exists(markdown_file):
            with open(markdown_file) as stream:
                existing = stream.read()
        with open(markdown_file, "w") as stream:
            stream.write(markdown(document, ros, existing))
        print("table written to %s" % markdown_file)
