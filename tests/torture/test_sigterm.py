#!/usr/bin/env python3
"""test_sigterm.py — SIGTERM under load at full size (issue 14, 2.7): 20 rounds of 16
clients (half on keep-alive connections, half a new connection per request) and two long
renders, SIGTERM mid-way: every request sent whole gets its answer or a 503 with
Retry-After, never a reset; the daemon exits 0.

    /usr/bin/python3 tests/torture/test_sigterm.py BUILD_DIR"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pylib"))
import loadkit  # noqa: E402
from tochertest import finish  # noqa: E402

loadkit.sigterm(loadkit.build_dir(sys.argv), "sigterm", rounds=20, clients=16, render_s=1.0)
finish()
