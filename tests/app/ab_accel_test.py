#!/usr/bin/env python3
"""CTest AbAccel.PairsTwoBinaries: bench/ab_accel.py runs two binaries (here the same one twice)
in pairs on a small mesh, summarises every cell, writes its JSON, and refuses bad input with a
clear message, a non-zero exit and no JSON.

Usage: ab_accel_test.py PENUMBRA_CLI SOURCE_DIR
"""

import json
import math
import os
import sys
import tempfile

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
from script_test import fail, run  # noqa: E402


def main():
    cli, src = sys.argv[1], sys.argv[2]
    script = os.path.join(src, "bench", "ab_accel.py")
    mesh = os.path.join(src, "tests", "data", "meshes", "cube.obj")
    small = ["--rays", "2000", "--image", "16", "--repeat", "1"]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "ab.json")
        p = run(script, cli, cli, mesh, "--pairs", "2", "--accel", "bvh,kdtree", *small,
                "--json", out)
        if p.returncode != 0:
            fail(f"exit {p.returncode}: {p.stderr}")
        for word in ("bvh", "kdtree", "primary", "incoherent", "occlusion", "bounce", "shadow"):
            if word not in p.stdout:
                fail(f"'{word}' missing from the table:\n{p.stdout}")
        d = json.load(open(out))
        if d["pairs"] != 2 or len(d["summary"]) != 2:
            fail(f"expected 2 pairs and 2 structures: {d['pairs']}, {len(d['summary'])}")
        for s in d["summary"]:
            cells = [c["cell"] for c in s["cells"]]
            if cells != ["primary", "incoherent", "occlusion", "bounce", "shadow"]:
                fail(f"{s['accel']}: cells {cells}")
            for c in s["cells"]:
                if len(c["old_mrays"]) != 2 or len(c["new_mrays"]) != 2:
                    fail(f"{s['accel']} {c['cell']}: not one figure per pair")
                for v in c["old_mrays"] + c["new_mrays"] + c["new_over_old"]:
                    if not (math.isfinite(v) and v > 0):
                        fail(f"{s['accel']} {c['cell']}: figure {v}")
                med = c["new_over_old_median"]
                if not (min(c["new_over_old"]) <= med <= max(c["new_over_old"])):
                    fail(f"{s['accel']} {c['cell']}: median {med} outside its range")

        # Bad input: not an executable; a structure accel-bench refuses. Neither writes JSON.
        bad_out = os.path.join(tmp, "bad.json")
        p = run(script, os.path.join(tmp, "nope"), cli, mesh, "--json", bad_out)
        if p.returncode == 0 or "nope: not an executable file" not in p.stderr:
            fail(f"missing executable: exit {p.returncode}, {p.stderr}")
        p = run(script, cli, cli, mesh, "--accel", "no_such_structure", *small,
                "--json", bad_out)
        if p.returncode == 0 or "accel-bench" not in p.stderr or "exited with" not in p.stderr:
            fail(f"refused structure: exit {p.returncode}, {p.stderr}")
        if os.path.exists(bad_out) or os.path.exists(bad_out + ".tmp"):
            fail("a failed comparison left a JSON file")
    print("ok")


if __name__ == "__main__":
    main()
