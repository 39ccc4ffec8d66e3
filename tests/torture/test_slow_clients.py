#!/usr/bin/env python3
"""test_slow_clients.py — full size (issue 14, 2.2): one host opens 1 100 connections that send a
request-header byte every 2 s and never finish. With default options the daemon must still
answer /healthz on a new connection from another address within 2 s, and from the same host
within 2 s once the header deadline (--header-timeout, 10 s by default) has closed them.

    /usr/bin/python3 tests/torture/test_slow_clients.py BUILD_DIR
"""
import os
import shutil
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
from hostile import Daemon, Trickler, healthz_seconds, raise_fd_limit  # noqa: E402
from tochertest import check, finish, say  # noqa: E402

BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build"))
N, EVERY, HEADER_DEADLINE = 1100, 2.0, 10.0


def worst(d, source, probes):
    """The slowest of `probes` /healthz answers from source, one every 0.5 s (None: one failed)."""
    times = []
    for _ in range(probes):
        t = healthz_seconds(d, source, 2.0)
        if t is None:
            return None
        times.append(t)
        time.sleep(0.5)
    return max(times)


def main():
    limit = raise_fd_limit(N + 400)
    say("# %s against %s; open-files limit %d" % (os.path.basename(__file__), BUILD, limit))
    tmp = tempfile.mkdtemp(prefix="tocher-slow.")
    d = Daemon(BUILD, tmp, "slow")
    try:
        slow = Trickler(d, N, EVERY)
        say("# %d connections opened from 127.0.0.1" % slow.open_count())
        time.sleep(2 * EVERY)
        t = worst(d, "127.0.0.2", 6)
        check("1 100 trickling connections from 127.0.0.1: /healthz from 127.0.0.2 within 2 s (worst %s)"
              % ("%.3f s" % t if t is not None else "none"), t is not None, "the daemon is off the air")
        time.sleep(max(0.0, slow.opened + HEADER_DEADLINE + 1.0 - time.time()))
        t = worst(d, "127.0.0.1", 4)
        check("past the %g s header deadline: /healthz from 127.0.0.1 within 2 s (worst %s)"
              % (HEADER_DEADLINE, "%.3f s" % t if t is not None else "none"), t is not None,
              "the trickling connections still hold the daemon")
        time.sleep(EVERY + 0.5)
        check("the trickling connections are closed (%d still open)" % slow.open_count(), slow.open_count() == 0,
              "they outlive the header deadline")
        slow.close()
        check("the daemon is alive", d.proc.poll() is None, d.stderr()[-400:])
    finally:
        d.kill()
        shutil.rmtree(tmp, ignore_errors=True)
    finish()


if __name__ == "__main__":
    main()
