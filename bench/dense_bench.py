#!/usr/bin/env python3
"""Dense-scan benchmark (issue 12; a command that prints figures, not a test).

    bench/dense_bench.py [--runs N] [--levels 0,1,2,3] [--tau PCT] [--mesh OFF]

Makes the mesh (default: bunny00 of the libcgal-demo data) denser by midpoint subdivision
(every triangle split into four at its edge midpoints: the same shape; level L gives 4^L times
the triangles: x4, x16, x64) with build/midpoint_subdivide, runs meshlab_scripts/run_pipeline.sh
on each (N runs, default 3) and prints the medians of: wall time, peak memory of the whole
process tree (meshlabserver, Xvfb and the shell scripts: the sum of their resident sets, sampled
every 0.1 s), and the report's figures (patches, irregular vertices, unprojectable %, RMS limit /
displaced error in 1/1000 of the bbox diagonal, per-stage times). Also prints the quality targets
of issue 12 against level 0 (patches and RMS limit within 15 %, unprojectable <= 0.1 %, RMS
displaced <= 0.08 permille). Uses the installed plugin (run scripts/setup.sh first).
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def tree_rss_kb(root):
    """Sum of VmRSS over `root` and all its descendants (kB)."""
    children = {}
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/stat") as f:
                ppid = int(f.read().rsplit(")", 1)[1].split()[1])
            children.setdefault(ppid, []).append(int(pid))
        except (OSError, IndexError, ValueError):
            pass
    total, todo = 0, [root]
    while todo:
        p = todo.pop()
        todo.extend(children.get(p, []))
        try:
            with open(f"/proc/{p}/status") as f:
                for line in f:
                    if line.startswith("VmRSS:"):
                        total += int(line.split()[1])
        except OSError:
            pass
    return total


def run_pipeline(mesh, out, tau):
    env = dict(os.environ, FITMAP_SKIP_SETUP="1")
    cmd = [os.path.join(REPO, "meshlab_scripts", "run_pipeline.sh"), "--tau", str(tau), mesh, out]
    t0 = time.monotonic()
    with open(out + ".log", "w") as log:
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env)
        peak = 0
        while proc.poll() is None:
            peak = max(peak, tree_rss_kb(proc.pid))
            time.sleep(0.1)
    wall = time.monotonic() - t0
    if proc.returncode != 0:
        sys.exit(f"pipeline failed on {mesh}: see {out}.log")
    with open(os.path.join(out, "report.json")) as f:
        return wall, peak / 1024.0, json.load(f)


def dense_mesh(src, level, cache):
    if level == 0:
        return src
    dst = os.path.join(cache, f"{os.path.splitext(os.path.basename(src))[0]}_x{4 ** level}.off")
    if not os.path.exists(dst):
        tool = os.path.join(os.environ.get("FITMAP_BUILD_DIR", os.path.join(REPO, "build")), "midpoint_subdivide")
        subprocess.run([tool, src, dst, str(level)], check=True)
    return dst


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--levels", default="0,1,2,3")
    ap.add_argument("--tau", type=float, default=1.0)
    ap.add_argument("--mesh", default=os.path.join(REPO, ".deps", "data", "meshes", "bunny00.off"))
    ap.add_argument("--cache", default=os.path.join(tempfile.gettempdir(), "fitmap_dense"))
    a = ap.parse_args()
    os.makedirs(a.cache, exist_ok=True)
    levels = [int(x) for x in a.levels.split(",")]
    work = tempfile.mkdtemp(prefix="fitmap_dense_bench.")
    rows = []
    for level in levels:
        mesh = dense_mesh(a.mesh, level, a.cache)
        runs = [run_pipeline(mesh, os.path.join(work, f"L{level}_{r}"), a.tau) for r in range(a.runs)]
        rep = runs[0][2]
        med = lambda key: statistics.median(r[2][key] for r in runs)
        stages = {k: statistics.median(r[2]["time_s"][k] for r in runs) for k in rep["time_s"]}
        mem = {k: statistics.median(r[2]["peak_memory_mb_per_stage"][k] for r in runs)
               for k in rep.get("peak_memory_mb_per_stage", {})}
        rows.append(dict(level=level, tris=rep["reference_faces"], wall=statistics.median(r[0] for r in runs),
                         peak=statistics.median(r[1] for r in runs), patches=med("patches"),
                         irregular=med("irregular_vertices"), unp=med("unprojectable_pct"),
                         L=med("rms_limit_permille"), D=med("rms_displaced_permille"), stages=stages, mem=mem))
    load = os.getloadavg()
    print(f"Dense-scan benchmark {time.strftime('%Y-%m-%d %H:%M')}, {os.cpu_count()} cores, load average "
          f"{load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} (1 / 5 / 15 min) at the end; tau {a.tau} %; "
          f"median of {a.runs} runs; errors in 1/1000 of the bbox diagonal")
    hdr = f"{'input':<12}{'triangles':>10}{'wall s':>8}{'peak MB':>9}{'patches':>8}{'irreg.':>7}{'unp.%':>7}{'RMS L':>7}{'RMS D':>8}  stages (s)"
    print(hdr)
    print("-" * len(hdr))
    for r in rows:
        st = ", ".join(f"{k} {v:.1f}" for k, v in r["stages"].items() if k != "total" and v >= 0.05)
        print(f"{'x' + str(4 ** r['level']):<12}{r['tris']:>10}{r['wall']:>8.1f}{r['peak']:>9.0f}{r['patches']:>8.0f}"
              f"{r['irregular']:>7.0f}{r['unp']:>7.3f}{r['L']:>7.3f}{r['D']:>8.4f}  {st}")
    print("Peak resident memory per stage of meshlabserver (MB; report.json peak_memory_mb_per_stage):")
    for r in rows:
        print(f"  x{4 ** r['level']}: " + ", ".join(f"{k} {v:.0f}" for k, v in r["mem"].items()))
    base = next((r for r in rows if r["level"] == 0), None)
    if base:
        print("Quality targets against x1 (patches and RMS L within 15 %, unprojectable <= 0.1 %, RMS D <= 0.08):")
        for r in rows:
            if r is base:
                continue
            dp = 100 * (r["patches"] / base["patches"] - 1)
            dl = 100 * (r["L"] / base["L"] - 1)
            ok = abs(dp) <= 15 and abs(dl) <= 15 and r["unp"] <= 0.1 and r["D"] <= 0.08
            print(f"  x{4 ** r['level']}: patches {dp:+.1f} %, RMS L {dl:+.1f} %, unprojectable {r['unp']:.3f} %, "
                  f"RMS D {r['D']:.4f} -> {'met' if ok else 'NOT met'}")


if __name__ == "__main__":
    main()
