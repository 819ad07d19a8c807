#!/usr/bin/env python3
"""Paired A/B comparison of two penumbra binaries on `accel-bench`.

The machines are shared and noisy, so a change to a structure is judged by running the old and
the new binary alternately on the same mesh (ABBA order: pair k runs old then new when k is even,
new then old when it is odd, so that a slow drift of the machine favours neither), and by
comparing ratios rather than rates:

- `x Embree` is each binary's own paired ratio against Embree 3 in the same run (accel-bench
  alternates the two every 131,072 rays), the steadiest figure when Embree is built in;
- `new/old` is, per pair, the new binary's figure over the old one's (its x Embree ratio when
  Embree ran, its rate otherwise), reported as the median and range over the pairs.

Usage:
  bench/ab_accel.py OLD NEW MESH [--pairs 2] [--accel bvh] [--threads 1] [--rays 500000]
                    [--repeat 3] [--image N] [--json OUT] [-- more accel-bench arguments]

OLD and NEW are penumbra executables (copy the old build aside before rebuilding). Prints one
table per structure and thread count; --json writes every run's figures and the summary.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

CELLS = ("primary", "incoherent", "occlusion", "bounce", "shadow")


def parse_args(argv):
    extra = []
    if "--" in argv:
        cut = argv.index("--")
        argv, extra = argv[:cut], argv[cut + 1:]
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("old", help="the old penumbra executable")
    p.add_argument("new", help="the new penumbra executable")
    p.add_argument("mesh", help="mesh or scene for accel-bench")
    p.add_argument("--pairs", type=int, default=2, help="old/new pairs to run (default 2)")
    p.add_argument("--accel", default="bvh", help="structures, as accel-bench's --accel")
    p.add_argument("--threads", default="1", help="thread counts, as accel-bench's --threads")
    p.add_argument("--rays", type=int, default=500000, help="incoherent rays (default 500000)")
    p.add_argument("--repeat", type=int, default=3, help="runs per measurement (default 3)")
    p.add_argument("--image", type=int, help="side of the primary rays' image")
    p.add_argument("--json", help="write every run and the summary to this file")
    args = p.parse_args(argv)
    if args.pairs < 1:
        p.error("--pairs must be at least 1")
    for exe in (args.old, args.new):
        if not (os.path.isfile(exe) and os.access(exe, os.X_OK)):
            p.error(f"{exe}: not an executable file")
    if not os.path.isfile(args.mesh):
        p.error(f"{args.mesh}: no such file")
    args.extra = extra
    return args


def run_once(exe, args, out_json):
    cmd = [exe, "accel-bench", args.mesh, "--accel", args.accel, "--threads", args.threads,
           "--rays", str(args.rays), "--repeat", str(args.repeat), "--json", out_json]
    if args.image is not None:
        cmd += ["--image", str(args.image)]
    cmd += args.extra
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if proc.returncode != 0:
        tail = "\n".join(proc.stderr.strip().splitlines()[-5:])
        sys.exit(f"ab_accel: {' '.join(cmd)} exited with {proc.returncode}:\n{tail}")
    with open(out_json) as f:
        rows = json.load(f)
    figures = {}  # (accel, threads) -> {cell: (mrays, vs_embree or None)}
    for row in rows:
        if row["accel"].startswith("embree"):
            continue
        for r in row["runs"]:
            figures[(row["accel"], r["threads"])] = {
                c: (r[c + "_mrays"], r.get(c + "_vs_embree")) for c in CELLS}
    return figures


def span(values):
    lo, hi = f"{min(values):.2f}", f"{max(values):.2f}"
    return lo if lo == hi else f"{lo}-{hi}"


def summarise(runs):
    """runs: list of (old_figures, new_figures), one per pair."""
    keys = [k for k in runs[0][0] if all(k in o and k in n for o, n in runs)]
    summary = []
    for accel, threads in keys:
        rows = []
        for c in CELLS:
            old = [o[(accel, threads)][c] for o, _ in runs]
            new = [n[(accel, threads)][c] for _, n in runs]
            embree = all(v[1] is not None for v in old + new)
            i = 1 if embree else 0
            ratios = [b[i] / a[i] for a, b in zip(old, new) if a[i] > 0]
            rows.append({
                "cell": c,
                "old_mrays": [v[0] for v in old], "new_mrays": [v[0] for v in new],
                "old_vs_embree": [v[1] for v in old] if embree else None,
                "new_vs_embree": [v[1] for v in new] if embree else None,
                "new_over_old": ratios,
                "new_over_old_median": statistics.median(ratios) if ratios else None,
            })
        summary.append({"accel": accel, "threads": threads, "cells": rows})
    return summary


def print_summary(summary, pairs):
    for s in summary:
        embree = s["cells"][0]["old_vs_embree"] is not None
        unit = "x Embree" if embree else "Mrays/s"
        print(f"{s['accel']}, {s['threads']} thread(s), {pairs} pair(s); new/old of {unit}")
        print(f"  {'':<11} {'old ' + unit:>13} {'new ' + unit:>13} {'new/old':>8} {'range':>11}")
        for r in s["cells"]:
            old = r["old_vs_embree"] if embree else r["old_mrays"]
            new = r["new_vs_embree"] if embree else r["new_mrays"]
            med = r["new_over_old_median"]
            med_s = f"{med:.3f}" if med is not None else "-"
            rng = span(r["new_over_old"]) if r["new_over_old"] else "-"
            print(f"  {r['cell']:<11} {span(old):>13} {span(new):>13} {med_s:>8} {rng:>11}")


def main(argv):
    args = parse_args(argv)
    runs = []
    with tempfile.TemporaryDirectory(prefix="ab_accel_") as tmp:
        out = os.path.join(tmp, "run.json")
        for k in range(args.pairs):
            order = ("old", "new") if k % 2 == 0 else ("new", "old")
            got = {}
            for which in order:
                got[which] = run_once(getattr(args, which), args, out)
            runs.append((got["old"], got["new"]))
    summary = summarise(runs)
    if not summary:
        sys.exit("ab_accel: the two binaries reported no structure in common")
    print_summary(summary, args.pairs)
    if args.json:
        tmp_path = args.json + ".tmp"
        with open(tmp_path, "w") as f:
            json.dump({"old": args.old, "new": args.new, "mesh": args.mesh,
                       "accel": args.accel, "pairs": args.pairs, "summary": summary}, f, indent=1)
        os.replace(tmp_path, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
