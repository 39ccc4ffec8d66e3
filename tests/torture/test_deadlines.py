#!/usr/bin/env python3
"""test_deadlines.py — request deadlines at full size (issue 14, 2.5): /v1/ordinates,
/v1/compare on a 300 x 300 grid (180 000 triangles) and /v1/evaluate of 100 000 points
(16 channels, gradients) with
--request-timeout at 15 % of their time answer 503 "time limit" well before the computation
would end.

    /usr/bin/python3 tests/torture/test_deadlines.py BUILD_DIR"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pylib"))
import loadkit  # noqa: E402
from tochertest import finish  # noqa: E402

loadkit.deadlines(loadkit.build_dir(sys.argv), "deadline", 300, 100000)
finish()
