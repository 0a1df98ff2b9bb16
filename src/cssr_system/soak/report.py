"""The soak's report (doc/soak.md): each figure beside its target as text, `doc/soak-latest.md` for the front-ends
that have a result (the page's sections of the others kept as they were), and a plot of resident memory, CPU and
threads over time with the churn marked. Pure Python: no ROS (matplotlib only when plotting).

python3 -m cssr_system.soak.report --markdown doc/soak-latest.md RESULT.json... (each a run's JSON, its front-end in
its "ros" field)
"""
import argparse
import json
import os
import re
import sys
from typing import Dict, List, Optional

from cssr_system.soak.figures import context, memory_slopes, number, table
from cssr_system.soak.schedule import DISABLE, ENABLE, GESTURE, RESTART


def text(result: dict) -> str:
    """Each figure beside its target, and what the run did."""
    rows = [("figure", "value", "target", "met?")] + table(result)
    widths = [max(len(row[column]) for row in rows) for column in range(3)]
    about = context(result)
    lines = ["soak, ROS %s: %s, %s" % (result.get("ros", "?"), length_text(about), churn_text(about))]
    lines += ["  ".join(cell.ljust(width) for cell, width in zip(row, widths)) + "  " + row[3] for row in rows]
    return "\n".join(lines)


def length_text(about: dict) -> str:
    """How long the run went, its warm-up, and whether it was cut short."""
    text = "%.0f minutes, of which %g of warm-up are not judged" % (about["minutes"], about["warm-up minutes"])
    if about["minutes"] < about["planned minutes"] - 0.5:
        text += " (cut short: %g were planned)" % about["planned minutes"]
    return text


def churn_text(about: dict) -> str:
    churn = about["churn"]
    return ("%d enables, %d disables, %d live settings, %d animate goals (%d cancelled), %d gestures, %d restarts of "
            "the simulated Pepper, %d departures of the base's listener; %d replies (%d failed)" % (
                churn.get("enable", 0), churn.get("disable", 0), churn.get("setting", 0), churn.get("animate", 0),
                churn.get("cancel", 0), churn.get("gesture", 0), churn.get("restart", 0), churn.get("listener", 0) // 2,
                about["replies"], about["failed replies"]))


SECTION = re.compile(r"^## ROS (.+)$", re.MULTILINE)


def sections(page: str) -> Dict[str, str]:
    """A report page's sections by front-end ("1", "1, simulated clock", "2"), each from its heading on."""
    starts = list(SECTION.finditer(page))
    ends = [match.start() for match in starts[1:]] + [len(page)]
    return {match.group(1): page[match.start():end].rstrip("\n") + "\n" for match, end in zip(starts, ends)}


def markdown(results: Dict[str, dict], plots: Dict[str, str], kept: Optional[Dict[str, str]] = None) -> str:
    """doc/soak-latest.md: one section per front-end (`results` by "1" or "2"), its plot beside it; `kept`: the
    sections of front-ends without a result this time, from the page as it was (a run of one front-end keeps the
    others' latest)."""
    lines = ["<!-- Written by `make soak` (cssr_system.soak.report). Do not edit: run it again. -->", "",
             "# Latest soak", "", "What the soak does and how to read it: [soak.md](soak.md).", ""]
    kept = {ros: section for ros, section in (kept or {}).items() if ros not in results}
    for ros in sorted(set(results) | set(kept)):
        if ros in kept:
            lines.append(kept[ros])
            continue
        result = results[ros]
        about = context(result)
        lines += ["## ROS %s" % ros, "",
                  "- %s, %s, %s cores; %s" % (result.get("started", "?"), result.get("configuration", "?"),
                                              result.get("cores", "?"), length_text(about)),
                  "- churn: " + churn_text(about),
                  "- process at the start and at the end: " + process_text(about),
                  "- node goals rejected, aborted or lost by the churn (a restart, a gesture): %d; error events in the "
                  "log: %d"
                  % (about["provoked"], about["log errors"]),
                  "- the base's listener: " + listener_text(about),
                  "- growth over the judged part: " + growth_text(result), "",
                  "| figure | value | target | met |", "|---|---|---|---|"]
        lines += ["| %s | %s | %s | %s |" % row for row in table(result)]
        if ros in plots:
            lines += ["", "![resident memory, CPU and threads, ROS %s](%s)" % (ros, plots[ros])]
        lines.append("")
    return "\n".join(lines)


def listener_text(about: dict) -> str:
    seen = about["base listener seen"]
    if seen is None:
        return "-"
    return "left %d times on its own; the node saw it leave %d times and come back %d times" % (
        about["churn"].get("listener", 0) // 2, seen["left"], seen["back"])


def growth_text(result: dict) -> str:
    """Resident memory's slope beside those of its parts: where it grows."""
    slopes = memory_slopes(result)
    if slopes["resident memory"] is None:
        return "-"
    text = "resident memory %s MB/h (anonymous %s, file-backed %s)" % tuple(
        number(slopes[key]) for key in ("resident memory", "resident anonymous", "resident file"))
    if slopes["malloc in use"] is not None:
        text += "; malloc in use %s MB/h, free but kept %s MB/h" % (
            number(slopes["malloc in use"]), number(slopes["malloc free"]))
    if slopes["python blocks"] is not None:
        text += "; Python's allocated blocks %+.0f an hour" % slopes["python blocks"]
    return text


def process_text(about: dict) -> str:
    first, last = about["first"], about["last"]
    if first is None:
        return "-"
    return "RSS %.1f -> %.1f MB, threads %d -> %d, open files %d -> %d; CPU mean %s %% of a core" % (
        first["resident memory"], last["resident memory"], first["threads"], last["threads"], first["open files"],
        last["open files"], number(about["cpu mean"]))


def plot(result: dict, path: str) -> str:
    """Resident memory, CPU and threads over time (minutes), the enabled spells shaded, restarts as red lines,
    gestures as grey ticks and the end of the warm-up dashed."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as pyplot
    samples = result["samples"]
    minutes = [sample["t"] / 60.0 for sample in samples]
    series = (("resident memory", "RSS (MB)"), ("cpu", "CPU (% of a core)"), ("threads", "threads"))
    figure, axes = pyplot.subplots(len(series), 1, figsize=(10, 7), sharex=True)
    for axis, (key, label) in zip(axes, series):
        points = [(at, sample[key]) for at, sample in zip(minutes, samples) if sample[key] is not None]
        axis.plot([at for at, _ in points], [value for _, value in points], linewidth=1.0)
        axis.set_ylabel(label)
        axis.axvline(result["warm up"] / 60.0, color="black", linestyle="--", linewidth=0.8)
        _mark_churn(axis, result)
    axes[-1].set_xlabel("minutes (dashed: end of the warm-up; green: enabled; red: simulated Pepper restarted; "
                        "grey: gestures)", fontsize=8)
    figure.suptitle("animateBehaviour soak, ROS %s" % result.get("ros", "?"))
    figure.tight_layout()
    figure.savefig(path, dpi=80)
    pyplot.close(figure)
    return path


def enabled_spans(marks) -> List[tuple]:
    """(start, end) in minutes of each spell between an enable and the next disable (or the last mark)."""
    spans, since = [], None
    for at, action, _detail in marks:
        if action == ENABLE and since is None:
            since = at
        elif action == DISABLE and since is not None:
            spans.append((since / 60.0, at / 60.0))
            since = None
    if since is not None and marks:
        spans.append((since / 60.0, marks[-1][0] / 60.0))
    return spans


def _mark_churn(axis, result: dict) -> None:
    for start, end in enabled_spans(result["marks"]):
        axis.axvspan(start, end, color="green", alpha=0.08, linewidth=0)
    for at, action, _detail in result["marks"]:
        if action == RESTART:
            axis.axvline(at / 60.0, color="red", linewidth=0.8, alpha=0.6)
        elif action == GESTURE:
            axis.axvline(at / 60.0, color="grey", linewidth=0.4, alpha=0.3)


def plot_name(ros: str) -> str:
    """The plot's file name of a run on ROS `ros` (e.g. "1, simulated clock": soak-latest-ros1-simulated-clock.png)."""
    return "soak-latest-ros%s.png" % re.sub(r"[^0-9a-z]+", "-", ros.lower()).strip("-")


def main(argv: List[str]) -> int:
    parser = argparse.ArgumentParser(description="The soak's report from its results (JSON).")
    parser.add_argument("results", nargs="+", help="a run's JSON; a missing one is left out")
    parser.add_argument("--markdown", required=True, help="the page to write (its plots beside it)")
    arguments = parser.parse_args(argv)
    results, plots = {}, {}
    for path in arguments.results:
        if os.path.exists(path):
            with open(path) as stream:
                result = json.load(stream)
            results[str(result.get("ros", "?"))] = result
    folder = os.path.dirname(os.path.abspath(arguments.markdown))
    for ros, result in results.items():
        name = plot_name(ros)
        plot(result, os.path.join(folder, name))
        plots[ros] = name
    kept = {}
    if os.path.exists(arguments.markdown):
        with open(arguments.markdown) as stream:
            kept = sections(stream.read())
    with open(arguments.markdown, "w") as stream:
        stream.write(markdown(results, plots, kept))
    print("report written to %s" % arguments.markdown)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
