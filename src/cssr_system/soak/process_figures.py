"""A process's figures as /proc gives them, by its pid (never by a name): resident memory (also by kind), threads,
open files, CPU seconds; and a log file's size with its rotated copy. `make benchmark` and `make soak` measure with
these."""
import os


def process_figures(pid: int) -> dict:
    """Resident memory (MB), threads and open files of process `pid`."""
    with open("/proc/%d/status" % pid) as stream:
        rss = next(int(line.split()[1]) for line in stream if line.startswith("VmRSS:")) / 1024.0
    return {"resident memory": rss, "threads": len(os.listdir("/proc/%d/task" % pid)),
            "open files": len(os.listdir("/proc/%d/fd" % pid))}


def resident_kinds(pid: int) -> dict:
    """Resident memory (MB) of process `pid` by kind: anonymous (the heaps, Python's arenas, the threads' stacks) and
    file-backed (the code of the libraries and modules it has run)."""
    with open("/proc/%d/status" % pid) as stream:
        fields = dict(line.split(":", 1) for line in stream if line.startswith(("RssAnon:", "RssFile:")))
    return {"resident anonymous": int(fields["RssAnon"].split()[0]) / 1024.0,
            "resident file": int(fields["RssFile"].split()[0]) / 1024.0}


def cpu_seconds(pid: int) -> float:
    """User and system CPU seconds process `pid` has used."""
    with open("/proc/%d/stat" % pid) as stream:
        fields = stream.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime + stime


def log_bytes(log: str) -> int:
    """Bytes of the log file `log` and of its rotated copy (`log`.1)."""
    return sum(os.path.getsize(name) for name in (log, log + ".1") if os.path.exists(name))
