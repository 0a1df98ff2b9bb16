"""The harness's report, one plain-text block per test: `format_run_header`, `format_test`, `format_run_footer`.
"""
import datetime
from typing import Optional, Sequence

from cssr_system.animate_behaviour.harness.checks import (HarnessOutcome, format_number, part_label,
                                                          format_vector)
from cssr_system.animate_behaviour.harness.oracle import ExpectedMotion
from cssr_system.animate_behaviour.harness.settings import BASE, HarnessConfiguration, TESTS
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
    expected = outcome.expected
    width = max(len(key) for key in outcome.items) + 1
    lines = [THIN_RULE, "Test {}: {} (behaviour {}, iteration {})".format(spec.number, spec.title, spec.name,
                                                                          outcome.iteration), THIN_RULE,
             "", "Configuration Settings:"]
    lines.extend("{} : {}".format(key.ljust(width), value) for key, value in outcome.items.items())
    lines.extend(["", "Joint names:"])
    for key in expected.parts:
        lines.append("{}: [{}]".format(part_label(key), ", ".join('"{}"'.format(j) for j in PARTS[key].joints)))
    if expected.base:
        lines.append('base: ["Wheels"]')
    lines.extend(["", "Home positions (the centres of the random positions):"])
    for key in expected.parts:
        lines.append("{}: {}".format(part_label(key), format_vector(PARTS[key].centre)))
    if expected.base:
        lines.append("base: heading at enable, turns bounded by {} rad".format(outcome.items.get("headingBound")))
    if expected.parts:
        lines.extend(["", "Bounds of the random positions (Table 1, computed by the harness):"])
        for key in expected.parts:
            lines.append("{}: {}".format(part_label(key), _bounds_text(expected, key)))
    if outcome.random_positions:
        lines.extend(["", "Random positions sent (first goal of each part, from the node's log):"])
        for key, rows in outcome.random_positions.items():
            lines.append("{} ({} of {} points):".format(part_label(key), len(rows),
                                                        outcome.random_count.get(key, 0)))
            lines.extend(format_vector(row) for row in rows)
    lines.extend(["", "Positions observed while enabled ({}):".format(outcome.observed_source)])
    for key, rows in outcome.observed.items():
        if key == BASE:
            lines.append("base turn from the heading at enable (rad):")
        else:
            lines.append("{}:".format(part_label(key)))
        lines.extend(format_vector(row) for row in rows)
    if not outcome.observed:
        lines.append("(no part moves in this test)")
    lines.extend(["", "Checks:"])
    for check in outcome.checks:
        lines.append("{}: {}".format(check.name, "PASSED" if check.passed else "FAILED"))
        lines.append("    {}".format(check.detail))
    lines.extend(["", "Result of Test {}: {}".format(spec.number, "PASSED" if outcome.passed else "FAILED"), ""])
    return "\n".join(lines) + "\n"


def format_run_footer(outcomes: Sequence[HarnessOutcome]) -> str:
    passed = all(outcome.passed for outcome in outcomes) and bool(outcomes)
    checks = sum(len(outcome.checks) for outcome in outcomes)
    failed = sum(len(outcome.failures) for outcome in outcomes)
    lines = [RULE, "Test Run Completed with Result: {} ({} test(s), {} checks, {} failed)".format(
        "PASSED" if passed else "FAILED", len(outcomes), checks, failed)]
    for outcome in outcomes:
        lines.append("  Test {}: {}: {}".format(TESTS[outcome.test].number, TESTS[outcome.test].title,
                                                "PASSED" if outcome.passed else "FAILED"))
        lines.extend("    FAILED: {}: {}".format(check.name, check.detail) for check in outcome.failures)
    lines.extend([RULE, ""])
    return "\n".join(lines) + "\n"
