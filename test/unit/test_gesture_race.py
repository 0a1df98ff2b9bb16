"""Unit tests of the gesture race's account (src/cssr_system/soak/gesture_race.py): what it counts as lost, and the
intervals it reports from the status lists it saw."""
import time

from cssr_system.soak.gesture_race import Gesture, PartRace, summary, text


def raced_part() -> PartRace:
    """The node's goals start at 10.0 and 11.0; a gesture sent at 11.990 shows running at 11.996, succeeds, and the
    node's next goal starts at 13.5; a second, sent at 14.010, shows running at 14.013 just after the node's goal of
    14.0, and is preempted."""
    race = PartRace("RArm")
    race.status_list(10.0, ["node-1"], False)
    race.status_list(11.0, ["node-2"], False)
    race.begin(Gesture("RArm", True, 11.990, -0.01))
    race.status_list(11.996, [], True)
    race.ended("SUCCEEDED", 12.8)
    race.status_list(13.5, ["node-3"], False)
    race.status_list(14.0, ["node-4"], False)
    race.begin(Gesture("RArm", False, 14.010, None))
    race.status_list(14.013, ["node-4"], True)
    race.ended("PREEMPTED", 14.05)
    return race


def test_a_gesture_that_ends_other_than_succeeded_is_lost_and_named():
    result = summary([raced_part()])
    assert (result["gestures"], result["lost"], result["lost by state"]) == (2, 1, {"PREEMPTED": 1})
    assert result["lost gestures"] == [{"part": "RArm", "state": "PREEMPTED", "aimed": False, "offset": None}]
    assert result["aimed"] == 1 and result["aimed within 20 ms of the boundary"] == 1


def test_the_intervals_are_from_each_acceptance_to_the_nodes_goals_either_side():
    result = summary([raced_part()])
    assert result["smallest acceptance to our next goal, s"] == 1.504  # 11.996 -> 13.5; the second has none after
    assert result["smallest our last goal to acceptance, s"] == 0.013  # 14.0 -> 14.013
    assert result["accepted within 20 ms after the node's goal start"] == 1
    assert result["sent to seen running, ms"] == {"median": 6.0, "99%": 6.0, "largest": 6.0}  # 3 ms and 6 ms


def test_a_gesture_never_seen_running_and_never_ended_is_lost_and_has_no_intervals():
    race = PartRace("Leg")
    race.status_list(1.0, ["node-1"], False)
    race.begin(Gesture("Leg", True, 1.5, 0.0))
    result = summary([race])
    assert result["lost"] == 1 and result["lost by state"] == {"None": 1}
    assert result["smallest acceptance to our next goal, s"] is None and result["sent to seen running, ms"] == {
        "median": None, "99%": None, "largest": None}
    assert "foreign gestures lost: 1" in text(result)


def test_with_resend_a_lost_gesture_is_sent_again_at_once_and_counted_apart():
    import random
    import threading
    from cssr_system.soak.gesture_race import play
    race, sent, stop = PartRace("RArm"), [], threading.Event()

    def node_goals():  # the node's goals start every 20 ms
        number = 0
        while not stop.is_set():
            number += 1
            race.status_list(time.monotonic(), ["node-%d" % number], False)
            time.sleep(0.02)

    def send(part):  # the first gesture loses its race, its resend and the next gesture succeed
        sent.append(part)
        race.status_list(time.monotonic(), [], True)
        race.ended("PREEMPTED" if len(sent) == 1 else "SUCCEEDED", time.monotonic())
    feeder = threading.Thread(target=node_goals, daemon=True)
    feeder.start()
    try:
        play(race, 2, send, random.Random(1), resend=True)
    finally:
        stop.set()
    assert [(gesture.state, gesture.resent) for gesture in race.gestures] == [
        ("PREEMPTED", False), ("SUCCEEDED", True), ("SUCCEEDED", False)]
    result = summary([race])
    assert (result["gestures"], result["lost"], result["resent"], result["lost when resent"]) == (2, 1, 1, 0)
    assert result["by part"] == {"RArm": 2}
    assert "resent at once: 1, of which lost again: 0" in text(result)


def test_the_period_for_an_aim_is_the_latest_interval_with_no_gesture_between_the_goals():
    race = PartRace("Leg")
    assert race.period() == 1.0, "no interval yet"
    race.status_list(0.0, ["node-1"], False)
    race.status_list(16.0, ["node-2"], False)
    assert race.period() == 16.0
    race.begin(Gesture("Leg", True, 17.0, 0.0))
    race.status_list(17.01, [], True)
    race.status_list(17.02, ["node-3"], True)  # a goal of the node's that starts while the gesture is in flight
    race.ended("PREEMPTED", 17.03)
    race.status_list(19.5, ["node-4"], False)  # the first goal after the gesture's end
    assert race.period() == 16.0, "the intervals across the gesture are not the node's period"
    race.status_list(35.0, ["node-5"], False)
    assert race.period() == 15.5
