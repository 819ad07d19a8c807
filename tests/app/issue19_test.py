#!/usr/bin/env python3
"""CTest Issue19.ChecksTheTargets: bench/issue19.py runs its rounds over two small meshes,
reports every mesh and target, writes a JSON whose medians lie within their ranges and whose
verdicts follow from them, merges the runs of --pin's bound one-thread process with the others',
and refuses bad input with a clear message, a non-zero exit and no JSON.

Usage: issue19_test.py PENUMBRA_CLI SOURCE_DIR
"""

import json
import os
import sys
import tempfile

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
from script_test import fail, run  # noqa: E402

CELLS = ("primary", "incoherent", "occlusion", "bounce", "shadow")


def check_stats(where, s):
    if s is None:
        return
    if not (s["min"] <= s["median"] <= s["max"]) or len(s["values"]) != 2:
        fail(f"{where}: median {s['median']} outside [{s['min']}, {s['max']}] or not 2 rounds")


def main():
    cli, src = sys.argv[1], sys.argv[2]
    script = os.path.join(src, "bench", "issue19.py")
    data = os.path.join(src, "tests", "data", "meshes")
    meshes = ",".join(os.path.join(data, m) for m in ("cube.obj", "cube.ply"))
    small = ["--rounds", "2", "--repeat", "1", "--rays", "2000", "--image", "16"]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "i19.json")
        p = run(script, "--penumbra", cli, "--meshes", meshes, "--threads", "1,2", *small,
                "--json", out)
        if p.returncode != 0:
            fail(f"exit {p.returncode}: {p.stderr}")
        for word in ("cube.obj", "cube.ply", "bvh over kdtree, 1 thr", "bvh over kdtree, 2 thr",
                     "kdtree within 2x of bvh in every set at 1 thread(s)", *CELLS):
            if word not in p.stdout:
                fail(f"'{word}' missing from the report:\n{p.stdout}")
        d = json.load(open(out))
        summary = d["summary"]
        if len(d["rounds"]) != 2 or summary["rounds"] != 2 or summary["threads"] != [1, 2]:
            fail(f"rounds {len(d['rounds'])}, threads {summary['threads']}")
        names = [m["mesh"] for m in summary["meshes"]]
        if names != ["cube.obj", "cube.ply"]:
            fail(f"meshes {names}")
        for m in summary["meshes"]:
            if m["triangles"] != 12 or m["mib"]["bvh"] <= 0:
                fail(f"{m['mesh']}: {m['triangles']} triangles, {m['mib']['bvh']} MiB")
            for t in ("1", "2"):
                for c in CELLS:
                    for kind in ("vs_embree", "over_kdtree"):
                        check_stats(f"{m['mesh']} {t} {c} {kind}", m["per_thread"][t][c][kind])
        # Each verdict follows from the medians it names.
        kd = [t for t in summary["targets"] if t["target"].startswith("kdtree within 2x")]
        if [t["threads"] for t in kd] != [1, 2]:
            fail(f"kd-tree targets {kd}")
        for t in kd:
            beyond = [f"{m['mesh']} {c}" for m in summary["meshes"] for c in CELLS
                      if m["per_thread"][str(t["threads"])][c]["over_kdtree"]["median"] > 2.0]
            if t["met"] != (not beyond) or len(t["misses"]) != len(beyond):
                fail(f"kd-tree verdict {t} against cells beyond 2x {beyond}")
        if all(m["embree"] for m in summary["meshes"]):
            inc = [t for t in summary["targets"]
                   if t["target"].startswith("incoherent >= 1.0") and t["threads"] == 1]
            want = all(m["per_thread"]["1"]["incoherent"]["vs_embree"]["median"] >= 1.0
                       for m in summary["meshes"])
            if len(inc) != 1 or inc[0]["met"] != want:
                fail(f"incoherent verdict {inc}, expected met = {want}")

        # --pin: the one-thread runs in a process of their own, bound to the CPU, merged with
        # the other thread counts' runs. A stand-in executable logs each run's thread count and
        # the CPUs it may use, then runs penumbra.
        cpu = min(os.sched_getaffinity(0))
        everyone = ",".join(map(str, sorted(os.sched_getaffinity(0))))
        log, fake = os.path.join(tmp, "affinity.log"), os.path.join(tmp, "fake_penumbra")
        real = os.path.abspath(cli)
        with open(fake, "w") as f:
            f.write(f"#!{sys.executable}\nimport os, sys\n"
                    f"with open({log!r}, 'a') as f:\n"
                    f"    cpus = ','.join(map(str, sorted(os.sched_getaffinity(0))))\n"
                    f"    f.write(sys.argv[4] + ' ' + cpus + '\\n')\n"
                    f"os.execv({real!r}, [{real!r}] + sys.argv[1:])\n")
        os.chmod(fake, 0o755)
        p = run(script, "--penumbra", fake, "--meshes", meshes, "--threads", "1,2", *small[2:],
                "--rounds", "1", "--pin", str(cpu), "--json", out)
        if p.returncode != 0:
            fail(f"--pin {cpu}: exit {p.returncode}: {p.stderr}")
        runs = [line.split() for line in open(log).read().splitlines()]
        want = [["2", everyone], ["1", str(cpu)]] * 2  # two meshes, one process per count
        if runs != want:
            fail(f"--pin {cpu}: runs (threads, CPUs) {runs}, expected {want}")
        for word in ("bvh over kdtree, 1 thr", "bvh over kdtree, 2 thr"):
            if word not in p.stdout:
                fail(f"--pin: '{word}' missing from the report:\n{p.stdout}")
        for name, rows in json.load(open(out))["rounds"][0].items():
            for accel, row in rows["full"].items():
                if [r["threads"] for r in row["runs"]] != [1, 2]:
                    fail(f"--pin: {name} {accel} runs at {[r['threads'] for r in row['runs']]}")

        # Bad input: a missing mesh, a mesh accel-bench refuses, a bad thread list or round
        # count, a missing executable. None writes JSON.
        bad_out = os.path.join(tmp, "bad.json")
        broken = os.path.join(tmp, "broken.obj")
        with open(broken, "w") as f:
            f.write("v 0 0\nf 1 2 3\n")
        for args, words in (
                (["--meshes", broken, *small], "exited with"),
                (["--meshes", os.path.join(tmp, "nope.obj")], "nope.obj: no such file"),
                (["--meshes", meshes, "--threads", "1,x"], "not a list of integers"),
                (["--meshes", meshes, "--rounds", "0"], "--rounds must be at least 1"),
                (["--meshes", meshes, "--pin", "100000"], "is not one this process may run on")):
            p = run(script, "--penumbra", cli, *args, "--json", bad_out)
            if p.returncode == 0 or words not in p.stderr:
                fail(f"{args}: exit {p.returncode}, {p.stderr}")
        p = run(script, "--penumbra", os.path.join(tmp, "nope"), "--meshes", meshes,
                "--json", bad_out)
        if p.returncode == 0 or "nope: not an executable file" not in p.stderr:
            fail(f"missing executable: exit {p.returncode}, {p.stderr}")
        if os.path.exists(bad_out) or os.path.exists(bad_out + ".tmp"):
            fail("a refused run left a JSON file")
    print("ok")


if __name__ == "__main__":
    main()
