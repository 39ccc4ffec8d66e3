"""hostile.py — what the hostile-load tests share (tests/endpoint/test_framing_limits.py and
tests/torture/*.py): a tocherd on loopback configured by TOCHER_* variables (a binary that
lacks a setting ignores it, so the same test runs against an older build), raw exchanges,
memory figures from /proc, and trickling connections."""
import os
import re
import resource
import socket
import threading
import time

from tochertest import Tocherd

JSON_POST = b"Host: t\r\nContent-Type: application/json\r\n"


def raise_fd_limit(want):
    """Raises this process's soft open-files limit (the daemon inherits it) towards want."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft < want:
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(want, hard), hard))
    return resource.getrlimit(resource.RLIMIT_NOFILE)[0]


class Daemon(Tocherd):
    """One tocherd with TOCHER_* settings from env (name=value), stderr in tmp."""

    def __init__(self, build, tmp, name, **env):
        super().__init__(os.path.join(build, "tocherd"), os.path.join(tmp, name + ".stderr"),
                         env={"TOCHER_" + k.upper(): str(v) for k, v in env.items()})

    def connect(self, source="127.0.0.1", timeout=10):
        return socket.create_connection(("127.0.0.1", self.port), timeout=timeout, source_address=(source, 0))


def read_all(s, timeout):
    """Every byte until the peer closes or timeout passes; (bytes, closed)."""
    s.settimeout(timeout)
    out, end = b"", time.time() + timeout
    try:
        while time.time() < end:
            b = s.recv(65536)
            if not b:
                return out, True
            out += b
    except socket.timeout:
        return out, False
    except OSError:
        return out, True
    return out, False


def exchange(d, data, timeout=10, source="127.0.0.1"):
    """Sends raw bytes on a new connection; (everything answered, closed by the daemon)."""
    s = d.connect(source, timeout)
    try:
        try:
            s.sendall(data)
        except OSError:
            pass
        return read_all(s, timeout)
    finally:
        s.close()


def healthz_seconds(d, source, timeout):
    """Seconds until /healthz answers 200 on a new connection from source; None if not within timeout."""
    t0 = time.time()
    try:
        s = d.connect(source, timeout)
        s.sendall(b"GET /healthz HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n")
        out, _ = read_all(s, max(0.1, timeout - (time.time() - t0)))
        s.close()
    except OSError:
        return None
    took = time.time() - t0
    return took if out.startswith(b"HTTP/1.1 200") and took <= timeout else None


def status_lines(out):
    return len(re.findall(rb"HTTP/1\.[01] \d{3} ", out))


class Trickler:
    """n connections from source that each send a request header byte every `every` seconds
    and never finish it; counts those the daemon closed."""

    HEAD = b"GET /healthz HTTP/1.1\r\nHost: t\r\nX-Slow: " + b"a" * 100000

    def __init__(self, d, n, every, source="127.0.0.1"):
        self.socks, self.closed, self.stop = [], 0, threading.Event()
        for _ in range(n):
            try:
                s = d.connect(source, 5)
                s.setblocking(False)
                self.socks.append(s)
            except OSError:
                break
        self.opened = time.time()
        self.every = every
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        i = 0
        while not self.stop.wait(self.every):
            live = []
            for s in self.socks:
                try:
                    s.send(self.HEAD[i:i + 1])
                    if s.recv(1, socket.MSG_PEEK) == b"":
                        raise OSError("closed")
                except BlockingIOError:
                    live.append(s)
                    continue
                except OSError:
                    self.closed += 1
                    s.close()
                    continue
                live.append(s)
            self.socks, i = live, i + 1

    def open_count(self):
        return len(self.socks)

    def close(self):
        self.stop.set()
        self.thread.join()
        for s in self.socks:
            s.close()
