#!/usr/bin/env python3
"""test_daemon_load.py — the daemon under load, short forms (tests/torture/ has the full
sizes), against real daemons started from BUILD_DIR:

    /usr/bin/python3 tests/endpoint/test_daemon_load.py BUILD_DIR

  1. head-of-line blocking: small /v1/ordinates on pre-opened keep-alive connections stay
     fast while as many long renders run as there are HTTP threads, and none is dropped;
  2. a full worker queue answers 503 with Retry-After at once;
  3. /v1/ordinates, /v1/evaluate, /v1/compare stop at --request-timeout with a 503;
  4. SIGTERM with requests in the sockets: each gets an answer, none a reset.
One "ok"/"FAIL" line per check, then "N passed, N failed" (exit 1 on any failure).
Thresholds are generous: a loaded 2-core machine, and sanitizer builds, must pass."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pylib"))
import loadkit  # noqa: E402
from tochertest import finish  # noqa: E402

BUILD = loadkit.build_dir(sys.argv)
SAN = loadkit.is_san(BUILD)

# Renders of 2 s and more: before the worker pool the small requests waited that long.
loadkit.hol(BUILD, "hol", renders=2, conns=6, render_s=2.0, limit_s=1.0)
loadkit.queue_full(BUILD, "queue", render_s=2.0)
loadkit.deadlines(BUILD, "deadline", 60 if SAN else 120, 5000 if SAN else 20000)
loadkit.sigterm(BUILD, "sigterm", rounds=2, clients=8, render_s=1.0)
finish()
