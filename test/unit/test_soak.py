"""The soak's ROS-free parts (doc/soak.md): its churn schedule, the least-squares slope and the percentiles, the
verdicts against the targets, the log read across a rotation, a run played on a fake driver, and the report."""
import json
import os
import subprocess
import sys
import time

import pytest

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.event_log import EventLog, format_log_line, format_timestamp
from cssr_system.soak import figures, report, run, schedule
from cssr_system.soak.run import LogTail, SoakRun, count_tracebacks

HOUR = 3600.0


def test_the_schedule_churns_as_described_and_keeps_goals_clear_of_restarts():
    steps = schedule.churn_schedule(HOUR, seed=3)
    assert steps == schedule.churn_schedule(HOUR, seed=3), "a seed repeats a run"
    assert [step.at for step in steps] == sorted(step.at for step in steps)
    switches = [step for step in steps if step.action in (schedule.ENABLE, schedule.DISABLE)]
    assert [step.action for step in switches[:4]] == ["enable", "disable", "enable", "disable"]
    gaps = [later.at - earlier.at for earlier, later in zip(switches, switches[1:])]
    assert min(gaps) >= 15.0 and max(gaps) <= 30.0
    settings = [step for step in steps if step.action == schedule.SETTING]
    assert {step.detail["name"] for step in settings} >= {"intensity", "tempo", "style", "base", "hands", "leg"}
    assert len(settings) == int(HOUR / 10.0) - 1
    restarts = [step.at for step in steps if step.action == schedule.RESTART]
    assert restarts == [300.0, 900.0, 1500.0, 2100.0, 2700.0, 3300.0]
    goals = [step for step in steps if step.action in (schedule.ANIMATE, schedule.GESTURE)]
    assert all(abs(step.at - restart) >= schedule.CLEARANCE for step in goals for restart in restarts)
    expected = {step.detail.get("expect") for step in goals}
    assert expected == {None, "duration elapsed", "cancelled", "replaced"}
    gestures = [step.at for step in steps if step.action == schedule.GESTURE]
    minutes = [int(at // schedule.GESTURE_PERIOD) for at in gestures]
    assert len(gestures) >= 50 and len(set(minutes)) == len(minutes), "at most one a minute"
    assert len({round(at % 10.0, 1) for at in gestures}) > 20, "at random moments, not at one phase of the settings"


def test_the_base_listener_leaves_on_its_own_half_way_between_two_restarts():
    steps = schedule.churn_schedule(HOUR, seed=3)
    listener = [(step.at, step.detail["present"]) for step in steps if step.action == schedule.LISTENER]
    assert listener == [(at + away, away > 0) for at in (600.0, 1200.0, 1800.0, 2400.0, 3000.0)
                        for away in (0.0, schedule.LISTENER_AWAY)]
    short = schedule.churn_schedule(180.0, restart_period=120.0)
    assert [step.at for step in short if step.action == schedule.LISTENER] == [120.0, 150.0]


def test_animate_goals_fall_in_disabled_spells_and_every_cancel_names_a_goal_sent_before_it():
    steps = schedule.churn_schedule(HOUR, seed=5)
    enabled, sent = False, set()
    for step in steps:
        if step.action in (schedule.ENABLE, schedule.DISABLE):
            enabled = step.action == schedule.ENABLE
        elif step.action == schedule.ANIMATE:
            assert not enabled, step
            sent.add(step.detail["goal"])
        elif step.action == schedule.CANCEL:
            assert step.detail["goal"] in sent


def test_the_slope_is_per_hour_and_ignores_noise_around_a_flat_line():
    times = [10.0 * index for index in range(361)]
    assert figures.slope_per_hour(times, [50.0 + t / HOUR for t in times]) == pytest.approx(1.0)
    assert figures.slope_per_hour(times, [50.0 + (0.3 if index % 2 else -0.3) for index in range(361)]) \
        == pytest.approx(0.0, abs=0.01)
    assert figures.slope_per_hour([5.0], [1.0]) is None
    assert figures.percentile([], 0.99) is None
    assert figures.percentile(list(range(101)), 0.99) == 99


def result_of(rss_growth_per_hour=0.0, threads=(30, 31), replies=0.01, goals=None, gone_wrong=()):
    samples = [{"t": 10.0 * index, "resident memory": 58.0 + rss_growth_per_hour * 10.0 * index / HOUR,
                "threads": threads[index % 2], "open files": 85, "cpu": 2.0, "log bytes": 1000}
               for index in range(420)]
    return {"ros": "1", "seconds": 4200.0, "warm up": 600.0, "samples": samples, "marks": [[1.0, "enable", {}]],
            "replies": [[at, "enable", replies, True] for at in range(0, 4200, 20)],
            "goals": goals if goals is not None else {"gesture-0": {"expect": "SUCCEEDED", "status": "SUCCEEDED"},
                                                      "animate-0": {"expect": "cancelled", "status": "PREEMPTED",
                                                                    "reason": "cancelled"}},
            "node goals gone wrong": list(gone_wrong), "log errors": 0, "tracebacks": 0}


def met(result):
    return {target.name: verdict for target, _value, verdict in figures.verdicts(result)}


def test_a_flat_run_meets_every_target():
    assert set(met(result_of()).values()) == {True}


@pytest.mark.parametrize("changes, failing", [
    ({"rss_growth_per_hour": 1.1}, "resident memory growth"),
    ({"threads": (28, 34)}, "threads, max - min"),
    ({"replies": 0.06}, "replies p99"),
    ({"goals": {"gesture-0": {"expect": "SUCCEEDED", "status": "ABORTED"}}}, "foreign gestures lost"),
    ({"goals": {"animate-0": {"expect": "replaced", "sent": 3.0}}},
     "animate goals and gestures not ending as expected"),
    ({"gone_wrong": [[900.0, "RArm", "ABORTED", False]]}, "node goals aborted or lost, not by a restart"),
    ({"gone_wrong": [[900.0, "RArm", "REJECTED", False]]}, "node goals rejected, not by a restart"),
])
def test_each_target_fails_on_its_own(changes, failing):
    verdicts = met(result_of(**changes))
    assert verdicts[failing] is False
    also = ["animate goals and gestures not ending as expected"] if failing == "foreign gestures lost" else []
    assert [name for name, verdict in verdicts.items() if verdict is False and name not in [failing] + also] in (
        [], ["replies p99, worst 10-minute window"])


def test_an_abort_or_a_rejection_a_restart_provoked_counts_for_nothing():
    verdicts = met(result_of(gone_wrong=[[905.0, "RArm", "LOST", True], [905.0, "RArm", "REJECTED", True]]))
    assert verdicts["node goals aborted or lost, not by a restart"] is True
    assert verdicts["node goals rejected, not by a restart"] is True


def test_the_warm_up_is_not_judged():
    result = result_of()
    result["samples"][3]["threads"] = 60
    assert met(result)["threads, max - min"] is True


def test_an_abort_of_the_gesture_part_right_after_a_gesture_or_anything_after_a_restart_is_the_churn_s(tmp_path):
    run = SoakRun(FakeDriver(tmp_path), [], 1.0, 0.0, progress=lambda line: None)
    run._gestures, run._restarts = [100.0], [[300.0, 303.0]]
    assert run.provoked(100.5, "RArm") and not run.provoked(100.5, "LArm") and not run.provoked(105.0, "RArm")
    assert run.provoked(310.0, "Leg") and not run.provoked(330.0, "Leg")


def test_the_log_is_read_once_across_a_rotation(tmp_path):
    path = str(tmp_path / "node.log")
    log = EventLog(path, max_bytes=600)
    tail = LogTail(path)
    seen = []
    for index in range(30):
        log.write(contract.ERROR, where="test", message="entry %d" % index)
        if index % 7 == 0:
            seen += [entry.fields["message"] for entry in tail.new_entries()]
    log.close()
    seen += [entry.fields["message"] for entry in tail.new_entries()]
    assert os.path.exists(path + ".1"), "the log rotated"
    assert seen == ["entry %d" % index for index in range(30)][-len(seen):]
    assert len(seen) >= 25, "at most the lines of one rotation between two reads are lost"


def test_tracebacks_are_counted_in_the_output(tmp_path):
    output = tmp_path / "node.out"
    output.write_text("a line\nTraceback (most recent call last):\n  File ...\nValueError\n")
    assert count_tracebacks(str(output)) == 1
    assert count_tracebacks(str(tmp_path / "none")) == 0


class FakeDriver:
    """The node is this test process; goals end at once as expected, but for gesture-0, which aborts."""

    def __init__(self, folder):
        self.log_file = str(folder / "node.log")
        self.output_file = str(folder / "node.out")
        self.heap_file = str(folder / "heap.json")
        self.calls = []
        with open(self.log_file, "w") as log:
            log.write(format_log_line(format_timestamp(time.time()), contract.GOAL_FINISHED,
                                      {"part": "RArm", "state": "ABORTED"}) + "\n")

    def attach(self, ended):
        self.ended = ended

    def node_pid(self):
        return os.getpid()

    def activate(self, state):
        self.calls.append(state)
        return True

    def set_setting(self, name, value):
        self.calls.append(name)
        return True

    def send_animate(self, goal, detail):
        self.ended(goal, "SUCCEEDED", detail["expect"])

    def cancel_animate(self, goal):
        self.calls.append("cancel")

    def play_gesture(self, goal):
        self.ended(goal, "ABORTED" if goal == "gesture-0" else "SUCCEEDED", "")

    def restart_controllers(self):
        self.calls.append("restart")

    def base_listener(self, present):
        self.calls.append("listener %s" % ("back" if present else "away"))
        with open(self.log_file, "a") as log:  # the node sees it at once
            log.write(format_log_line(format_timestamp(time.time()), contract.CONTROLLER_CONNECTED if present
                                      else contract.CONTROLLER_LOST, {"part": "Wheels"}) + "\n")


def test_a_run_plays_the_schedule_samples_the_process_and_sets_each_end_beside_the_expected(tmp_path):
    driver = FakeDriver(tmp_path)
    steps = [schedule.Step(0.0, schedule.ENABLE, {}), schedule.Step(0.01, schedule.RESTART, {}),
             schedule.Step(0.02, schedule.GESTURE, {"goal": "gesture-0"}),
             schedule.Step(0.03, schedule.ANIMATE, {"goal": "animate-0", "duration": 0.0, "intensity": 1.0,
                                                    "parts": [], "expect": "cancelled"}),
             schedule.Step(0.04, schedule.CANCEL, {"goal": "animate-0"}),
             schedule.Step(0.05, schedule.SETTING, {"name": "intensity", "value": 0.5}),
             schedule.Step(0.06, schedule.LISTENER, {"present": False}),
             schedule.Step(0.07, schedule.LISTENER, {"present": True})]
    with open(driver.heap_file, "w") as heap:
        heap.write('{"malloc in use": 14.5, "malloc free": 6.0, "python blocks": 220000}')
    checkpoints = []
    run = SoakRun(driver, steps, 0.3, 0.0, progress=lambda line: None, sample_period=0.05,
                  checkpoint=checkpoints.append)
    result = run.run()
    assert driver.calls == ["enabled", "restart", "cancel", "intensity", "listener away", "listener back"]
    assert len(result["samples"]) >= 5 and result["samples"][0]["threads"] >= 1 and checkpoints
    assert result["samples"][0]["malloc in use"] == 14.5 and result["samples"][0]["resident anonymous"] > 0
    assert result["base listener seen"] == {"left": 1, "back": 1}
    assert [reply[1] for reply in result["replies"]] == ["enable", "setting"]
    assert figures.unexpected_ends(result) == ["gesture-0: expected SUCCEEDED, got ABORTED"]
    assert [row[2:] for row in result["node goals gone wrong"]] == [["ABORTED", False]]
    text = report.text(result)
    assert "animate goals and gestures not ending as expected" in text and "NO" in text


def test_each_runs_plot_has_a_plain_file_name():
    assert [report.plot_name(ros) for ros in ("1", "2", "1, simulated clock")] == [
        "soak-latest-ros1.png", "soak-latest-ros2.png", "soak-latest-ros1-simulated-clock.png"]


def test_the_enabled_spells_are_shaded_from_each_enable_to_the_next_disable():
    marks = [[60.0, "enable", {}], [90.0, "setting", {}], [120.0, "disable", {}], [180.0, "enable", {}],
             [240.0, "setting", {}]]
    assert report.enabled_spans(marks) == [(1.0, 2.0), (3.0, 4.0)]


def test_the_report_page_and_its_plot(tmp_path):
    result = result_of(rss_growth_per_hour=0.2)
    result["marks"] += [[300.0, schedule.RESTART, {}], [330.0, schedule.GESTURE, {"goal": "gesture-0"}]]
    plot = report.plot(result, str(tmp_path / "soak.png"))
    assert os.path.getsize(plot) > 1000
    page = report.markdown({"1": result, "2": result_of()}, {"1": "soak.png"})
    assert page.count("| resident memory growth (MB/h) |") == 2
    for sample in result["samples"]:
        sample.update({"resident anonymous": sample["resident memory"] - 18.0, "resident file": 18.0,
                       "malloc in use": 14.5, "malloc free": 6.0 + 0.2 * sample["t"] / HOUR, "python blocks": 2e5})
    assert report.growth_text(result) == ("resident memory 0.20 MB/h (anonymous 0.20, file-backed 0); malloc in use "
                                          "0 MB/h, free but kept 0.20 MB/h; Python's allocated blocks +0 an hour")
    assert "## ROS 1" in page and "## ROS 2" in page and "![" in page
    assert "cut short" not in page
    result["samples"] = result["samples"][:200]
    assert "33 minutes, of which 10 of warm-up are not judged (cut short: 70 were planned)" in report.markdown(
        {"1": result}, {})


def test_a_run_of_one_front_end_rewrites_its_section_and_keeps_the_others(tmp_path):
    page = tmp_path / "soak-latest.md"
    both = {"1": result_of(rss_growth_per_hour=0.2), "2": result_of()}
    both["1, simulated clock"] = dict(both["1"], ros="1, simulated clock")
    page.write_text(report.markdown(both, {}))
    before = report.sections(page.read_text())
    assert sorted(before) == ["1", "1, simulated clock", "2"]
    again = tmp_path / "soak-ros2.json"
    again.write_text(json.dumps(dict(result_of(rss_growth_per_hour=0.4), ros="2")))
    assert report.main(["--markdown", str(page), str(again), str(tmp_path / "missing.json")]) == 0
    after = report.sections(page.read_text())
    assert sorted(after) == ["1", "1, simulated clock", "2"]
    assert after["1"] == before["1"] and after["1, simulated clock"] == before["1, simulated clock"]
    assert "| resident memory growth (MB/h) | 0.40 |" in after["2"]
    assert "| resident memory growth (MB/h) | 0.40 |" not in before["2"]


def test_the_probe_writes_what_the_allocators_hold(tmp_path):
    heap = tmp_path / "heap.json"
    probe = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "soak_probe")
    environment = dict(os.environ, PYTHONPATH=probe, CSSR_SOAK_HEAP_FILE=str(heap), CSSR_SOAK_HEAP_PERIOD="0.05")
    subprocess.run([sys.executable, "-c", "import time; time.sleep(0.5)"], env=environment, check=True)
    figures = run.read_heap(str(heap))
    assert figures["python blocks"] > 1000
    assert figures["malloc in use"] is None or 0.1 < figures["malloc in use"] < 1000.0  # None without glibc
