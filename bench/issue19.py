#!/usr/bin/env python3
"""Issue #19's targets ("Faster than Embree"), measured in interleaved rounds and checked.

Each round runs `penumbra accel-bench MESH --accel bvh,kdtree --versus kdtree` on every mesh in
turn, so that a machine whose load drifts during the hour affects every mesh alike; a second,
short run per mesh at one thread gives the build times at one thread (accel-bench builds with
the largest thread count it traces with). The report gives, per mesh and thread count, the
median and the range over the rounds of

- `bvh` x Embree 3 in each set of rays (primary, incoherent, occlusion, bounce, shadow: the
  ratios accel-bench pairs chunk by chunk with Embree's runs),
- `bvh` over `kdtree` (accel-bench's --versus quotients),
- build times, memory, and nodes and primitive tests per incoherent ray,

then one line per target of the issue, each said to be met or not by the medians (and whether
every round met it). The targets are those of the issue at one thread; the lines for the other
thread counts are reported alongside. Build time is judged on spheres-1m and the terrain (the
meshes the issue names), memory on every mesh.

Usage:
  bench/issue19.py [--penumbra build/penumbra] [--scenes ../shared/scenes] [--terrain PLY]
                   [--meshes PATH,PATH,...] [--rounds 3] [--threads 1,2] [--repeat 5]
                   [--rays 500000] [--image N] [--pin CPU] [--json OUT]

--pin CPU runs every one-thread measurement as a process of its own bound to that CPU (the
other thread counts in another process, unbound), so that the scheduler does not move it and a
CPU known to be slower can be left out. It does not remove a machine's slow episodes: on the
Zen 4 of docs/accel.md ("2026-12-07, twenty-first session") they slowed one side of the pair in
a process, mostly `bvh` (by up to 42 %), bound or not.

The default meshes are the issue's five: bunny.obj, human_blend.obj, cylinder_engine.obj and
spheres-1m.ply from --scenes, and the terrain of bench/make_terrain.py (--terrain, or written to
a temporary directory when not given). --json writes every round's figures and the summary
(through a temporary file and a rename: no partial file). With Embree not built in, accel-bench
prints no ratios to it, and only the targets that do not need them are checked.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

CELLS = ("primary", "incoherent", "occlusion", "bounce", "shadow")
HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SCENE_MESHES = ("bunny.obj", "human_blend.obj", "cylinder_engine.obj", "spheres-1m.ply")
# Meshes whose build time the issue judges (by file stem).
BUILD_MESHES = ("spheres-1m", "terrain")


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--penumbra", default=os.path.join(HERE, "..", "build", "penumbra"),
                   help="the penumbra executable (default build/penumbra)")
    p.add_argument("--scenes", default=os.path.join(HERE, "..", "..", "shared", "scenes"),
                   help="directory of the benchmark meshes (default ../shared/scenes)")
    p.add_argument("--terrain", help="the terrain PLY (default: written by make_terrain.py)")
    p.add_argument("--meshes", help="comma-separated meshes instead of the issue's five")
    p.add_argument("--rounds", type=int, default=3, help="rounds over every mesh (default 3)")
    p.add_argument("--threads", default="1,2", help="thread counts (default 1,2)")
    p.add_argument("--repeat", type=int, default=5, help="accel-bench --repeat (default 5)")
    p.add_argument("--rays", type=int, default=500000, help="incoherent rays (default 500000)")
    p.add_argument("--image", type=int, help="side of the primary rays' image")
    p.add_argument("--pin", type=int, metavar="CPU",
                   help="run the one-thread measurements bound to this CPU")
    p.add_argument("--json", help="write every round and the summary to this file")
    args = p.parse_args(argv)
    if args.rounds < 1:
        p.error("--rounds must be at least 1")
    try:
        args.thread_list = sorted({int(t) for t in args.threads.split(",")})
    except ValueError:
        p.error(f"--threads: '{args.threads}' is not a list of integers")
    if not args.thread_list or args.thread_list[0] < 1:
        p.error("--threads: thread counts must be at least 1")
    if args.pin is not None:
        if not hasattr(os, "sched_setaffinity"):
            p.error("--pin: this system cannot bind a process to a CPU")
        if args.pin not in os.sched_getaffinity(0):
            allowed = ",".join(str(c) for c in sorted(os.sched_getaffinity(0)))
            p.error(f"--pin: CPU {args.pin} is not one this process may run on ({allowed})")
    if not (os.path.isfile(args.penumbra) and os.access(args.penumbra, os.X_OK)):
        p.error(f"{args.penumbra}: not an executable file")
    if args.meshes:
        args.mesh_list = [m for m in args.meshes.split(",") if m]
    else:
        args.mesh_list = [os.path.join(args.scenes, m) for m in DEFAULT_SCENE_MESHES]
        if args.terrain:
            args.mesh_list.append(args.terrain)
    for m in args.mesh_list:
        if not os.path.isfile(m):
            p.error(f"{m}: no such file")
    return args


def stem(path):
    return os.path.splitext(os.path.basename(path))[0]


def mesh_names(paths):
    """Each mesh's name in the report: its file stem, or its file name where stems repeat."""
    stems = [stem(p) for p in paths]
    names = [s if stems.count(s) == 1 else os.path.basename(p) for s, p in zip(stems, paths)]
    if len(set(names)) != len(names):
        sys.exit("issue19: two meshes have the same file name; give each its own")
    return names


def accel_bench(args, mesh, threads, out_json, extra):
    """One accel-bench run's rows by structure; a one-thread run is bound to --pin's CPU."""
    cmd = [args.penumbra, "accel-bench", mesh, "--threads", threads, "--json", out_json] + extra

    def bind():  # in the child, before accel-bench starts
        os.sched_setaffinity(0, {args.pin})

    pinned = args.pin is not None and threads == "1"
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                          preexec_fn=bind if pinned else None)
    if proc.returncode != 0:
        tail = "\n".join(proc.stderr.strip().splitlines()[-5:])
        sys.exit(f"issue19: {' '.join(cmd)} exited with {proc.returncode}:\n{tail}")
    with open(out_json) as f:
        return {row["accel"].split(":")[0]: row for row in json.load(f)}


def measure(args, tmp):
    """Every round's rows: rounds[r][mesh stem] = {'full': {accel: row}, 'one': {accel: row}}."""
    rounds = []
    out = os.path.join(tmp, "run.json")
    bench = ["--accel", "bvh,kdtree", "--versus", "kdtree", "--repeat", str(args.repeat),
             "--rays", str(args.rays)]
    if args.image is not None:
        bench += ["--image", str(args.image)]
    # Build times at one thread: the sets of rays are made small, as only the builds count.
    builds = ["--accel", "bvh", "--repeat", "3", "--rays", "1000", "--image", "16"]
    names = mesh_names(args.mesh_list)
    for r in range(args.rounds):
        got = {}
        for mesh, name in zip(args.mesh_list, names):
            if args.pin is not None and 1 in args.thread_list and args.thread_list != [1]:
                # The other thread counts' process gives the rows (built with the most
                # threads); the bound one-thread process adds its runs and, having built at
                # one thread, the build times at one thread.
                rest = ",".join(str(t) for t in args.thread_list if t != 1)
                full = accel_bench(args, mesh, rest, out, bench)
                pinned = accel_bench(args, mesh, "1", out, bench)
                for accel, row in full.items():
                    row["runs"] = pinned[accel]["runs"] + row["runs"]
                rows = {"full": full, "one": pinned}
            else:
                full = accel_bench(args, mesh, ",".join(map(str, args.thread_list)), out, bench)
                rows = {"full": full}
                if args.thread_list != [1]:
                    rows["one"] = accel_bench(args, mesh, "1", out, builds)
            got[name] = rows
        rounds.append(got)
        print(f"round {r + 1} of {args.rounds} done", file=sys.stderr, flush=True)
    return rounds


def stats(values):
    values = [v for v in values if v is not None]
    if not values:
        return None
    return {"median": statistics.median(values), "min": min(values), "max": max(values),
            "values": values}


def summarise(args, rounds):
    meshes = []
    for name in rounds[0]:
        full = [rd[name]["full"] for rd in rounds]
        one = [rd[name].get("one", rd[name]["full"]) for rd in rounds]
        embree = "embree" in full[0]
        m = {"mesh": name, "triangles": full[0]["bvh"]["triangles"], "embree": embree,
             "build_threads": full[0]["bvh"]["build_threads"], "per_thread": {}}
        for key, rows in (("build_ms", full), ("build_ms_1_thread", one)):
            m[key] = {a: stats([rw[a]["build_ms"] for rw in rows])
                      for a in ("bvh", "kdtree", "embree") if a in rows[0]}
        m["mib"] = {a: full[0][a]["bytes"] / 2**20 for a in ("bvh", "kdtree", "embree")
                    if a in full[0]}
        m["per_ray"] = {a: full[0][a]["per_ray"]["incoherent"] for a in ("bvh", "kdtree")}
        for t in args.thread_list:
            runs = [next(x for x in rw["bvh"]["runs"] if x["threads"] == t) for rw in full]
            cell = {}
            for c in CELLS:
                cell[c] = {"vs_embree": stats([x.get(c + "_vs_embree") for x in runs]),
                           "over_kdtree": stats([x["over_versus"][c] for x in runs])}
            m["per_thread"][str(t)] = cell
        meshes.append(m)
    return {"rounds": len(rounds), "threads": args.thread_list, "meshes": meshes,
            "targets": check_targets(args, meshes)}


def check_targets(args, meshes):
    """One entry per target and thread count: met by the medians, by every round, and why."""
    targets = []

    def add(name, threads, misses, all_rounds, detail):
        targets.append({"target": name, "threads": threads, "met": not misses,
                        "every_round": all_rounds and not misses, "misses": misses,
                        "detail": detail})

    for t in args.thread_list:
        key = str(t)
        if all(m["embree"] for m in meshes):
            for c, bound in (("incoherent", 1.0), ("primary", 1.0), ("occlusion", 1.0)):
                cells = {m["mesh"]: m["per_thread"][key][c]["vs_embree"] for m in meshes}
                misses = [f"{n} {s['median']:.2f}" for n, s in cells.items() if s["median"] < bound]
                every = all(s["min"] >= bound for s in cells.values())
                add(f"{c} >= {bound} x Embree on every mesh", t, misses, every,
                    ", ".join(f"{n} {s['median']:.2f}" for n, s in cells.items()))
            inc = {m["mesh"]: m["per_thread"][key]["incoherent"]["vs_embree"] for m in meshes}
            best = max(inc, key=lambda n: inc[n]["median"])
            add("incoherent >= 1.2 x Embree on at least one mesh", t,
                [] if inc[best]["median"] >= 1.2 else [f"best {best} {inc[best]['median']:.2f}"],
                any(s["min"] >= 1.2 for s in inc.values()),
                f"best {best} {inc[best]['median']:.2f}")
        kd = []
        every = True
        for m in meshes:
            for c in CELLS:
                s = m["per_thread"][key][c]["over_kdtree"]
                if s["median"] > 2.0:
                    kd.append(f"{m['mesh']} {c} {s['median']:.2f}")
                every = every and s["max"] <= 2.0
        cells = len(CELLS) * len(meshes)
        add("kdtree within 2x of bvh in every set", t, kd, every,
            f"{cells - len(kd)} of {cells} within")
    if all(m["embree"] for m in meshes):
        mem = [f"{m['mesh']} {m['mib']['bvh']:.1f} > {m['mib']['embree']:.1f} MiB"
               for m in meshes if m["mib"]["bvh"] > m["mib"]["embree"]]
        add("bvh memory <= Embree's on every mesh", None, mem, not mem,
            ", ".join(f"{m['mesh']} {m['mib']['bvh']:.1f} ({m['mib']['embree']:.1f})"
                      for m in meshes))
        judged = [m for m in meshes if stem(m["mesh"]) in BUILD_MESHES]
        for key, label in (("build_ms_1_thread", "1 thread"), ("build_ms", "the most threads")):
            misses, every, parts = [], True, []
            for m in judged:
                ours, theirs = m[key]["bvh"], m[key]["embree"]
                parts.append(f"{m['mesh']} {ours['median']:.0f} ({theirs['median']:.0f}) ms")
                if ours["median"] > theirs["median"]:
                    misses.append(parts[-1])
                every = every and ours["max"] <= theirs["min"]
            if judged:
                add(f"bvh build <= Embree's at {label} on {' and '.join(BUILD_MESHES)}", None,
                    misses, every, ", ".join(parts))
    return targets


def fmt(s):
    if s is None:
        return "-"
    lo, hi = f"{s['min']:.2f}", f"{s['max']:.2f}"
    return f"{s['median']:.2f}" + ("" if lo == hi else f" ({lo}-{hi})")


def print_report(summary):
    print(f"issue #19, {summary['rounds']} round(s); medians (ranges) over the rounds")
    for m in summary["meshes"]:
        b = m["build_ms"]
        line = (f"\n{m['mesh']} ({m['triangles']} triangles): bvh {m['mib']['bvh']:.1f} MiB, "
                f"build {b['bvh']['median']:.1f} ms at {m['build_threads']} thread(s), "
                f"{m['build_ms_1_thread']['bvh']['median']:.1f} at 1")
        if m["embree"]:
            line += (f"; Embree {m['mib']['embree']:.1f} MiB, {b['embree']['median']:.1f} ms, "
                     f"{m['build_ms_1_thread']['embree']['median']:.1f} at 1")
        print(line)
        print("  nodes / tests per incoherent ray: bvh {:.1f} / {:.1f}, kdtree {:.1f} / {:.1f}".format(
            m["per_ray"]["bvh"]["nodes"], m["per_ray"]["bvh"]["prims"],
            m["per_ray"]["kdtree"]["nodes"], m["per_ray"]["kdtree"]["prims"]))
        print(f"  {'':<22}" + "".join(f"{c:>19}" for c in CELLS))
        for t, cells in m["per_thread"].items():
            if m["embree"]:
                print(f"  {'bvh x Embree, ' + t + ' thr':<22}" +
                      "".join(f"{fmt(cells[c]['vs_embree']):>19}" for c in CELLS))
            print(f"  {'bvh over kdtree, ' + t + ' thr':<22}" +
                  "".join(f"{fmt(cells[c]['over_kdtree']):>19}" for c in CELLS))
    print("\ntargets (met by the medians; 'every round' when each round met it too):")
    for tg in summary["targets"]:
        where = f" at {tg['threads']} thread(s)" if tg["threads"] is not None else ""
        state = ("met, every round" if tg["every_round"] else "met") if tg["met"] else "NOT met"
        why = "; ".join(tg["misses"]) if tg["misses"] else tg["detail"]
        print(f"  {tg['target']}{where}: {state} ({why})")


def main(argv):
    args = parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="issue19_") as tmp:
        if not args.meshes and not args.terrain:
            terrain = os.path.join(tmp, "terrain.ply")
            subprocess.run([sys.executable, os.path.join(HERE, "make_terrain.py"), terrain],
                           check=True, stdout=subprocess.DEVNULL)
            args.mesh_list.append(terrain)
        rounds = measure(args, tmp)
    summary = summarise(args, rounds)
    print_report(summary)
    if args.json:
        tmp_path = args.json + ".tmp"
        with open(tmp_path, "w") as f:
            json.dump({"meshes": args.mesh_list, "threads": args.threads,
                       "repeat": args.repeat, "rays": args.rays, "summary": summary,
                       "rounds": rounds}, f, indent=1)
        os.replace(tmp_path, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
