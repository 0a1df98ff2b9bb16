#!/usr/bin/env python3
"""Reads every JUnit XML file under a folder and prints the failures and one closing line
`N passed, N failed[, N skipped]`. Exits 1 when a test failed or errored, when no test passed,
or when an expected result file is missing (a suite that did not run at all). A suite that counts more failures than
its test cases show (rosunit counts a failing unittest subTest, or a class's set-up, under no test case) counts them
too."""
import argparse
import os
import sys
import xml.etree.ElementTree as ElementTree


def unseen_failures(root) -> int:
    """The failures and errors the file's suites count beyond those of their test cases."""
    suites = [root] if root.tag == "testsuite" else list(root.iter("testsuite"))
    counted = sum(int(suite.get("failures") or 0) + int(suite.get("errors") or 0) for suite in suites)
    shown = sum(1 for case in root.iter("testcase") for child in case if child.tag in ("failure", "error"))
    return max(0, counted - shown)


def tally(path, results_dir):
    """(passed, failed, skipped, problem lines) of one result file."""
    where = os.path.relpath(path, results_dir)
    try:
        root = ElementTree.parse(path).getroot()
        unseen = unseen_failures(root)
    except (ElementTree.ParseError, ValueError) as error:
        return 0, 0, 0, ["{}: unreadable result file ({})".format(path, error)]
    passed, failed, skipped, problems = 0, unseen, 0, []
    if unseen:
        problems.append("FAILED {}: {} failure(s) under no test case (a subTest, a class's set-up): see its "
                        "output".format(where, unseen))
    for case in root.iter("testcase"):
        outcome = [child for child in case if child.tag in ("failure", "error", "skipped")]
        if not outcome:
            passed += 1
        elif outcome[0].tag == "skipped":
            skipped += 1
        else:
            failed += 1
            message = (outcome[0].get("message") or outcome[0].text or "").strip()
            problems.append("FAILED {}.{} ({}): {}".format(
                case.get("classname", ""), case.get("name", ""), where,
                message.splitlines()[0][:300] if message else outcome[0].tag))
    return passed, failed, skipped, problems


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("results_dir")
    parser.add_argument("--expect", action="append", default=[],
                        help="a result file name (below results_dir) that must exist")
    args = parser.parse_args()

    passed, failed, skipped, problems = 0, 0, 0, []
    for directory, _, files in os.walk(args.results_dir):
        for name in sorted(name for name in files if name.endswith(".xml")):
            counts = tally(os.path.join(directory, name), args.results_dir)
            passed, failed, skipped = passed + counts[0], failed + counts[1], skipped + counts[2]
            problems += counts[3]

    for expected in args.expect:
        if not any(name == expected for _, _, files in os.walk(args.results_dir) for name in files):
            failed += 1
            problems.append("FAILED {}: no result file (the suite did not run)".format(expected))

    for problem in problems:
        print(problem)
    line = "{} passed, {} failed".format(passed, failed)
    if skipped:
        line += ", {} skipped".format(skipped)
    print(line)
    return 1 if failed or not passed else 0


if __name__ == "__main__":
    sys.exit(main())
