"""daemonio.py — shared by the Python tests that start tocherd: reading its startup line
without hanging on a daemon that never prints one."""
import os
import select
import time


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
