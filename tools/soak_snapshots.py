#!/usr/bin/env python3
"""The allocation sites whose memory grew between two tracemalloc snapshots of a soak (doc/soak.md):

  python3 tools/soak_snapshots.py FOLDER [--first N] [--top 15]

compares the snapshot N of FOLDER (default: the second, the first after a warm-up of 5 minutes) with the last, by
traceback, the largest growth first, each with the lines that made it (the innermost frame first)."""
import argparse
import glob
import os
import sys
import tracemalloc


def main(argv) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder")
    parser.add_argument("--first", type=int, default=1, help="index of the earlier snapshot (0: the first)")
    parser.add_argument("--top", type=int, default=15)
    parser.add_argument("--frames", type=int, default=6, help="frames shown per site")
    arguments = parser.parse_args(argv)
    names = sorted(glob.glob(os.path.join(arguments.folder, "snapshot-*.tracemalloc")))
    if len(names) < 2:
        print("soak_snapshots: %d snapshot(s) in %s: two are needed" % (len(names), arguments.folder))
        return 1
    first, last = names[min(arguments.first, len(names) - 2)], names[-1]
    ignored = [tracemalloc.Filter(False, tracemalloc.__file__), tracemalloc.Filter(False, "<frozen importlib*")]
    before = tracemalloc.Snapshot.load(first).filter_traces(ignored)
    after = tracemalloc.Snapshot.load(last).filter_traces(ignored)
    differences = after.compare_to(before, "traceback")
    total = sum(entry.size_diff for entry in differences) / 1024.0
    print("%s -> %s: %+.1f kB in all" % (os.path.basename(first), os.path.basename(last), total))
    for entry in differences[:arguments.top]:
        print("%+9.1f kB %+7d blocks" % (entry.size_diff / 1024.0, entry.count_diff))
        for line in entry.traceback.format(limit=arguments.frames, most_recent_first=True):
            print("      " + line)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
