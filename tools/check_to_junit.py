"""Runs one check command and records it as a JUnit test case, so static checks (Python 3.8
compatibility, catkin_lint) count in the test summary like any test.

usage: python3 tools/check_to_junit.py RESULT_XML CHECK_NAME -- COMMAND [ARG ...]
       python3 tools/check_to_junit.py --skipped REASON RESULT_XML CHECK_NAME   (a check that cannot run here)"""
import subprocess
import sys
import time
import xml.etree.ElementTree as ElementTree


def write_skipped(reason: str, result_path: str, check_name: str) -> int:
    suite = ElementTree.Element("testsuite", name="checks", tests="1", skipped="1")
    case = ElementTree.SubElement(suite, "testcase", classname="checks", name=check_name)
    ElementTree.SubElement(case, "skipped", message=reason)
    ElementTree.ElementTree(suite).write(result_path, encoding="utf-8", xml_declaration=True)
    print("{}: skipped: {}".format(check_name, reason))
    return 0


def main(argv):
    if len(argv) == 4 and argv[0] == "--skipped":
        return write_skipped(*argv[1:])
    if len(argv) < 4 or argv[2] != "--":
        print(__doc__, file=sys.stderr)
        return 2
    result_path, check_name, command = argv[0], argv[1], argv[3:]
    started = time.monotonic()
    completed = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               universal_newlines=True)
    output = completed.stdout.strip()
    suite = ElementTree.Element("testsuite", name="checks", tests="1",
                                failures="0" if completed.returncode == 0 else "1")
    case = ElementTree.SubElement(suite, "testcase", classname="checks", name=check_name,
                                  time="{:.3f}".format(time.monotonic() - started))
    if completed.returncode != 0:
        lines = output.splitlines()
        failure = ElementTree.SubElement(case, "failure", message=(lines[-1] if lines else "failed"))
        failure.text = output
    ElementTree.ElementTree(suite).write(result_path, encoding="utf-8", xml_declaration=True)
    print("{}: {}".format(check_name, "passed" if completed.returncode == 0 else "FAILED"))
    if completed.returncode != 0:
        print(output)
    return completed.returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
