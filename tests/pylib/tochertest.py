"""tochertest.py — shared by the Python test scripts: the "ok"/"FAIL" lines and the closing
"N passed, N failed" tally (thread-safe), and reading tocherd's startup line without hanging."""
import os
import re
import select
import sys
import threading
import time

LOCK = threading.Lock()
_count = {"pass": 0, "fail": 0}
SAN_RE = re.compile(r"AddressSanitizer|LeakSanitizer|runtime error:|UndefinedBehaviorSanitizer")


def say(line):
    with LOCK:
        print(line, flush=True)


def check(name, ok, detail=""):
    """Counts and prints one check; returns ok."""
    with LOCK:
        _count["pass" if ok else "fail"] += 1
        print(("ok   %s" % name) if ok else ("FAIL %s: %s" % (name, detail)), flush=True)
    return ok


def tally():
    return "%d passed, %d failed" % (_count["pass"], _count["fail"])


def finish():
    """Prints the tally as the last line and exits 1 on any failure."""
    print(tally(), flush=True)
    sys.exit(1 if _count["fail"] else 0)


def first_line(proc, timeout):
    """The first line proc writes on its stdout pipe, waiting at most timeout seconds ('' if none)."""
    fd, buf, end = proc.stdout.fileno(), b"", time.time() + timeout
    while not buf.endswith(b"\n"):
        ready, _, _ = select.select([fd], [], [], max(0.0, end - time.time()))
        if not ready:
            break
        chunk = os.read(fd, 512)
        if not chunk:
            break
        buf += chunk
    return buf.decode("utf-8", "replace").rstrip("\n")
