#!/usr/bin/env python3
"""test_manifests.py — the deployment files parse and say what issue 16 asks: deploy/k8s/*.yaml
(Python's yaml), docker/compose.yaml, deploy/nginx/tocher.conf (against the daemon's own --help
defaults, and `nginx -t` on both its rendering and the Kubernetes ConfigMap's copy):

    /usr/bin/python3 tests/cluster/test_manifests.py BUILD_DIR

One "ok"/"FAIL" line per check, then "N passed, N failed".
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "pylib"))
sys.path.insert(0, os.path.join(ROOT, "deploy"))
from tochertest import check, finish  # noqa: E402
from cluster import NGINX, nginx_main_conf, render_nginx  # noqa: E402

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
if not os.path.isabs(BUILD) and not os.path.isdir(BUILD):
    BUILD = os.path.join(ROOT, BUILD)
K8S = os.path.join(ROOT, "deploy", "k8s")
CONF = os.path.join(ROOT, "deploy", "nginx", "tocher.conf")


def dig(d, *path, default=None):
    for p in path:
        if isinstance(d, dict) and p in d:
            d = d[p]
        elif isinstance(d, list) and isinstance(p, int) and p < len(d):
            d = d[p]
        else:
            return default
    return d


def flag(args, name):
    """The value after name in an argument list, or None."""
    return args[args.index(name) + 1] if name in args and args.index(name) + 1 < len(args) else None


def nginx_t(site_text):
    """`nginx -t` on site_text inside a generated main config; (ok, output)."""
    d = tempfile.mkdtemp(prefix="tocher-nginx-t.")
    try:
        site = os.path.join(d, "site.conf")
        with open(site, "w") as f:
            f.write(site_text)
        os.makedirs(os.path.join(d, "nginx-tmp"))
        conf = os.path.join(d, "nginx.conf")
        with open(conf, "w") as f:
            f.write(nginx_main_conf(d, site))
        r = subprocess.run([NGINX, "-t", "-e", os.path.join(d, "err.log"), "-p", d, "-c", conf],
                           capture_output=True, text=True, timeout=30)
        return r.returncode == 0, (r.stdout + r.stderr).strip()
    finally:
        shutil.rmtree(d, ignore_errors=True)


def main():
    # ---- Kubernetes ----
    docs, bad = {}, []
    files = sorted(f for f in os.listdir(K8S) if f.endswith(".yaml"))
    for f in files:
        try:
            with open(os.path.join(K8S, f)) as fh:
                for d in yaml.safe_load_all(fh):
                    if d:
                        docs.setdefault(d["kind"], []).append(d)
                        if not (d.get("apiVersion") and dig(d, "metadata", "name") is not None or d["kind"] == "Kustomization"):
                            bad.append("%s: %s without apiVersion or name" % (f, d["kind"]))
        except (yaml.YAMLError, KeyError, TypeError) as e:
            bad.append("%s: %s" % (f, e))
    check("deploy/k8s: %d files parse, every object has apiVersion, kind, name" % len(files), files and not bad, bad)
    kust = (docs.get("Kustomization") or [{}])[0]
    check("kustomization.yaml lists every other manifest",
          sorted(kust.get("resources", [])) == sorted(f for f in files if f != "kustomization.yaml"), kust.get("resources"))

    def named(kind, name):
        return next((d for d in docs.get(kind, []) if dig(d, "metadata", "name") == name), None)

    dep = named("Deployment", "tocherd") or {}
    pod = dig(dep, "spec", "template", "spec", default={})
    c = dig(pod, "containers", 0, default={})
    args = c.get("args", [])
    check("tocherd: readinessProbe GET /readyz", dig(c, "readinessProbe", "httpGet", "path") == "/readyz", c.get("readinessProbe"))
    check("tocherd: livenessProbe GET /healthz", dig(c, "livenessProbe", "httpGet", "path") == "/healthz", c.get("livenessProbe"))
    res = c.get("resources", {})
    check("tocherd: cpu and memory requested, memory limited",
          all(dig(res, *p) for p in (("requests", "cpu"), ("requests", "memory"), ("limits", "memory"))), res)
    pre = dig(c, "lifecycle", "preStop", "exec", "command", default=[])
    sleep = int(pre[-1]) if pre and pre[0] == "sleep" else None
    grace = flag(args, "--shutdown-grace")
    tgps = pod.get("terminationGracePeriodSeconds", 30)
    check("tocherd: preStop sleep, terminationGracePeriodSeconds (%s) > sleep (%s) + --shutdown-grace (%s)" % (tgps, sleep, grace),
          sleep is not None and grace is not None and tgps > sleep + int(grace), pre)
    psc, csc = pod.get("securityContext", {}), c.get("securityContext", {})
    check("tocherd: runAsNonRoot with a numeric non-zero uid, read-only root, no privilege escalation, no capabilities",
          psc.get("runAsNonRoot") is True and isinstance(psc.get("runAsUser"), int) and psc["runAsUser"] > 0 and
          csc.get("readOnlyRootFilesystem") is True and csc.get("allowPrivilegeEscalation") is False and
          dig(csc, "capabilities", "drop") == ["ALL"], (psc, csc))
    env = {e["name"]: e.get("value") for e in c.get("env", [])}
    check("tocherd: listens beyond loopback, behind a proxy (no per-address limit)",
          env.get("TOCHER_LISTEN", "").startswith("0.0.0.0:") and flag(args, "--max-connections-per-ip") == "0", (env, args))
    rsvc = named("Service", "redis") or {}
    store = flag(args, "--store") or ""
    rport = dig(rsvc, "spec", "ports", 0, "port")
    check("tocherd: --store redis:// names the redis Service and its port (%s)" % store,
          store == "redis://%s:%s" % (dig(rsvc, "metadata", "name"), rport), store)
    labels = dig(dep, "spec", "template", "metadata", "labels", default={})
    svcs = [d for d in docs.get("Service", []) if dig(d, "spec", "selector") and
            all(labels.get(k) == v for k, v in d["spec"]["selector"].items()) and d is not rsvc]
    headless = [s for s in svcs if dig(s, "spec", "clusterIP") == "None"]
    check("tocherd: a Service and two headless Services (ready pods; all pods) select its pods",
          len(svcs) >= 3 and len(headless) == 2 and dig(dep, "spec", "selector", "matchLabels", "app.kubernetes.io/name")
          == labels.get("app.kubernetes.io/name"), [dig(s, "metadata", "name") for s in svcs])
    hpa = (docs.get("HorizontalPodAutoscaler") or [{}])[0]
    tgt = dig(hpa, "spec", "scaleTargetRef", default={})
    cpu = [m for m in dig(hpa, "spec", "metrics", default=[]) if dig(m, "resource", "name") == "cpu"]
    check("HorizontalPodAutoscaler autoscaling/v2 scales Deployment tocherd on CPU, min <= max",
          hpa.get("apiVersion") == "autoscaling/v2" and tgt.get("kind") == "Deployment" and tgt.get("name") == "tocherd"
          and cpu and dig(cpu[0], "resource", "target", "averageUtilization") and
          1 <= dig(hpa, "spec", "minReplicas", default=1) <= dig(hpa, "spec", "maxReplicas", default=0), hpa.get("spec"))
    rconf = dig(named("ConfigMap", "redis-config"), "data", "redis.conf", default="")
    mm = re.search(r"^maxmemory (\d+)gb$", rconf, re.M)
    rdep = dig(named("Deployment", "redis"), "spec", "template", "spec", default={})
    rlim = dig(rdep, "containers", 0, "resources", "limits", "memory", default="0Mi")
    lim_mb = int(rlim[:-2]) * (1024 if rlim.endswith("Gi") else 1) if rlim[-2:] in ("Mi", "Gi") else 0
    check("redis: maxmemory with allkeys-lru, below its container's memory limit (%s)" % rlim,
          mm and "maxmemory-policy allkeys-lru" in rconf and lim_mb > int(mm.group(1)) * 1024 and
          dig(rdep, "volumes", 0, "configMap", "name") == "redis-config", rconf)
    check("redis: probes run redis-cli ping, non-root",
          dig(rdep, "containers", 0, "readinessProbe", "exec", "command") == ["redis-cli", "ping"] and
          dig(rdep, "securityContext", "runAsNonRoot") is True, rdep.get("securityContext"))

    # nginx in Kubernetes: the same config as deploy/nginx/tocher.conf, upstreams resolved.
    with open(CONF) as f:
        conf = f.read()
    cm = dig(named("ConfigMap", "nginx-tocher"), "data", "tocher.conf", default="")
    check("nginx ConfigMap: hash $mesh_id consistent", "hash $mesh_id consistent;" in cm)
    ns = dig(dep, "metadata", "namespace")
    ready = [dig(s, "metadata", "name") for s in headless if not dig(s, "spec", "publishNotReadyAddresses")]
    anyp = [dig(s, "metadata", "name") for s in headless if dig(s, "spec", "publishNotReadyAddresses") is True]
    fq = ["%s.%s.svc.cluster.local:8080" % (n, ns) for n in ready[:1] + anyp[:1]]
    ups = [re.search(r"^\s*server (\S+) resolve", b, re.M) for b in re.findall(r"upstream (\w+) \{([^}]*)\}", cm)
           for b in [b[1]]]
    ups = [u.group(1) if u else None for u in ups]
    check("nginx ConfigMap: the hashed upstream resolves the ready pods, the round-robin one all pods (%s)" % fq,
          len(fq) == 2 and ups == fq and len(re.findall(r"^\s*zone \w+ \d+m;", cm, re.M)) == 2, ups)

    def core(text):
        """The config without comments, the upstreams' server/zone lines and the resolver."""
        out = []
        for line in text.split("\n"):
            s = line.split("#", 1)[0].strip()
            if s and not re.match(r"(server \S+:8080 |zone |resolver )", s):
                out.append(s)
        return out
    check("nginx ConfigMap equals deploy/nginx/tocher.conf but for the upstreams' servers", core(cm) == core(conf),
          [x for x in core(cm) if x not in core(conf)] + [x for x in core(conf) if x not in core(cm)])
    # nginx 1.22 (Debian's) lacks "resolve" (1.27.3): checked with the pods' name replaced by an address.
    k8s_local = re.sub(r"server \S+:8080 resolve", "server 127.0.0.1:9", cm).replace("listen 80;", "listen 127.0.0.1:9;")
    k8s_local = re.sub(r"^resolver .*$", "", k8s_local, flags=re.M).replace("/var/cache/nginx/tocher", "nginx-cache")
    ok, out = nginx_t(k8s_local)
    check("nginx -t accepts the ConfigMap's config (pods' name replaced by an address)", ok, out[-300:])
    ndep = dig(named("Deployment", "nginx"), "spec", "template", "spec", default={})
    check("nginx Deployment mounts the ConfigMap as conf.d/default.conf, probes /nginx-health",
          dig(ndep, "volumes", 0, "configMap", "name") == "nginx-tocher" and
          dig(ndep, "volumes", 0, "configMap", "items", 0, "path") == "default.conf" and
          dig(ndep, "containers", 0, "readinessProbe", "httpGet", "path") == "/nginx-health", ndep.get("volumes"))

    # ---- deploy/nginx/tocher.conf against the daemon ----
    helptext = subprocess.run([os.path.join(BUILD, "tocherd"), "--help"], capture_output=True, text=True).stdout
    mb = re.search(r"TOCHER_MAX_BODY, default (\d+)", helptext)
    cmbs = re.search(r"client_max_body_size (\d+)m;", conf)
    check("tocher.conf: client_max_body_size (%s MiB) = tocherd's --max-body default (%s)" %
          (cmbs and cmbs.group(1), mb and mb.group(1)), mb and cmbs and int(cmbs.group(1)) << 20 == int(mb.group(1)))
    nu = re.search(r"^\s*proxy_next_upstream ([^;]*);", conf, re.M)
    check("tocher.conf: proxy_next_upstream error timeout http_502 http_503, idempotent requests only",
          nu and set(nu.group(1).split()) == {"error", "timeout", "http_502", "http_503"}, nu and nu.group(0))
    check("tocher.conf: hash on the mesh id for mesh routes, keep-alive upstreams, a tile cache",
          conf.count("hash $mesh_id consistent;") == 1 and conf.count("keepalive 32;") == 2 and
          'proxy_set_header Connection "";' in conf and "proxy_http_version 1.1;" in conf and
          "proxy_cache tocher_tiles;" in conf and "proxy_cache_valid 200 1y;" in conf)
    ok, out = nginx_t(render_nginx(conf, ["127.0.0.1:9", "127.0.0.1:10"], "127.0.0.1:9", "nginx-cache"))
    check("nginx -t accepts tocher.conf rendered for loopback", ok, out[-300:])

    # ---- docker/compose.yaml ----
    with open(os.path.join(ROOT, "docker", "compose.yaml")) as f:
        comp = yaml.safe_load(f)
    svc = comp.get("services", {})
    reps = sorted(n for n in svc if n.startswith("tocherd-"))
    check("compose: redis, 3 tocherd replicas, nginx; a health check on every service",
          {"redis", "nginx"} <= set(svc) and len(reps) == 3 and all(dig(s, "healthcheck", "test") for s in svc.values()),
          list(svc))
    okr = all("http://127.0.0.1:8080/readyz" in dig(svc[r], "healthcheck", "test", default=[]) and
              flag(svc[r].get("command", []), "--store") == "redis://redis:6379" and
              dig(svc[r], "build", "dockerfile") == "docker/Dockerfile" for r in reps)
    check("compose: replicas built from docker/Dockerfile, --store redis://redis:6379, health from /readyz", okr)
    gp = [svc[r].get("stop_grace_period", "10s") for r in reps]
    check("compose: stop_grace_period > --shutdown-grace",
          all(int(g.rstrip("s")) > int(flag(svc[r]["command"], "--shutdown-grace") or 30) for g, r in zip(gp, reps)), gp)
    vols = svc.get("nginx", {}).get("volumes", [])
    src = vols[0].split(":")[0] if vols else ""
    check("compose: nginx mounts deploy/nginx/tocher.conf, waits for healthy replicas",
          os.path.normpath(os.path.join(ROOT, "docker", src)) == CONF and
          all(dig(svc["nginx"], "depends_on", r, "condition") == "service_healthy" for r in reps), vols)
    upn = re.findall(r"server (tocherd-\d+):8080", conf)
    check("tocher.conf's upstream servers are compose's replicas", sorted(set(upn)) == reps and len(upn) == 2 * len(reps), upn)
    finish()


if __name__ == "__main__":
    main()
