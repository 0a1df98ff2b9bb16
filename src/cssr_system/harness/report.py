"""The harness's report, one plain-text block per test: `format_run_header`, `format_test`, `format_run_footer`.
"""
import datetime
from typing import List, Optional, Sequence

from cssr_system.harness.checks import (HarnessOutcome, format_number, part_label,
                                        format_vector)
from cssr_system.harness.oracle import ExpectedMotion
from cssr_system.harness.settings import BASE, HarnessConfiguration, TESTS
from cssr_system.pepper.joint_table import PARTS


RULE = "=" * 90


THIN_RULE = "-" * 90


def _timestamp(moment: datetime.datetime) -> str:
    return moment.strftime("%Y-%m-%d %H:%M:%S")


def format_run_header(started: datetime.datetime, harness: HarnessConfiguration, iteration: int,
                      node_name: str, node_config_file: str, node_log_file: str,
                      iterations: Optional[int] = None) -> str:
    lines = [RULE, "=== New Test Run Started at {} ===".format(_timestamp(started)), RULE,
             "Platform                 : {}".format(harness.platform),
             "Iteration                : {} of {}".format(iteration, iterations or harness.iterations),
             "Tests                    : {} ({:g} s each)".format(", ".join(harness.tests), harness.test_duration),
             "Harness configuration    : {}".format(harness.source),
             "Node                     : {}".format(node_name),
             "Node configuration file  : {}".format(node_config_file),
             "Node log file            : {}".format(node_log_file),
             "Tolerances               : position {}, heading {} rad".format(
                 format_number(harness.position_tolerance), format_number(harness.heading_tolerance)),
             ""]
    return "\n".join(lines) + "\n"


def _bounds_text(expected: ExpectedMotion, key: str) -> str:
    texts = []
    for joint in PARTS[key].joints:
        bound = expected.bounds[joint]
        texts.append("{} [{}, {}]".format(joint, format_number(bound.lower), format_number(bound.upper)) if bound.moving
                     else "{} held at {}".format(joint, format_number(bound.centre)))
    return ", ".join(texts)


def format_test(outcome: HarnessOutcome) -> str:
    """The report section of one test."""
    spec = TESTS[outcome.test]
    width = max(len(key) for key in outcome.items) + 1
    lines = [THIN_RULE, "Test {}: {} (behaviour {}, iteration {})".format(spec.number, spec.title, spec.name,
                                                                          outcome.iteration), THIN_RULE,
             "", "Configuration Settings:"]
    lines.extend("{} : {}".format(key.ljust(width), value) for key, value in outcome.items.items())
    lines.extend(_joint_names_lines(outcome.expected))
    lines.extend(_home_lines(outcome))
    lines.extend(_bounds_lines(outcome.expected))
    lines.extend(_random_positions_lines(outcome))
    lines.extend(_observed_lines(outcome))
    lines.extend(_checks_lines(outcome))
    lines.extend(["", "Result of Test {}: {}".format(spec.number, _verdict(outcome.passed)), ""])
    return "\n".join(lines) + "\n"


def _verdict(passed: bool) -> str:
    return "PASSED" if passed else "FAILED"


def _joint_names_lines(expected: ExpectedMotion) -> List[str]:
    """The joints of each part the test moves, and the base's wheels when it turns."""
    lines = ["", "Joint names:"]
    for key in expected.parts:
        lines.append("{}: [{}]".format(part_label(key), ", ".join('"{}"'.format(j) for j in PARTS[key].joints)))
    if expected.base:
        lines.append('base: ["Wheels"]')
    return lines


def _home_lines(outcome: HarnessOutcome) -> List[str]:
    """The centre of each moving part, and the base's bound on its turns."""
    lines = ["", "Home positions (the centres of the random positions):"]
    for key in outcome.expected.parts:
        lines.append("{}: {}".format(part_label(key), format_vector(PARTS[key].centre)))
    if outcome.expected.base:
        lines.append("base: heading at enable, turns bounded by {} rad".format(outcome.items.get("headingBound")))
    return lines


def _bounds_lines(expected: ExpectedMotion) -> List[str]:
    """The bounds of each moving part's random positions; nothing when no joint part moves."""
    if not expected.parts:
        return []
    lines = ["", "Bounds of the random positions (Table 1, computed by the harness):"]
    lines.extend("{}: {}".format(part_label(key), _bounds_text(expected, key)) for key in expected.parts)
    return lines


def _random_positions_lines(outcome: HarnessOutcome) -> List[str]:
    """The first goal's positions of each part from the node's log; nothing when there are none."""
    if not outcome.random_positions:
        return []
    lines = ["", "Random positions sent (first goal of each part, from the node's log):"]
    for key, rows in outcome.random_positions.items():
        lines.append("{} ({} of {} points):".format(part_label(key), len(rows), outcome.random_count.get(key, 0)))
        lines.extend(format_vector(row) for row in rows)
    return lines


def _observed_lines(outcome: HarnessOutcome) -> List[str]:
    """The positions observed while enabled, part by part (the base as its turn from the heading)."""
    lines = ["", "Positions observed while enabled ({}):".format(outcome.observed_source)]
    for key, rows in outcome.observed.items():
        if key == BASE:
            lines.append("base turn from the heading at enable (rad):")
        else:
            lines.append("{}:".format(part_label(key)))
        lines.extend(format_vector(row) for row in rows)
    if not outcome.observed:
        lines.append("(no part moves in this test)")
    return lines


def _checks_lines(outcome: HarnessOutcome) -> List[str]:
    """Each check's verdict and detail."""
    lines = ["", "Checks:"]
    for check in outcome.checks:
        lines.append("{}: {}".format(check.name, _verdict(check.passed)))
        lines.append("    {}".format(check.detail))
    return lines


def format_run_footer(outcomes: Sequence[HarnessOutcome]) -> str:
    passed = all(outcome.passed for outcome in outcomes) and bool(outcomes)
    checks = sum(len(outcome.checks) for outcome in outcomes)
    failed = sum(len(outcome.failures) for outcome in outcomes)
    lines = [RULE, "Test Run Completed with Result: {} ({} test(s), {} checks, {} failed)".format(
        _verdict(passed), len(outcomes), checks, failed)]
    for outcome in outcomes:
        lines.append("  Test {}: {}: {}".format(TESTS[outcome.test].number, TESTS[outcome.test].title,
                                                _verdict(outcome.passed)))
        lines.extend("    FAILED: {}: {}".format(check.name, check.detail) for check in outcome.failures)
    lines.extend([RULE, ""])
    return "\n".join(lines) + "\n"
