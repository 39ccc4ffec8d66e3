"""data.py — what build/report wrote, read back: run.json (the run, its methods, scenes and
surfaces), results.csv (one row per scene x mesh x method), surfaces.csv and the scanlines."""
import csv
import json
import os


def _value(s):
    """A CSV field as int, float or text; '' as None."""
    if s == "":
        return None
    for conv in (int, float):
        try:
            return conv(s)
        except ValueError:
            pass
    return s


def read_csv(path):
    with open(path, newline="") as f:
        return [{k: _value(v) for k, v in row.items()} for row in csv.DictReader(f)]


def mesh_label(row):
    """The mesh's label as bench/plan.c writes it ("disc N=8", "adaptive t=0.05")."""
    if row["mesh"] == "adaptive":
        return "adaptive t=%g" % row["threshold"]
    return "%s N=%d" % (row["mesh"], row["density"])


class Run:
    """One measurement: lookups by (scene, mesh label, method)."""

    def __init__(self, datadir):
        self.dir = datadir
        with open(os.path.join(datadir, "run.json")) as f:
            self.info = json.load(f)
        self.c = self.info["constants"]
        self.methods = [m["name"] for m in self.info["methods"]]
        self.method_info = {m["name"]: m for m in self.info["methods"]}
        self.scene_info = {s["name"]: s for s in self.info["scenes"]}
        self.rows = read_csv(os.path.join(datadir, "results.csv"))
        self._by = {}
        for r in self.rows:
            r["label"] = mesh_label(r)
            self._by[(r["scene"], r["label"], r["method"])] = r
        present = {r["scene"] for r in self.rows}
        self.scenes = [s["name"] for s in self.info["scenes"] if s["name"] in present]
        labels = {r["label"] for r in self.rows}
        self.meshes = [m for m in self.info["meshes"] if m["label"] in labels]
        path = os.path.join(datadir, "surfaces.csv")
        self.surfaces = read_csv(path) if os.path.exists(path) else []

    def get(self, scene, label, method, ok_only=True):
        r = self._by.get((scene, label, method))
        return r if r and (r["status"] == "ok" or not ok_only) else None

    def any_on(self, scene, label):
        """A row of the mesh, one that ran if any did: for the mesh's own figures (vertices,
        triangles, the exact B's overshoot)."""
        rows = [r for r in (self.get(scene, label, m, ok_only=False) for m in self.methods) if r]
        return next((r for r in rows if r["status"] == "ok"), rows[0] if rows else None)

    def labels(self, kind=None):
        """The meshes measured, in plan order (of one kind)."""
        return [m["label"] for m in self.meshes if kind is None or m["kind"] == kind]

    def mesh(self, label):
        return next((m for m in self.meshes if m["label"] == label), None)

    def disc(self, n):
        label = "disc N=%d" % n
        return label if self.mesh(label) else None

    def skipped(self):
        return [r for r in self.rows if r["status"] != "ok"]

    def scanlines(self, scene):
        """{column: [values]} of <scene>-scanline.csv (x, y, reference, "method@mesh")."""
        path = os.path.join(self.dir, "%s-scanline.csv" % scene)
        if not os.path.exists(path):
            return {}
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
        return {h: [float(r[i]) for r in rows[1:]] for i, h in enumerate(rows[0])}

    def surface_rows(self, surface=None, c0=None, method=None):
        return [r for r in self.surfaces if (surface is None or r["surface"] == surface)
                and (c0 is None or r["c0_flags"] == c0) and (method is None or r["method"] == method)]

    def surface_row(self, surface, c0, method):
        rows = self.surface_rows(surface, c0, method)
        return rows[0] if rows and rows[0]["status"] == "ok" else None


def run_ms(r):
    return r["build_ms"] + r["render_ms"]
