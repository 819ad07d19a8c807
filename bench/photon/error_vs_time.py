#!/usr/bin/env python3
"""Error against time of path, photon and sppm on a bundled scene, against a long path render.

For each integrator and each time budget T, renders the scene with --time-limit T (photon: its
final gather at increasing spp, since its photon maps are built once) and reports the relative
RMSE of the whole image and of a region of interest (the caustic in caustic.json) against the
reference, with the wall time of the whole run (preprocessing included). Then, for a target
error, the time each integrator needs to reach it (log-log interpolation between budgets).

Usage (from the repository root, after a Release build):
  /usr/bin/python3 bench/photon/error_vs_time.py --scene caustic --times 1,2,4,8,16
  /usr/bin/python3 bench/photon/error_vs_time.py --scene cornell-box --times 1,2,4,8,16
Needs numpy. The reference is cached under --work (default /tmp/penumbra-photon-bench).
"""
import argparse
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

# Per scene: resolution, reference spp, region of interest (x0, y0, x1, y1 as image fractions),
# photon's parameters and spp per time step.
SCENES = {
    "caustic": {"file": "scenes/caustic.json", "res": (160, 120), "ref_spp": 16384,
                "roi": (0.38, 0.62, 0.56, 0.78), "roi_name": "caustic"},
    "cornell-box": {"file": "scenes/cornell-box.json", "res": (128, 128), "ref_spp": 8192,
                    "roi": (0.05, 0.3, 0.2, 0.7), "roi_name": "red wall"},
    "cornell-box-caustics": {"file": "scenes/cornell-box-caustics.json", "res": (128, 128),
                             "ref_spp": 16384, "roi": (0.5, 0.82, 0.85, 0.95),
                             "roi_name": "caustic under the glass sphere"},
}


REF_SEED = 1000003


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(h, w, 3)[::-1]  # PFM rows run bottom to top


def render(args, scene, integrator, out, spp, time_limit=None, seed=None):
    cmd = [args.penumbra, "render", scene["file"], "--integrator", integrator, "--spp", str(spp),
           "--resolution", "%dx%d" % scene["res"], "--threads", str(args.threads), "-o", out]
    if seed is not None:
        cmd += ["--seed", str(seed)]
    if time_limit:
        cmd += ["--time-limit", str(time_limit)]
    start = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - start
    if r.returncode != 0:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), r.stderr))
    m = re.search(r"wrote .* \((\d+) spp", r.stdout + r.stderr)
    return wall, int(m.group(1)) if m else -1


def rel_rmse(img, ref, roi=None):
    if roi is not None:
        h, w = ref.shape[:2]
        x0, y0, x1, y1 = roi
        sl = (slice(int(y0 * h), int(y1 * h)), slice(int(x0 * w), int(x1 * w)))
        img, ref = img[sl], ref[sl]
    return math.sqrt(float(np.mean((img - ref) ** 2))) / float(np.mean(ref))


def time_to(errors, times, target):
    """Log-log interpolated time at which the error first reaches target (None if never)."""
    for i, e in enumerate(errors):
        if e <= target:
            if i == 0:
                return times[0] * (e / target) ** 2  # extrapolate with the 1/sqrt(t) rate
            t0, t1, e0, e1 = times[i - 1], times[i], errors[i - 1], e
            if e0 == e1:
                return t1
            f = math.log(target / e0) / math.log(e1 / e0)
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="caustic", choices=sorted(SCENES))
    ap.add_argument("--penumbra", default="build/penumbra")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--times", default="1,2,4,8,16")
    ap.add_argument("--ref-spp", type=int)
    ap.add_argument("--integrators", default="path,sppm,photon")
    ap.add_argument("--photon", default="photon", help="photon's spec (parameters)")
    ap.add_argument("--target", type=float, help="relative RMSE of the region for time-to-error")
    ap.add_argument("--work", default="/tmp/penumbra-photon-bench")
    args = ap.parse_args()
    scene = SCENES[args.scene]
    os.makedirs(args.work, exist_ok=True)
    ref_spp = args.ref_spp or scene["ref_spp"]
    ref_path = os.path.join(args.work, "ref-%s-%dx%d-%d-seed%d.pfm"
                            % (args.scene, *scene["res"], ref_spp, REF_SEED))
    if not os.path.exists(ref_path):
        print("reference: path at %d spp ..." % ref_spp, flush=True)
        # Its own seed: renders with the scene's seed share their first samples with it, and
        # their error against it would read low.
        wall, _ = render(args, scene, "path", ref_path, ref_spp, seed=REF_SEED)
        print("reference took %.1f s" % wall, flush=True)
    ref = read_pfm(ref_path)
    times = [float(t) for t in args.times.split(",")]
    results = {}
    print("| integrator | budget (s) | wall (s) | spp | rel. RMSE image | rel. RMSE %s |"
          % scene["roi_name"])
    print("|---|---|---|---|---|---|")
    for name in args.integrators.split(","):
        spec = args.photon if name == "photon" else name
        rows = []
        for t in times:
            out = os.path.join(args.work, "%s-%s-%g.pfm" % (args.scene, name, t))
            wall, spp = render(args, scene, spec, out, 1 << 24, t)
            img = read_pfm(out)
            rows.append((wall, rel_rmse(img, ref), rel_rmse(img, ref, scene["roi"]), spp))
            print("| %s | %g | %.2f | %d | %.4f | %.4f |" % (spec, t, wall, spp, rows[-1][1],
                                                            rows[-1][2]), flush=True)
        results[spec] = rows
    # The reference's own error, from path's largest budget scaled by the spp: independent of the
    # renders (its own seed), so its square adds to every row's squared error.
    if "path" in results:
        _, roi_err, spp = results["path"][-1][2], results["path"][-1][2], results["path"][-1][3]
        print("\nthe reference's own relative RMSE on the %s: about %.4f (path's at %d spp x "
              "sqrt(%d / %d))" % (scene["roi_name"], roi_err * math.sqrt(spp / ref_spp), spp,
                                 spp, ref_spp))
    target = args.target
    if target is None:  # the error path reaches on the region with the largest budget
        target = results.get("path", next(iter(results.values())))[-1][2]
    print("\ntime to a relative RMSE of %.4f on the %s:" % (target, scene["roi_name"]))
    for spec, rows in results.items():
        t = time_to([r[2] for r in rows], [r[0] for r in rows], target)
        print("  %-40s %s" % (spec, "%.2f s" % t if t else "not reached (floor %.4f)" %
                                min(r[2] for r in rows)))


if __name__ == "__main__":
    main()
