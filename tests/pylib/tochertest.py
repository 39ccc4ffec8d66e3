"""tochertest.py — shared by the Python test scripts: the "ok"/"FAIL" lines and the closing
"N passed, N failed" tally (thread-safe), reading tocherd's startup line without hanging, and
one tocherd started on a free loopback port (Tocherd)."""
import os
import re
import select
import signal
import subprocess
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


def daemon_env(extra=None):
    """The caller's environment without its TOCHER_* settings (the image plugin's path kept),
    plus extra: what a test's daemon starts with, whatever the shell had set."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("TOCHER_") or k == "TOCHER_IMAGE_LIB"}
    env.update(extra or {})
    return env


class Tocherd:
    """One tocherd on 127.0.0.1:0: its flags and extra environment, stderr to err_path, the
    startup line read (line, version, port). strict: a daemon that does not start raises;
    otherwise started is False and port None. The scripts' own Daemon classes add what they track."""

    def __init__(self, tocherd, err_path, flags=(), env=None, strict=True):
        self.err_path = err_path
        with open(err_path, "wb") as errf:
            self.proc = subprocess.Popen([tocherd, "--listen", "127.0.0.1:0", *flags], stdin=subprocess.DEVNULL,
                                         stdout=subprocess.PIPE, stderr=errf, env=daemon_env(env))
        self.line = first_line(self.proc, 30)
        m = re.fullmatch(r"tocherd (\S+) listening on http://127\.0\.0\.1:(\d+)", self.line)
        self.started = m is not None
        self.version, self.port = (m.group(1), int(m.group(2))) if m else (None, None)
        if strict and not m:
            self.kill()
            raise RuntimeError("%s: startup line %r; stderr: %s" % (err_path, self.line, self.stderr()[:400]))

    @property
    def pid(self):
        return self.proc.pid

    def alive(self):
        return self.proc.poll() is None

    def status(self, key):
        """A /proc/PID/status figure in kB (VmRSS, VmHWM, VmSize); -1 if absent."""
        with open("/proc/%d/status" % self.proc.pid) as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1])
        return -1

    def stderr(self):
        try:
            with open(self.err_path, "rb") as f:
                return f.read().decode("utf-8", "replace")
        except OSError:
            return ""

    def stop(self, timeout=30):
        """SIGTERM and wait: the exit status, or None if it had to be killed."""
        if self.alive():
            self.proc.send_signal(signal.SIGTERM)
        try:
            return self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            return None

    def kill(self):
        if self.alive():
            self.proc.kill()
        try:
            self.proc.wait(5)
        except subprocess.TimeoutExpired:
            pass
