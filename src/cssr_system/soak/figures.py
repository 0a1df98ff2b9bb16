"""A soak's figures beside their targets (doc/soak.md), from a run's result (soak.run.SoakRun.result), over the
samples after its warm-up: the growth of resident memory (least-squares slope), the spread of threads and open
files, the log's largest size, tracebacks, the node's goals rejected or gone wrong without a restart to blame, the
animate goals and gestures that did not end as expected, and the replies' 99th percentile, over the run and over its
worst 10-minute window. Pure Python: no ROS.
"""
from typing import List, NamedTuple, Optional, Sequence

from cssr_system.animate_behaviour.event_log import DEFAULT_MAX_BYTES

WINDOW = 600.0  # s of each window of replies
LOG_BOUND = 2 * DEFAULT_MAX_BYTES + 64 * 1024  # the log and its one rotated copy, and a line being written


class Target(NamedTuple):
    name: str
    unit: str
    bound: float  # the figure at most this


TARGETS = (Target("resident memory growth", "MB/h", 0.5), Target("threads, max - min", "", 4),
           Target("open files, max - min", "", 8), Target("log and its rotated copy, largest", "MB", LOG_BOUND / 1e6),
           Target("tracebacks", "", 0), Target("node goals rejected, not by a restart", "", 0),
           Target("node goals aborted or lost, not by a restart", "", 0),
           Target("animate goals and gestures not ending as expected", "", 0), Target("foreign gestures lost", "", 0),
           Target("replies p99", "ms", 50), Target("replies p99, worst 10-minute window", "ms", 50))


def slope_per_hour(times: Sequence[float], values: Sequence[float]) -> Optional[float]:
    """The least-squares slope of `values` over `times` (s), per hour; None with fewer than two times."""
    count = len(times)
    if count < 2:
        return None
    mean_t, mean_v = sum(times) / count, sum(values) / count
    spread = sum((t - mean_t) ** 2 for t in times)
    if spread == 0.0:
        return None
    return 3600.0 * sum((t - mean_t) * (v - mean_v) for t, v in zip(times, values)) / spread


def percentile(values: Sequence[float], fraction: float) -> Optional[float]:
    """Nearest rank (the benchmark's rule); None for no values."""
    if not values:
        return None
    ordered = sorted(values)
    return ordered[int(round(fraction * (len(ordered) - 1)))]


def judged_samples(result: dict) -> List[dict]:
    return [sample for sample in result["samples"] if sample["t"] >= result["warm up"]]


MEMORY_PARTS = ("resident anonymous", "resident file", "malloc in use", "malloc free", "python blocks")


def memory_slopes(result: dict) -> dict:
    """The least-squares slope per hour, over the judged samples, of resident memory and of what makes it up (by
    kind of page, and what the node's allocators hold: soak.run.HEAP_KEYS); None where not measured."""
    samples = judged_samples(result)
    slopes = {}
    for key in ("resident memory",) + MEMORY_PARTS:
        measured = [(sample["t"], sample[key]) for sample in samples if sample.get(key) is not None]
        slopes[key] = slope_per_hour([at for at, _ in measured], [value for _, value in measured])
    return slopes


def spread(samples: Sequence[dict], key: str) -> Optional[float]:
    values = [sample[key] for sample in samples]
    return max(values) - min(values) if values else None


def unexpected_ends(result: dict) -> List[str]:
    """Each animate goal or gesture that did not end as expected, with how it ended."""
    wrong = []
    for name, goal in sorted(result["goals"].items()):
        expect = goal.get("expect")
        got = goal.get("reason") if name.startswith("animate") else goal.get("status")
        if got != expect:
            wrong.append("%s: expected %s, got %s" % (name, expect, got if "status" in goal else "no end"))
    return wrong


def gestures_lost(result: dict) -> int:
    """Another node's gestures that did not end SUCCEEDED (README: "Sharing the robot": none may)."""
    return sum(1 for name, goal in result["goals"].items()
               if name.startswith("gesture") and goal.get("status") != "SUCCEEDED")


def worst_window_p99(replies: Sequence[list], warm_up: float) -> Optional[float]:
    windows = {}
    for at, _what, seconds, _success in replies:
        if at >= warm_up:
            windows.setdefault(int((at - warm_up) // WINDOW), []).append(seconds)
    values = [percentile(window, 0.99) for window in windows.values()]
    return max(values) if values else None


def figures(result: dict) -> dict:
    """Each target's figure (None when not measured), by the target's name."""
    samples = judged_samples(result)
    judged_replies = [reply for reply in result["replies"] if reply[0] >= result["warm up"]]
    p99 = percentile([reply[2] for reply in judged_replies], 0.99)
    worst = worst_window_p99(result["replies"], result["warm up"])
    gone_wrong = result["node goals gone wrong"]
    values = [slope_per_hour([sample["t"] for sample in samples], [sample["resident memory"] for sample in samples]),
              spread(samples, "threads"), spread(samples, "open files"),
              max(sample["log bytes"] for sample in result["samples"]) / 1e6 if result["samples"] else None,
              result["tracebacks"], sum(state == "REJECTED" and not provoked for _, _, state, provoked in gone_wrong),
              sum(state != "REJECTED" and not provoked for _, _, state, provoked in gone_wrong),
              len(unexpected_ends(result)), gestures_lost(result), None if p99 is None else 1000.0 * p99,
              None if worst is None else 1000.0 * worst]
    return {target.name: value for target, value in zip(TARGETS, values)}


def verdicts(result: dict) -> List[tuple]:
    """(target, figure, met) of every target; met is None when the figure was not measured."""
    measured = figures(result)
    return [(target, measured[target.name],
             None if measured[target.name] is None else measured[target.name] <= target.bound + 1e-9)
            for target in TARGETS]


def context(result: dict) -> dict:
    """What else the run tells: its length so far (a run cut short tells its checkpoint's), the process figures at
    the start and at the end, the churn done."""
    samples = result["samples"]
    cpu = [sample["cpu"] for sample in judged_samples(result) if sample["cpu"] is not None]
    actions = {}
    for _at, action, _detail in result["marks"]:
        actions[action] = actions.get(action, 0) + 1
    return {"minutes": samples[-1]["t"] / 60.0 if samples else 0.0, "planned minutes": result["seconds"] / 60.0,
            "warm-up minutes": result["warm up"] / 60.0,
            "first": samples[0] if samples else None, "last": samples[-1] if samples else None,
            "cpu mean": sum(cpu) / len(cpu) if cpu else None, "churn": actions,
            "replies": len(result["replies"]), "failed replies": sum(not reply[3] for reply in result["replies"]),
            "goals": len(result["goals"]), "log errors": result["log errors"],
            "provoked": sum(bool(provoked) for *_, provoked in result["node goals gone wrong"]),
            "base listener seen": result.get("base listener seen")}


def number(value: Optional[float]) -> str:
    return "-" if value is None else ("%d" % value if float(value).is_integer() else "%.2f" % value)


def table(result: dict) -> List[tuple]:
    """(figure, value, target, met) rows as text."""
    return [(target.name + (" (%s)" % target.unit if target.unit else ""), number(value),
             "<= %s" % number(target.bound), "-" if met is None else ("yes" if met else "NO"))
            for target, value, met in verdicts(result)]
