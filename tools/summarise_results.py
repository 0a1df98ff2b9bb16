#!/usr/bin/env python3
"""Reads every JUnit XML file under a folder and prints the failures and one closing line
`N passed, N failed[, N skipped]`. Exits 1 when a test failed or errored, when no test passed,
or when an expected result file is missing (a suite that did not run at all)."""
import argparse
import os
import sys
import xml.etree.ElementTree as ElementTree


def testcases(path):
    root = ElementTree.parse(path).getroot()
    return root.iter("testcase")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("results_dir")
    parser.add_argument("--expect", action="append", default=[],
                        help="a result file name (below results_dir) that must exist")
    args = parser.parse_args()

    passed, failed, skipped, problems = 0, 0, 0, []
    for directory, _, files in os.walk(args.results_dir):
        for name in sorted(files):
            if not name.endswith(".xml"):
                continue
            path = os.path.join(directory, name)
            try:
                cases = list(testcases(path))
            except ElementTree.ParseError as error:
                problems.append("{}: unreadable result file ({})".format(path, error))
                continue
            for case in cases:
                title = "{}.{}".format(case.get("classname", ""), case.get("name", ""))
                outcome = [child for child in case if child.tag in ("failure", "error", "skipped")]
                if not outcome:
                    passed += 1
                elif outcome[0].tag == "skipped":
                    skipped += 1
                else:
                    failed += 1
                    message = (outcome[0].get("message") or outcome[0].text or "").strip()
                    problems.append("FAILED {} ({}): {}".format(
                        title, os.path.relpath(path, args.results_dir), message.splitlines()[0][:300]
                        if message else outcome[0].tag))

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
