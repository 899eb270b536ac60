#!/usr/bin/env python3
"""Runs every corpus input (tests/corpus/make_corpus.py) through the installed plugin end to end
with meshlabserver and gives each run a verdict (issue 16).

    tests/corpus/make_corpus.py /tmp/corpus
    tests/corpus/run_corpus.py [--filters fitmaps,pipeline,loop_refine,loop_curvature]
        [--timeout S] [--jobs N] [--include-dataset DIR] [--limit N] [--only 'a.off,nm_*,data/*']
        [--sample K]
        CORPUSDIR OUTDIR

fitmaps / loop_refine / loop_curvature run meshlab_scripts/<filter>.mlx through
scripts/meshlabserver.sh and save the result with `-o out.ply -m vq ...`; pipeline runs
`FITMAP_SKIP_SETUP=1 meshlab_scripts/run_pipeline.sh INPUT RUNDIR`, pipeline_budget the same
with `--patches 200` (a valid run above the budget must warn that it was not reached). Each run has a timeout
(default 120 s; the ctest test passes 300). Verdicts:
  valid             exit 0, outputs exist and are finite (pipeline: report.json with patches > 0
                    and a finite unprojectable_pct, every number finite)
  clear-error       non-zero exit with an "Error: ..." line from the plugin naming the problem
                    (and the manifest's keywords)
  crash             signal / abort / meshlabserver died without an Error line
  hang              timeout
  silent-wrong      exit 0 but a check fails, or the manifest expected an error
  unexpected-error  a clear error where the manifest expects a valid result
  unclear-error     an error whose message is internal or lacks the expected keywords
  crash-reader      MeshLab 2020.09's own importer died before the plugin ran (not ours)
  reader-error      MeshLab's importer refused the file cleanly before the plugin ran
--include-dataset DIR adds every DIR/*.off (expected valid; non-manifold: valid or error;
no faces: error). --sample K (the CI's data-set run, which would take 50 min on a slow 2-core CI
machine with every filter): every input runs the first filter (fitmaps) and every K-th input (in
name order) also one of the others, in turn; the other runs are not made (a line before the
table says how many were). Prints runs per verdict per filter, writes OUTDIR/verdicts.json (every run:
input, filter, verdict, message, exit code, seconds, log) and exits 1 if any run is a crash,
hang, silent-wrong, unexpected-error or unclear-error (crash-reader / reader-error are listed
only). Each run's files and log stay in OUTDIR/runs/<filter>/<input>/.
"""
import argparse
import concurrent.futures
import fnmatch
import json
import math
import os
import re
import shutil
import signal
import struct
import subprocess
import sys
import time

from make_corpus import BUDGET, FILTERS, read_off, topology

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FAILURES = ["crash", "hang", "silent-wrong", "unexpected-error", "unclear-error"]
VERDICTS = ["valid", "clear-error"] + FAILURES + ["crash-reader", "reader-error"]
SAVE_MASK = {"fitmaps": ["vq", "vc"], "loop_refine": ["vq"], "loop_curvature": ["vq", "vc"]}


# ----------------------------------------------------------------------------- output checks
PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
             "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f",
             "float32": "f", "double": "d", "float64": "d"}


def read_ply(path):
    """{element: [{property: value}]} of a PLY file (ascii / binary, scalar and list properties)."""
    with open(path, "rb") as fh:
        data = fh.read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    fmt, elements = None, []
    for line in data[:end].decode("ascii", "replace").splitlines():
        w = line.split()
        if w[:1] == ["format"]:
            fmt = w[1]
        elif w[:1] == ["element"]:
            elements.append((w[1], int(w[2]), []))
        elif w[:1] == ["property"]:
            elements[-1][2].append((w[-1], w[1:-1]))
    out = {}
    if fmt == "ascii":
        tok, pos = data[end:].split(), 0
        def scalar(t):
            nonlocal pos
            pos += 1
            return float(tok[pos - 1]) if PLY_TYPES[t] in "fd" else int(tok[pos - 1])
    else:
        bo, pos = "<" if fmt == "binary_little_endian" else ">", end
        def scalar(t):
            nonlocal pos
            c = PLY_TYPES[t]
            pos += struct.calcsize(c)
            return struct.unpack_from(bo + c, data, pos - struct.calcsize(c))[0]
    for name, count, props in elements:
        rows = []
        for _ in range(count):
            row = {}
            for pname, ptype in props:
                if ptype[0] == "list":
                    row[pname] = [scalar(ptype[2]) for _ in range(scalar(ptype[1]))]
                else:
                    row[pname] = scalar(ptype[0])
            rows.append(row)
        out[name] = rows
    return out


def check_ply(path, quality=False):
    """'' or what is wrong with a mesh output."""
    if not os.path.isfile(path) or os.path.getsize(path) == 0:
        return "%s was not written" % os.path.basename(path)
    try:
        ply = read_ply(path)
    except Exception as e:  # noqa: BLE001 - any parse failure is a finding
        return "%s is not a readable PLY (%s)" % (os.path.basename(path), e)
    verts, faces = ply.get("vertex", []), ply.get("face", [])
    name = os.path.basename(path)
    if not verts or not faces:
        return "%s has %d vertices and %d faces" % (name, len(verts), len(faces))
    if quality and "quality" not in verts[0]:
        return "%s has no vertex quality" % name
    for key in ("x", "y", "z", "quality"):
        bad = sum(1 for v in verts if key in v and not math.isfinite(v[key]))
        if bad:
            return "%s: %d vertices with non-finite %s" % (name, bad, key)
    idx = [i for f in faces for i in f.get("vertex_indices", f.get("vertex_index", []))]
    if any(i < 0 or i >= len(verts) for i in idx):
        return "%s: face index out of range" % name
    return ""


def check_pipeline(rundir, entry, budget=0):
    for f in ("fitmap.ply", "limit.ply", "displaced.ply"):
        err = check_ply(os.path.join(rundir, f), quality=True)
        if err:
            return err
    obj = os.path.join(rundir, "control.obj")
    if not os.path.isfile(obj):
        return "control.obj was not written"
    with open(obj) as fh:
        lines = fh.read().splitlines()
    coords = [float(x) for l in lines if l.startswith("v ") for x in l.split()[1:4]]
    if not any(l.startswith("f ") for l in lines) or not all(map(math.isfinite, coords)):
        return "control.obj has no faces or non-finite vertices"
    try:
        with open(os.path.join(rundir, "report.json")) as fh:
            rep = json.load(fh)
    except (OSError, ValueError) as e:
        return "report.json missing or unreadable (%s)" % e
    nums = []
    def walk(x, key):
        if isinstance(x, dict):
            for k, v in x.items():
                walk(v, key + "." + k)
        elif isinstance(x, list):
            for v in x:
                walk(v, key)
        elif isinstance(x, (int, float)) and not isinstance(x, bool):
            nums.append((key, x))
    walk(rep, "report")
    bad = [k for k, v in nums if not math.isfinite(v)]
    if bad:
        return "report.json has non-finite %s" % ", ".join(sorted(set(bad))[:3])
    if not rep.get("patches", 0) > 0:
        return "report.json: patches = %s" % rep.get("patches")
    if not isinstance(rep.get("unprojectable_pct"), (int, float)):
        return "report.json has no unprojectable_pct"
    if budget:
        # a budget missed without a word is a silent wrong result (the log must warn)
        log = open(os.path.join(rundir, "meshlab.log"), errors="replace").read()
        if rep["patches"] > budget + budget // 50 and "was not reached" not in log:
            return "%d patches for a budget of %d, and no warning that it was not reached" % (rep["patches"], budget)
        return ""
    for key, limit in entry.get("report_max", {}).items():
        if isinstance(rep.get(key), (int, float)) and rep[key] > limit:
            return "report.json: %s = %.3g > %g" % (key, rep[key], limit)
    return ""


# ----------------------------------------------------------------------------- running
def run(cmd, log, timeout, env=None):
    """Exit code of cmd (stdout+stderr line-buffered into log), or None after a timeout."""
    with open(log, "wb") as out:
        p = subprocess.Popen(["stdbuf", "-oL", "-eL"] + cmd, stdout=out, stderr=subprocess.STDOUT,
                             stdin=subprocess.DEVNULL, cwd=REPO, env=env, start_new_session=True)
        try:
            return p.wait(timeout)
        except subprocess.TimeoutExpired:
            for sig in (signal.SIGTERM, signal.SIGKILL):
                try:
                    os.killpg(p.pid, sig)
                except ProcessLookupError:
                    break
                try:
                    p.wait(5)
                    break
                except subprocess.TimeoutExpired:
                    pass
            return None


PREFIX = re.compile(r"^(Compute Fitmaps|Fitmap Quad Simplification|Fit Catmull-Clark Surface|Loop Surrogate|"
                    r"Refine Surface|Curvature|Snap Points|Fitmaps|reference layer):\s*")


def clear_message(msg):
    """A message a user can act on: words, not an internal step name or exception text."""
    core = msg
    while PREFIX.match(core):
        core = PREFIX.sub("", core, count=1)
    words = re.findall(r"[A-Za-z]{2,}", core)
    return len(words) >= 3 and not re.match(r"(internal error|std::|basic_string|vector::)", core)


def verdict_of(rc, text, out_error, entry, flt):
    """(verdict, message) of one run from its exit code, log text and output check."""
    exp = entry["expect"][flt]
    after = text[text.find("filter: "):] if "filter: " in text else ""
    errors = [m.group(1).strip() for m in re.finditer(r"^(?:LOG: \d+ )?\s*Error:\s*(.*)$", after, re.M)
              if "trying to save" not in m.group(1)]
    loaded = re.search(r"^Mesh .* loaded has ", text, re.M) is not None
    low = text.lower()
    if rc is None:
        return "hang", "no result after the timeout"
    missing = [k for k in entry.get("log_keywords", []) if k not in low]
    if rc == 0:
        if out_error:
            return "silent-wrong", out_error
        if missing:
            return "silent-wrong", "the log does not mention " + ", ".join(missing)
        if exp["verdict"] == "error":
            if any(k in low for k in entry.get("accept_valid_if_log", [])):
                return "valid", "repaired by MeshLab's loader: " + ", ".join(entry["accept_valid_if_log"])
            return "silent-wrong", "a result where an error was expected"
        return "valid", ""
    # xvfb-run reports a signal as 128 + N (meshlabserver's exit(-1) is 255); run_pipeline.sh says 1,
    # but the shell's report of the signal is in the log
    died = re.search(r"Segmentation fault|Aborted|core dumped|terminate called|Floating point exception|"
                     r"Terminated|Killed", text)
    signal_exit = 128 < rc <= 192 or rc < 0 or died is not None
    if not loaded and not errors:
        refused = re.search(r"(Opening (Failure|Error|Problems)|Meshlab Opening Error|not possible to import).*",
                            text)
        if refused and not signal_exit:
            return "reader-error", refused.group(0).strip()
        return "crash-reader", "meshlabserver died while loading (exit %s)" % rc
    if signal_exit:
        sig = rc - 128 if rc > 128 else -rc
        name = signal.Signals(sig).name if sig in signal.Signals._value2member_map_ else died.group(0)
        return "crash", "killed by %s%s" % (name, "; last error: " + errors[-1] if errors else "")
    if not errors:
        if "was not written" in text:
            return "silent-wrong", re.search(r".*was not written.*", text).group(0)
        problem = re.search(r"Problem with filter: .*", text)
        if problem:
            return "unclear-error", problem.group(0) + " (no Error: line)"
        return "crash", "meshlabserver died without an Error line (exit %s)" % rc
    msg = errors[0]
    if not clear_message(msg):
        return "unclear-error", msg
    if exp["verdict"] == "valid":
        return "unexpected-error", msg
    lmsg = msg.lower()
    lacking = [k for k in exp.get("keywords", []) if not any(a in lmsg for a in k.split("|"))]
    if lacking:
        return "unclear-error", msg + "  [lacks: " + ", ".join(lacking) + "]"
    if missing:
        return "unclear-error", msg + "  [log lacks: " + ", ".join(missing) + "]"
    return "clear-error", msg


def run_one(inp, entry, flt, outdir, timeout):
    rundir = os.path.join(outdir, "runs", flt, entry["name"].replace("/", "_"))
    shutil.rmtree(rundir, ignore_errors=True)
    os.makedirs(rundir)
    log = os.path.join(rundir, "run.log")
    t0 = time.time()
    if flt in ("pipeline", "pipeline_budget"):
        env = dict(os.environ, FITMAP_SKIP_SETUP="1")
        budget = BUDGET if flt == "pipeline_budget" else 0
        args = ["--patches", str(budget)] if budget else []
        rc = run([os.path.join(REPO, "meshlab_scripts", "run_pipeline.sh")] + args + [inp, rundir], log, timeout, env)
        mlog = os.path.join(rundir, "meshlab.log")
        text = open(log, errors="replace").read()
        if os.path.isfile(mlog):
            text = open(mlog, errors="replace").read() + "\n" + text
        out_error = check_pipeline(rundir, entry, budget) if rc == 0 else ""
    else:
        out = os.path.join(rundir, "out.ply")
        rc = run([os.path.join(REPO, "scripts", "meshlabserver.sh"), "-i", inp, "-o", out, "-m"] + SAVE_MASK[flt] +
                 ["-s", os.path.join(REPO, "meshlab_scripts", flt + ".mlx")], log, timeout)
        text = open(log, errors="replace").read()
        out_error = check_ply(out, quality=(flt != "loop_refine")) if rc == 0 else ""
    verdict, msg = verdict_of(rc, text, out_error, entry, flt)
    return {"input": entry["name"], "kind": entry.get("kind", ""), "filter": flt, "verdict": verdict,
            "message": msg, "expected": entry["expect"][flt]["verdict"], "exit": rc,
            "seconds": round(time.time() - t0, 1), "log": os.path.relpath(log, outdir)}


def dataset_entries(folder):
    """Manifest entries for DIR/*.off: valid (non-manifold edges and vertices too), no faces: error."""
    entries = []
    for name in sorted(f for f in os.listdir(folder) if f.endswith(".off")):
        path = os.path.join(folder, name)
        try:
            V, F = read_off(path)
            t = topology(V, F) if all(0 <= i < len(V) for f in F for i in f) else None
        except (ValueError, IndexError):
            t = None
        if t and t["faces"] == 0:
            exp, kind = ("error", ["no faces|point cloud|empty"]), "point-cloud"
        elif t and t["non_manifold_edges"]:  # triangles separated by the working copy (input_prep.h)
            exp, kind = ("valid", []), "non-manifold"
        elif t and t["non_manifold_vertices"]:  # split by the working copy (input_prep.h)
            exp, kind = ("valid", []), "non-manifold-vertex"
        else:
            exp, kind = ("valid", []), "dataset" if t else "dataset-unparsed"
        entries.append({"name": "data/" + name, "path": path, "kind": kind,
                        "expect": {f: {"verdict": exp[0], "keywords": exp[1]} for f in FILTERS}})
    return entries


def sampled_jobs(entries, filters, k):
    """(entry, filter) runs: all of them for k <= 1; else every entry with filters[0] and entry i
    (i % k == 0) also with filters[1 + (i // k) % (len(filters) - 1)]."""
    if k <= 1 or len(filters) < 2:
        return [(e, f) for e in entries for f in filters]
    jobs = []
    for i, e in enumerate(entries):
        jobs.append((e, filters[0]))
        if i % k == 0:
            jobs.append((e, filters[1 + (i // k) % (len(filters) - 1)]))
    return jobs


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("corpus")
    ap.add_argument("outdir")
    ap.add_argument("--filters", default=",".join(FILTERS))
    ap.add_argument("--timeout", type=float, default=120)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--include-dataset", metavar="DIR")
    ap.add_argument("--limit", type=int, help="only the first N inputs")
    ap.add_argument("--only", help="comma-separated input names or patterns (data/* = the dataset)")
    ap.add_argument("--sample", type=int, default=1, metavar="K",
                    help="every input runs the first filter, every K-th also one other in turn (default 1: all)")
    a = ap.parse_args()
    filters = a.filters.split(",")
    if any(f not in FILTERS for f in filters):
        ap.error("--filters: choose from " + ",".join(FILTERS))
    with open(os.path.join(a.corpus, "manifest.json")) as fh:
        entries = json.load(fh)["files"]
    for e in entries:
        e["path"] = os.path.abspath(os.path.join(a.corpus, e["name"]))
    if a.include_dataset:
        entries += dataset_entries(a.include_dataset)
    if a.only:
        entries = [e for e in entries if any(fnmatch.fnmatch(e["name"], p) for p in a.only.split(","))]
    entries = entries[:a.limit] if a.limit else entries
    outdir = os.path.abspath(a.outdir)
    os.makedirs(outdir, exist_ok=True)
    jobs = sampled_jobs(entries, filters, a.sample)
    if a.sample > 1:
        print("run_corpus: --sample %d: %d of %d runs (every input through %s, one input in %d also through one of %s "
              "in turn)" % (a.sample, len(jobs), len(entries) * len(filters), filters[0], a.sample,
                            ", ".join(filters[1:])), flush=True)
    results = []
    with concurrent.futures.ThreadPoolExecutor(max(1, a.jobs)) as pool:
        futs = [pool.submit(run_one, e["path"], e, f, outdir, a.timeout) for e, f in jobs]
        for k, fu in enumerate(concurrent.futures.as_completed(futs), 1):
            r = fu.result()
            results.append(r)
            print("[%d/%d] %-22s %-15s %-16s %5.1fs %s" % (k, len(jobs), r["input"], r["filter"], r["verdict"],
                                                           r["seconds"], r["message"][:110]), flush=True)
    order = {(e["name"], f): i for i, (e, f) in enumerate(jobs)}
    results.sort(key=lambda r: order[(r["input"], r["filter"])])
    table = {v: {f: sum(1 for r in results if r["verdict"] == v and r["filter"] == f) for f in filters}
             for v in VERDICTS}
    print("\n%-17s" % "verdict" + "".join("%16s" % f for f in filters))
    for v in VERDICTS:
        if any(table[v].values()):
            print("%-17s" % v + "".join("%16d" % table[v][f] for f in filters))
    failing = [r for r in results if r["verdict"] in FAILURES]
    readers = [r for r in results if r["verdict"] in ("crash-reader", "reader-error")]
    for title, rows in (("failing runs", failing), ("MeshLab reader problems (not counted)", readers)):
        if rows:
            print("\n%s:" % title)
            for r in rows:
                print("  %-22s %-15s %-16s %s" % (r["input"], r["filter"], r["verdict"], r["message"]))
    with open(os.path.join(outdir, "verdicts.json"), "w") as fh:
        json.dump({"table": table, "runs": results}, fh, indent=1)
        fh.write("\n")
    print("\nrun_corpus: %d runs, %d failing; %s" % (len(results), len(failing), os.path.join(outdir, "verdicts.json")))
    sys.exit(1 if failing else 0)


if __name__ == "__main__":
    main()
