"""The gesture race (doc/soak.md, "The gesture race"): another node's gestures on every controller of the node, each
sent at a random moment against the node's goals there, half of them aimed at the node's next goal boundary (just
before, at, or just after it), the others anywhere in a goal period. It counts the gestures that end other than
SUCCEEDED (README: "Sharing the robot": none should), and times, from the controllers' status lists as the race
sees them, each gesture's acceptance against the node's goals before and after it. The front-ends' drivers
(cssr_system.ros1.gesture_race, cssr_system.ros2.gesture_race) start the processes and hand the status lists and
the gestures' ends here. Pure Python: no ROS.
"""
import argparse
import json
import os
import random
import threading
import time
from typing import Callable, Dict, Iterable, List, Optional, Sequence, Tuple

from cssr_system.pepper.joint_table import PARTS
from cssr_system.soak.processes import BUSY

NEAR = 0.02  # s: a gesture accepted this close after the node's goal start counts as "just after" it
AIM = 0.1  # s either side of the node's predicted next goal boundary that an aimed gesture leaves in
GESTURE_DURATION = 0.8  # s
RESUMED_STARTS = 2  # the node's goals that start on a part after a gesture's end before the next gesture is timed
WAIT = 40.0  # s at most for the node's goals to start (a breath takes seconds), or for a gesture's end
SUCCEEDED = "SUCCEEDED"
PERIOD_BOUNDS = (0.2, 20.0)  # s: the node's goal period taken for a prediction, clamped (a breathing goal: ~16 s)
RACE_PARTS = ("RArm", "LArm", "RHand", "LHand", "Leg")
QUIET_TIME = 0.5  # s: the node's yieldQuietTime in the race


def gesture_points(part: str, duration: float = GESTURE_DURATION) -> List[Tuple[float, Tuple[float, ...]]]:
    """(time, positions) of a small gesture of `part`: away from its centre and back, ending at rest there."""
    centre = PARTS[part].centre
    away = tuple(value + (0.08 if index == 0 else 0.0) for index, value in enumerate(centre))
    return [(0.4 * duration, away), (duration, tuple(centre))]


class Gesture:
    """`resent`: sent again at once because the first try did not succeed (the README's advice to another node)."""

    def __init__(self, part: str, aimed: bool, sent_at: float, aim_offset: Optional[float],
                 resent: bool = False) -> None:
        self.part, self.aimed, self.sent_at, self.aim_offset, self.resent = part, aimed, sent_at, aim_offset, resent
        self.accepted_at: Optional[float] = None  # first seen running on the controller's status
        self.state: Optional[str] = None  # its end; None: none came
        self.ended_at: Optional[float] = None


class PartRace:
    """One controller: the node's goals' starts and the gestures, from its status lists. Safe from any thread."""

    def __init__(self, part: str) -> None:
        self.part = part
        self.node_starts: List[float] = []
        self.gestures: List[Gesture] = []
        self._regular: Optional[float] = None  # the latest interval between two of the node's goals, no gesture between
        self._node_seen: set = set()
        self._changed = threading.Condition()

    def status_list(self, now: float, node_running: Iterable[str], gesture_running: bool) -> None:
        """One status list received at `now`: the ids of the node's goals running, and whether a gesture runs."""
        with self._changed:
            for goal_id in node_running:
                if goal_id not in self._node_seen:
                    self._node_seen.add(goal_id)
                    self._note_start(now)
            current = self.gestures[-1] if self.gestures else None
            if gesture_running and current is not None and current.accepted_at is None:
                current.accepted_at = now
            self._changed.notify_all()

    def _note_start(self, now: float) -> None:
        latest = self.node_starts[-1] if self.node_starts else None
        ended = self.gestures[-1].ended_at if self.gestures else None
        if latest is not None and (not self.gestures or (ended is not None and ended < latest)):
            self._regular = now - latest
        self.node_starts.append(now)

    def begin(self, gesture: Gesture) -> None:
        with self._changed:
            self.gestures.append(gesture)

    def ended(self, state: str, now: float) -> None:
        with self._changed:
            self.gestures[-1].state, self.gestures[-1].ended_at = state, now
            self._changed.notify_all()

    def wait_for(self, condition: Callable[[], bool], timeout: float = WAIT) -> bool:
        with self._changed:
            return self._changed.wait_for(condition, timeout)

    def period(self) -> float:
        """The node's goal period on the part, for a prediction: the latest interval between two of its goals with
        no gesture between them (the first goal after a gesture may differ), else 1 s."""
        with self._changed:
            period = 1.0 if self._regular is None else self._regular
        return min(max(period, PERIOD_BOUNDS[0]), PERIOD_BOUNDS[1])


def play(race: PartRace, count: int, send: Callable[[str], None], rng: random.Random,
         clock: Callable[[], float] = time.monotonic, stop: Optional[threading.Event] = None,
         resend: bool = False) -> None:
    """`count` gestures on `race`'s part, one at a time: each once the node animates the part again (RESUMED_STARTS
    of its goals started since the last gesture's end), aimed or not in turn; `send(part)` sends one, whose end
    comes to `race.ended`. `resend`: a gesture that did not succeed is sent again at once, once."""
    stop = stop or threading.Event()
    for number in range(count):
        starts = len(race.node_starts)
        if stop.is_set() or not race.wait_for(lambda: len(race.node_starts) >= starts + RESUMED_STARTS):
            return
        aimed = number % 2 == 0
        latest, period = race.node_starts[-1], race.period()
        offset = rng.uniform(-AIM, AIM) if aimed else None
        at = latest + period + offset if aimed else clock() + rng.uniform(0.0, period)
        time.sleep(max(0.0, at - clock()))
        race.begin(Gesture(race.part, aimed, clock(), offset))
        send(race.part)
        race.wait_for(lambda: race.gestures[-1].state is not None, GESTURE_DURATION + WAIT)
        if resend and race.gestures[-1].state != SUCCEEDED:
            race.begin(Gesture(race.part, aimed, clock(), offset, resent=True))
            send(race.part)
            race.wait_for(lambda: race.gestures[-1].state is not None, GESTURE_DURATION + WAIT)


def intervals(race: PartRace) -> List[Tuple[Gesture, Optional[float], Optional[float]]]:
    """Each accepted gesture with the time from the node's last goal start before its acceptance, and from its
    acceptance to the node's next goal start on the part (None: none)."""
    rows = []
    for gesture in race.gestures:
        if gesture.accepted_at is None:
            rows.append((gesture, None, None))
            continue
        before = [start for start in race.node_starts if start <= gesture.accepted_at]
        after = [start for start in race.node_starts if start > gesture.accepted_at]
        rows.append((gesture, gesture.accepted_at - before[-1] if before else None,
                     after[0] - gesture.accepted_at if after else None))
    return rows


def summary(races: Sequence[PartRace]) -> Dict[str, object]:
    """The race's figures: gestures sent and lost (ending other than SUCCEEDED, or not at all), by state and by
    part; the smallest interval from a gesture's acceptance to the node's next goal on that part; the aimed
    gestures' offsets from the predicted boundary."""
    every = [row for race in races for row in intervals(race)]
    rows = [row for row in every if not row[0].resent]
    resent = [gesture for gesture, _, _ in every if gesture.resent]
    lost = [gesture for gesture, _, _ in rows if gesture.state != SUCCEEDED]
    next_goals = [after for _, _, after in rows if after is not None]
    offsets = [gesture.aim_offset for gesture, _, _ in rows if gesture.aim_offset is not None]
    just_after = sum(before is not None and before <= NEAR for _, before, _ in rows)
    ways = sorted(gesture.accepted_at - gesture.sent_at for gesture, _, _ in rows if gesture.accepted_at is not None)
    states: Dict[str, int] = {}
    for gesture in lost:
        states[str(gesture.state)] = states.get(str(gesture.state), 0) + 1
    return {"gestures": len(rows), "lost": len(lost), "lost by state": states, "resent": len(resent),
            "lost when resent": sum(gesture.state != SUCCEEDED for gesture in resent),
            "by part": {race.part: sum(not gesture.resent for gesture in race.gestures) for race in races},
            "aimed": len(offsets), "aimed within 20 ms of the boundary": sum(abs(value) <= 0.02 for value in offsets),
            "smallest acceptance to our next goal, s": round(min(next_goals), 4) if next_goals else None,
            "smallest our last goal to acceptance, s": round(min(before for _, before, _ in rows
                                                                 if before is not None), 4)
            if any(before is not None for _, before, _ in rows) else None,
            "sent to seen running, ms": {"median": milliseconds(ways, 0.5), "99%": milliseconds(ways, 0.99),
                                         "largest": milliseconds(ways, 1.0)},
            "accepted within 20 ms after the node's goal start": just_after,
            "lost gestures": [{"part": gesture.part, "state": gesture.state, "aimed": gesture.aimed,
                               "offset": gesture.aim_offset} for gesture in lost],
            "every gesture": [[gesture.part, gesture.state, gesture.aim_offset, before, after, gesture.resent]
                              for gesture, before, after in every]}


def milliseconds(values: Sequence[float], fraction: float) -> Optional[float]:
    """The value at `fraction` of the sorted `values`, in ms (None: no values)."""
    return round(1000.0 * values[min(len(values) - 1, int(fraction * len(values)))], 1) if values else None


def text(result: Dict[str, object]) -> str:
    lines = ["gestures sent: %d; lost (not SUCCEEDED): %d %s" % (
        result["gestures"], result["lost"], result["lost by state"] or ""),
             "by part: %s" % ", ".join("%s %d" % item for item in sorted(result["by part"].items())),
             "aimed at the node's next goal boundary: %d (%d within 20 ms of it)" % (
                 result["aimed"], result["aimed within 20 ms of the boundary"]),
             "smallest interval from a gesture's acceptance to the node's next goal on that part: %s s" %
             result["smallest acceptance to our next goal, s"],
             "smallest interval from the node's last goal to a gesture's acceptance: %s s (%d within 20 ms)" % (
                 result["smallest our last goal to acceptance, s"],
                 result["accepted within 20 ms after the node's goal start"]),
             "from a gesture's send to the race seeing it running on the status: %s ms" % ", ".join(
                 "%s %s" % item for item in result["sent to seen running, ms"].items()),
             "foreign gestures lost: %d" % result["lost"]]
    if result["resent"]:
        lines.append("resent at once: %d, of which lost again: %d" % (result["resent"], result["lost when resent"]))
    return "\n".join(lines)


def run_parts(parts: Sequence[str], count: int, send: Callable[[str], None], races: Dict[str, PartRace],
              seed: int = 1, resend: bool = False) -> Dict[str, object]:
    """`count` gestures in all, spread over `parts` (a thread each, side by side), then the summary."""
    threads = []
    for index, part in enumerate(parts):
        share = count // len(parts) + (1 if index < count % len(parts) else 0)
        thread = threading.Thread(target=play, args=(races[part], share, send, random.Random(seed * 100 + index)),
                                  kwargs=dict(resend=resend), name="gestures " + part, daemon=True)
        thread.start()
        threads.append(thread)
    for thread in threads:
        thread.join()
    return summary([races[part] for part in parts])


def arguments(argv: List[str]) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description="the gesture race (doc/soak.md)")
    parser.add_argument("--gestures", type=int, default=100, help="gestures in all, spread over the parts")
    parser.add_argument("--style", choices=("random", "breathing"), default="random", help="the node's motionStyle")
    parser.add_argument("--parts", default=",".join(RACE_PARTS), help="the parts that get gestures")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--resend", action="store_true",
                        help="send a gesture that did not succeed again at once (README: \"Sharing the robot\")")
    parser.add_argument("--folder", required=True, help="the run's folder: output of every process, the log")
    parser.add_argument("--json", required=True, help="the run's result")
    return parser.parse_args(argv)


def node_parameters(style: str) -> dict:
    """The soak's busy configuration (a goal on every part about every second) in `style`, with a short quiet time:
    more gestures a minute, the same race at each goal boundary."""
    return dict(BUSY, motionStyle=style, yieldQuietTime=QUIET_TIME)


def withheld_goals(log_file: str) -> int:
    """The node's goals that its last look withheld (goal_finished WITHHELD in its log)."""
    if not os.path.exists(log_file):
        return 0
    with open(log_file) as log:
        return sum(1 for line in log if " goal_finished " in line and '"state": "WITHHELD"' in line)


def run(driver, options: argparse.Namespace, ros: str) -> int:
    """The race on `driver` (its processes not started yet): 0 when every gesture SUCCEEDED."""
    parts = [part for part in options.parts.split(",") if part]
    started = time.monotonic()
    driver.start(parts)
    driver.activate("enabled")
    result = run_parts(parts, options.gestures, driver.send, driver.races, options.seed, options.resend)
    driver.activate("disabled")
    result.update(ros=ros, style=options.style, minutes=round((time.monotonic() - started) / 60.0, 2),
                  load=os.getloadavg()[0], cores=os.cpu_count(),
                  withheld=withheld_goals(os.path.join(options.folder, "node.log")))
    with open(options.json, "w") as output:
        json.dump(result, output, indent=1)
    print("ROS %s, style %s: %s\nthe node's goals withheld by its last look: %d" % (
        ros, options.style, text(result), result["withheld"]), flush=True)
    return 0 if result["lost when resent" if options.resend else "lost"] == 0 else 1
