"""Unit tests of what the ROS 2 recorder makes of the controllers' references (recording/commanded.py,
`commanded_by_reference`; recording/run_recorder.py): the node's commanded line from its first goal to a part, a gap
and a mark while the part yields to another node, as the node's log tells."""
import numpy

from cssr_system.animate_behaviour import contract
from cssr_system.animate_behaviour.event_log import EventLog, read_log
from cssr_system.pepper.joint_table import JOINTS, PARTS
from cssr_system.recording.commanded import ReferenceSample, commanded_by_reference
from cssr_system.recording.recording import LoggedYield, Mark, goals_sent_from_log, yields_from_log
from cssr_system.recording.run_recorder import RunRecorder

NODE, OTHER = "/animateBehaviour", "/gesture"
ARM = PARTS["RArm"]
UPDATES = numpy.arange(0.0, 10.0, 0.02)  # the controllers' updates, 50 Hz


def reference(time):
    """The right arm's reference at `time`: its centre, the shoulder pitch moving."""
    return tuple(centre + (0.1 * numpy.sin(time) if name == "RShoulderPitch" else 0.0)
                 for name, centre in zip(ARM.joints, ARM.centre))


def samples(part="RArm"):
    joints = PARTS[part].joints
    # In the controller's own joint order, which need not be the part's.
    return [ReferenceSample(time, part, tuple(reversed(joints)), tuple(reversed(reference(time) if part == "RArm"
                                                                                else PARTS[part].centre)))
            for time in UPDATES]


def test_the_reference_is_the_nodes_from_its_first_goal_and_not_while_the_part_yields():
    times = UPDATES + 0.01  # /joint_states' times, half-way between the updates
    commanded = commanded_by_reference(NODE, samples() + samples("LArm"), times,
                                       goals_sent=[(1.0, "RArm"), (2.0, "RArm"), (6.0, "RArm")],
                                       yielded=[(4.0, "RArm")])
    assert commanded.source == NODE and commanded.joint_names == ARM.joints  # no goal to the left arm: not its
    ours = ((times >= 1.0) & (times < 4.0)) | (times >= 6.0)
    assert numpy.all(numpy.isnan(commanded.positions[~ours]))
    for row in numpy.nonzero(ours & (times < UPDATES[-1]))[0]:  # between two updates: between their references
        expected = (numpy.array(reference(UPDATES[row])) + numpy.array(reference(UPDATES[row + 1]))) / 2.0
        numpy.testing.assert_allclose(commanded.positions[row], expected, atol=1e-12)
    numpy.testing.assert_allclose(commanded.positions[-1], reference(UPDATES[-1]), atol=1e-12)  # then held


def test_no_goal_of_the_node_or_no_reference_means_no_commanded_line():
    assert commanded_by_reference(NODE, samples(), UPDATES, goals_sent=[]) is None
    assert commanded_by_reference(NODE, samples(), UPDATES, goals_sent=[(1.0, "LArm")]) is None


def write_log(path, epoch):
    clock = [epoch]
    with EventLog(path, clock=lambda: clock[0]) as log:
        for offset, event, fields in (
                (1.0, contract.GOAL_SENT, dict(part="RArm", purpose="animate")),
                (4.0, contract.PART_YIELDED, dict(part="RArm", controller="c", caller=OTHER, kind="goal")),
                (4.5, contract.PART_YIELDED, dict(part="Leg", controller="c", caller=OTHER, kind="joint_angles")),
                (5.5, contract.PART_RESUMED, dict(part="Leg", controller="c", caller=OTHER, seconds=1.0)),
                (6.0, contract.PART_RESUMED, dict(part="RArm", controller="c", caller=OTHER, seconds=2.0)),
                (6.0, contract.GOAL_SENT, dict(part="RArm", purpose="animate")),
                (7.0, contract.PART_YIELDED, dict(part="LArm", controller="c", caller=OTHER, kind="command")),
                (8.0, contract.BEHAVIOUR_ENDED, dict(reason="disabled", home=True))):
            clock[0] = epoch + offset
            log.write(event, **fields)
    return read_log(path)


def test_the_log_tells_the_nodes_goals_and_its_yields(tmp_path):
    entries = write_log(str(tmp_path / "node.log"), 1000.0)
    assert goals_sent_from_log(entries) == [(1001.0, "RArm"), (1006.0, "RArm")]
    assert goals_sent_from_log(entries, since=1002.0) == [(1006.0, "RArm")]
    assert yields_from_log(entries) == [LoggedYield(1004.0, 1006.0, "RArm", OTHER, "goal"),
                                        LoggedYield(1004.5, 1005.5, "Leg", OTHER, "joint_angles"),
                                        LoggedYield(1007.0, 1008.0, "LArm", OTHER, "command")]  # ends at disable


def test_a_recorder_given_references_draws_the_nodes_line_and_marks_the_other_nodes_goal(tmp_path):
    recorder = RunRecorder(NODE, None, "/pepper/odom")
    recorder.start_epoch = 1000.0
    for time in UPDATES:
        recorder.add_joint_states(1000.0 + time, list(JOINTS), [0.0] * len(JOINTS))
        recorder.add_reference(1000.0 + time, "RArm", ARM.joints, reference(time))
    recording = recorder.recording(write_log(str(tmp_path / "node.log"), 1000.0))
    commanded = recording.commanded
    assert commanded.joint_names == ARM.joints
    assert numpy.all(numpy.isnan(commanded.positions[(commanded.times < 1.0) | ((commanded.times >= 4.0)
                                                                                & (commanded.times < 6.0))]))
    assert numpy.all(numpy.isfinite(commanded.positions[(commanded.times >= 1.0) & (commanded.times < 4.0)]))
    # The other node's goal is marked; its setAngles calls are marked from the calls themselves, not from the log.
    assert recording.marks == (Mark(4.0, 6.0, OTHER + ": goal", "RArm"), Mark(7.0, 8.0, OTHER + ": command", "LArm"))
