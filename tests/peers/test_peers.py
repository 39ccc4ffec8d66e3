#!/usr/bin/python3
"""test_peers.py — tocher against the peers people use today, on the same mesh,
data and gradients: `normal` vs matplotlib's CubicTriInterpolator(kind='user')
(reduced HCT) and `affine` vs scipy's CloughTocher2DInterpolator given the same
gradients (its `grad` attribute). Runs the real CLI (argv[1]) on JSON files.
Ends with "N passed, N failed"; skips (0 passed) without scipy/matplotlib."""
import json
import os
import subprocess
import sys
import tempfile

try:
    import numpy as np
    import scipy.interpolate
    import scipy.spatial
    import matplotlib.tri as mtri
except ImportError as e:  # the CI installs them; a bare machine may not have them
    print("skipped: %s (install python3-scipy python3-matplotlib)" % e)
    print("0 passed, 0 failed")
    sys.exit(0)

CLI = sys.argv[1] if len(sys.argv) > 1 else "build/tocher"
TOL = 1e-12
passed = failed = 0


def check(name, ok, detail):
    global passed, failed
    print("%s %s: %s" % ("ok  " if ok else "FAIL", name, detail))
    passed += ok
    failed += not ok


def f(x, y, ch=0):
    a = 1.0 + 0.4 * ch
    v = np.sin(2 * a * x + 0.3) * np.cos(1.7 * y) + 0.5 * x * x * y
    gx = 2 * a * np.cos(2 * a * x + 0.3) * np.cos(1.7 * y) + x * y
    gy = -1.7 * np.sin(2 * a * x + 0.3) * np.sin(1.7 * y) + 0.5 * x * x
    return v, gx, gy


def unit_square_points(rng, n):
    """Corners, boundary points and jittered interior points: the hull is the
    unit square, so matplotlib's x/y rescaling (by their ranges) is the identity."""
    pts = [(0, 0), (1, 0), (1, 1), (0, 1)]
    for t in np.linspace(0.1, 0.9, 7):
        pts += [(t, 0), (1, t), (t, 1), (0, t)]
    pts += list(map(tuple, 0.03 + 0.94 * rng.random((n, 2))))
    return np.array(pts, dtype=float)


def tocher_eval(request, points):
    with tempfile.TemporaryDirectory() as d:
        mesh, pts = os.path.join(d, "mesh.json"), os.path.join(d, "points.json")
        with open(mesh, "w") as fh:
            json.dump(request, fh)
        with open(pts, "w") as fh:
            json.dump({"points": points.tolist()}, fh)
        out = subprocess.run([CLI, "eval", mesh, pts], capture_output=True, text=True)
    if out.returncode != 0:
        raise RuntimeError("tocher eval failed: " + out.stderr)
    res = json.loads(out.stdout)
    if res["outside"]:
        raise RuntimeError("points reported outside: %s" % res["outside"][:5])
    return np.array(res["values"], dtype=float)


def run(seed, nchan):
    rng = np.random.default_rng(seed)
    P = unit_square_points(rng, 60)
    tri = scipy.spatial.Delaunay(P)
    T = tri.simplices.astype(int)
    x, y = P[:, 0], P[:, 1]
    chans = [f(x, y, ch) for ch in range(nchan)]
    Z = np.stack([c[0] for c in chans], axis=1)                                    # (n, C)
    G = np.stack([np.stack([c[1], c[2]], axis=1) for c in chans], axis=1)        # (n, C, 2)
    Q = 0.002 + 0.996 * rng.random((2000, 2))
    base = {"vertices": P.tolist(), "triangles": T.tolist(),
            "values": Z[:, 0].tolist() if nchan == 1 else Z.tolist(),
            "gradients": G[:, 0, :].tolist() if nchan == 1 else G.tolist(),
            "method": "clough-tocher", "tangents": "given",
            "range": "free"}  # the paper's cubic: the peers do not limit their range
    scale = np.abs(Z).max()

    # normal vs matplotlib's reduced HCT
    got = tocher_eval(dict(base, cross_boundary="normal"), Q).reshape(len(Q), nchan)
    triang = mtri.Triangulation(x, y, T)
    for ch in range(nchan):
        ip = mtri.CubicTriInterpolator(triang, Z[:, ch], kind="user", dz=(G[:, ch, 0], G[:, ch, 1]))
        want = np.asarray(ip(Q[:, 0], Q[:, 1]).filled(np.nan))
        err = np.nanmax(np.abs(got[:, ch] - want)) / scale
        check("normal == matplotlib CubicTriInterpolator(kind='user') [seed %d, ch %d/%d]" % (seed, ch, nchan),
              np.isfinite(want).all() and err <= TOL, "max relative difference %.2e" % err)

    # affine vs scipy's CloughTocher2DInterpolator with the same gradients
    got = tocher_eval(dict(base, cross_boundary="affine"), Q).reshape(len(Q), nchan)
    ip = scipy.interpolate.CloughTocher2DInterpolator(tri, Z)
    ip.grad = G.copy()
    want = ip(Q)
    err = np.nanmax(np.abs(got - want)) / scale
    check("affine == scipy CloughTocher2DInterpolator(grad=given) [seed %d, %d ch]" % (seed, nchan),
          np.isfinite(want).all() and err <= TOL, "max relative difference %.2e" % err)

    # The check can fail: the two cross-boundary rules differ from each other.
    diff = np.abs(tocher_eval(dict(base, cross_boundary="normal"), Q)
                  - tocher_eval(dict(base, cross_boundary="affine"), Q)).max() / scale
    check("normal and affine differ (the comparison above can fail) [seed %d]" % seed, diff > 1e-6,
          "max relative difference %.2e" % diff)


for seed, nchan in ((1, 1), (2, 1), (3, 3)):
    run(seed, nchan)
print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
