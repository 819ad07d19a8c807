"""Renders one scene with penumbra and with Blender Cycles and compares them (compare.sh runs it).

Steps: check the regions on penumbra's first-hit renders; render N spp with both renderers (one
or more seeds); render or reuse the long references; compare per-region mean radiance and
time x MSE against each reference; print a Markdown report and write it to --out.
See docs/cycles-comparison.md.
"""
import argparse
import datetime
import hashlib
import json
import math
import os
import platform
import re
import shlex
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, HERE)
import image_io  # noqa: E402
import regions as regionlib  # noqa: E402


def parse_args(argv):
    p = argparse.ArgumentParser(prog="compare.sh", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scene", default=os.path.join(REPO, "scenes/cornell-box.json"))
    p.add_argument("--regions", default=os.path.join(HERE, "cornell_regions.json"))
    p.add_argument("--integrator", default="path", help="penumbra integrator (default path)")
    p.add_argument("--spp", type=int, default=64, help="samples per pixel of the timed renders")
    p.add_argument("--threads", type=int, default=os.cpu_count(), help="threads for both")
    p.add_argument("--seed", type=int, default=0, help="seed of the first timed render")
    p.add_argument("--repeats", type=int, default=1,
                   help="timed renders per renderer, seeds seed..seed+repeats-1 (from 5 on, the "
                        "errors of the region means come from their spread)")
    p.add_argument("--resolution", help="WxH (default: the scene's)")
    p.add_argument("--max-depth", type=int, default=64, help="bounces, both renderers")
    p.add_argument("--cycles-bounces", type=int,
                   help="Cycles' bounce limit if not --max-depth (0: direct light only, to check "
                        "the conversion against penumbra's distribution integrator)")
    p.add_argument("--cycles-pattern", choices=["PROGRESSIVE_MULTI_JITTER", "SOBOL"],
                   default="PROGRESSIVE_MULTI_JITTER", help="Cycles' sampling pattern")
    p.add_argument("--ref-spp", type=int, default=4096, help="samples per pixel of references")
    p.add_argument("--reference", choices=["penumbra", "cycles", "both"], default="penumbra",
                   help="which long reference renders to make (cached in --workdir)")
    p.add_argument("--penumbra", default=os.path.join(REPO, "build/penumbra"))
    p.add_argument("--penumbra-args", default="",
                   help="extra flags for penumbra render, e.g. '--sampler sobol'")
    p.add_argument("--blender", default="blender")
    p.add_argument("--workdir", default=os.path.join(os.environ.get("TMPDIR", "/tmp"),
                                                     "penumbra-cycles"))
    p.add_argument("--out", help="write the Markdown report to this file too")
    p.add_argument("--fresh", action="store_true", help="re-render cached references")
    return p.parse_args(argv)


# --- running the renderers -------------------------------------------------------------------

def duration_s(text):
    """Seconds of penumbra's format_duration: '12.3s', '1m 05s', '2h 03m'."""
    m = re.fullmatch(r"(\d+)h (\d+)m", text)
    if m:
        return 3600 * int(m[1]) + 60 * int(m[2])
    m = re.fullmatch(r"(\d+)m (\d+)s", text)
    if m:
        return 60 * int(m[1]) + int(m[2])
    return float(text.rstrip("s"))


def clock_s(text):
    """Seconds of Blender's clock format: 'MM:SS.ss' or 'HH:MM:SS.ss'."""
    s = 0.0
    for part in text.split(":"):
        s = 60 * s + float(part)
    return s


def run(cmd, log_path):
    """Runs a command, keeps its output in log_path, raises with the log's tail on failure."""
    start = time.time()
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.time() - start
    with open(log_path, "w", encoding="utf-8") as f:
        f.write(" ".join(shlex.quote(c) for c in cmd) + "\n" + proc.stdout)
    if proc.returncode != 0:
        tail = "\n".join(proc.stdout.splitlines()[-15:])
        raise RuntimeError(f"command failed ({proc.returncode}): {' '.join(cmd)}\n{tail}\n"
                           f"(log: {log_path})")
    return proc.stdout, wall


def penumbra_render(a, out, integrator, spp, seed, extra=()):
    """Renders with penumbra; returns its times (render as printed on stderr, and total)."""
    cmd = [a.penumbra, "render", a.scene, "-o", out, "--integrator", integrator,
           "--spp", str(spp), "--threads", str(a.threads), "--seed", str(seed),
           "--max-depth", str(a.max_depth)]
    if a.resolution:
        cmd += ["--resolution", a.resolution]
    cmd += list(extra)
    text, wall = run(cmd, out + ".log")
    m = re.search(r"^render (\S+(?: \S+)?)  \(total ([^)]+)\)(.*)$", text, re.M)
    if not m:
        raise RuntimeError(f"no 'render ... (total ...)' line in penumbra's output ({out}.log)")
    render, total = duration_s(m[1]), duration_s(m[2])
    rays = re.search(r"(\d+) rays", m[3])
    return {"render_s": render, "sampling_s": render, "startup_s": max(0.0, wall - total),
            "build_s": total - render, "wall_s": wall, "rays": int(rays[1]) if rays else None}


def cycles_render(a, out_pfm, spp, seed, blend=None):
    """Renders with Cycles through penumbra_to_blender.py; returns Blender's reported times."""
    exr, timings_path = out_pfm[:-4] + ".exr", out_pfm[:-4] + ".timings.json"
    cmd = [a.blender, "-b", "--factory-startup", "--python-exit-code", "1",
           "--python", os.path.join(HERE, "penumbra_to_blender.py"), "--",
           "--scene", a.scene, "--output", exr, "--pfm", out_pfm, "--spp", str(spp),
           "--threads", str(a.threads), "--seed", str(seed),
           "--max-depth", str(a.max_depth if a.cycles_bounces is None else a.cycles_bounces),
           "--sampling-pattern", a.cycles_pattern,
           "--timings", timings_path, "--launched-at", repr(time.time())]
    if blend:
        cmd += ["--save-blend", blend]
    if a.resolution:
        cmd += ["--resolution", a.resolution]
    text, wall = run(cmd, out_pfm + ".log")
    with open(timings_path, encoding="utf-8") as f:
        t = json.load(f)
    total = re.search(r"^ Time: (\S+) \(Saving: (\S+)\)", text, re.M)
    first = re.search(r"\| Time:(\S+) \|.*\| Sample 0/", text)
    done = re.search(r"\| Time:(\S+) \|.*\| Finished$", text, re.M)
    if not (total and first and done):
        raise RuntimeError(f"Blender's render times not found in {out_pfm}.log")
    render = clock_s(total[1]) - clock_s(total[2])
    return {"render_s": render, "sampling_s": clock_s(done[1]) - clock_s(first[1]),
            "startup_s": t["startup_s"], "build_s": t["build_s"], "wall_s": wall,
            "blender": t["blender"]}


def cached(a, path, key, make):
    """Reuses a reference render made with the same key (command, binary) unless --fresh."""
    meta = path + ".json"
    if not a.fresh and os.path.exists(path) and os.path.exists(meta):
        with open(meta, encoding="utf-8") as f:
            old = json.load(f)
        if old.get("key") == key:
            print("  (cached)", file=sys.stderr)
            return old["times"]
    times = make()
    with open(meta, "w", encoding="utf-8") as f:
        json.dump({"key": key, "times": times}, f, indent=1)
    return times


def file_key(path):
    """A file's content hash: an edited scene or converter invalidates the references."""
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()[:16]


def binary_key(program):
    """Path, size and modification time of a program: a rebuilt renderer invalidates its refs."""
    exe = shutil.which(program) or program
    st = os.stat(exe)
    return f"{os.path.realpath(exe)}:{st.st_size}:{int(st.st_mtime)}"


# --- statistics and the report ---------------------------------------------------------------

def fmt_value(m, e):
    """m±e with enough decimals to show two digits of the error (at least 4, at most 7)."""
    if not np.isfinite(m):
        return "—"
    d = 4 if not e > 0 else int(min(7, max(4, 1 - math.floor(math.log10(e)))))
    return f"{m:.{d}f}±{e:.{d}f}"


def fmt_rgb(mean, err):
    return ", ".join(fmt_value(m, e) for m, e in zip(mean, err))


def region_table(regions, title, name_a, images_a, name_b, images_b):
    """Markdown table of per-region means of two renderers, their ratio and its z-score."""
    lines = [f"**{title}** (RGB mean radiance ± standard error)", "",
             f"| region | pixels | {name_a} | {name_b} | {name_a} / {name_b} | (a − b) / σ |",
             "| --- | ---: | --- | --- | --- | --- |"]
    h, w = images_a[0].shape[:2]
    for r in regions:
        ma, ea = regionlib.mean_and_error_over_seeds(images_a, r)
        mb, eb = regionlib.mean_and_error_over_seeds(images_b, r)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where((ma > 0) & (mb > 0), ma / mb, np.nan)
            ratio_err = ratio * np.sqrt((ea / ma) ** 2 + (eb / mb) ** 2)
            z = (ma - mb) / np.sqrt(ea ** 2 + eb ** 2)
        x0, y0, x1, y1 = regionlib.pixel_rect(r, w, h)
        lines.append(f"| {r['name']} | {(x1 - x0) * (y1 - y0)} | {fmt_rgb(ma, ea)} | "
                     f"{fmt_rgb(mb, eb)} | {fmt_rgb(ratio, ratio_err)} | "
                     f"{', '.join(f'{v:+.1f}' if np.isfinite(v) else '—' for v in z)} |")
    return lines


def mse(image, ref, mask=None):
    """Mean squared error over the pixels of mask (all pixels without one) and channels."""
    d = image.astype(np.float64) - ref
    d2 = (d * d).mean(axis=2)
    return float(d2.mean() if mask is None else d2[mask].mean())


def rel_mse(image, ref):
    """Relative MSE, mean((x - ref)^2 / (ref^2 + 0.01)) (Rousselle et al. 2011's relMSE)."""
    d = image.astype(np.float64) - ref
    return float(np.mean(d * d / (ref * ref + 0.01)))


def off_emitters(albedo):
    """Mask of the pixels that see no emitter, even partly (mode=albedo shows an emitter's
    radiance, above any albedo), grown by one pixel: the light's antialiased edge pixels, whose
    error is pixel sampling and not light transport, would otherwise dominate the MSE."""
    lit = albedo.max(axis=2) > 1.0
    grown = lit.copy()
    grown[1:] |= lit[:-1]
    grown[:-1] |= lit[1:]
    grown[:, 1:] |= grown[:, :-1].copy()
    grown[:, :-1] |= grown[:, 1:].copy()
    return ~grown


def errors(runs, refs, mask):
    """Per run and reference: MSE, MSE off the emitters, relMSE (means over the repeats)."""
    for r in runs.values():
        r["errors"] = {}
        for ref_name, ref in refs.items():
            r["errors"][ref_name] = {
                "mse": float(np.mean([mse(im, ref["image"]) for im in r["images"]])),
                "mse_off": float(np.mean([mse(im, ref["image"], mask) for im in r["images"]])),
                "rel": float(np.mean([rel_mse(im, ref["image"]) for im in r["images"]]))}


def mean_times(r):
    return {k: float(np.mean([x[k] for x in r["times"]]))
            for k in ("startup_s", "build_s", "render_s", "sampling_s")}


def time_table(a, runs):
    """Markdown table of the mean times of the timed renders."""
    lines = ["| renderer | spp | threads | startup (s) | scene build (s) | render (s) | "
             "of which sampling (s) |", "| --- | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for name, r in runs.items():
        t = mean_times(r)
        lines.append(f"| {name} | {r['spp']} | {a.threads} | {t['startup_s']:.2f} | "
                     f"{t['build_s']:.2f} | {t['render_s']:.2f} | {t['sampling_s']:.2f} |")
    return lines


def error_table(runs, refs):
    """Markdown table of the errors of the timed renders against each reference."""
    lines = ["| renderer | reference | MSE | render × MSE | MSE off the light | "
             "render × MSE off the light | relMSE |",
             "| --- | --- | ---: | ---: | ---: | ---: | ---: |"]
    for ref_name in refs:
        for name, r in runs.items():
            t, e = mean_times(r)["render_s"], r["errors"][ref_name]
            lines.append(f"| {name} | {ref_name} | {e['mse']:.3e} | {t * e['mse']:.3e} | "
                         f"{e['mse_off']:.3e} | {t * e['mse_off']:.3e} | {e['rel']:.3e} |")
    return lines


def efficiency_lines(a, runs, refs, pen_name):
    """Efficiency ratios and each reference's own noise, estimated from its own renderer."""
    lines = []
    owner = {"penumbra": pen_name, "Cycles": "Cycles"}
    tp, tc = mean_times(runs[pen_name]), mean_times(runs["Cycles"])
    for ref_name in refs:
        ep, ec = runs[pen_name]["errors"][ref_name], runs["Cycles"]["errors"][ref_name]
        parts = []
        for key, label in (("mse", "all pixels"), ("mse_off", "off the light")):
            ratio = (tc["render_s"] * ec[key]) / (tp["render_s"] * ep[key])
            ratio_s = (tc["sampling_s"] * ec[key]) / (tp["sampling_s"] * ep[key])
            parts.append(f"{ratio:.3f} {label} ({ratio_s:.3f} with sampling times)")
        # Same renderer, independent seeds: E[MSE] = V/N + V/R, so the reference's own share is
        # MSE * N / (N + R) (exact for independent sampling, an upper bound for Cycles' PMJ).
        own = runs[owner[ref_name]]["errors"][ref_name]
        noise = own["mse"] * a.spp / (a.spp + a.ref_spp)
        noise_off = own["mse_off"] * a.spp / (a.spp + a.ref_spp)
        lines.append(f"Against the {ref_name} reference: efficiency 1/(render × MSE) of penumbra "
                     f"over Cycles {'; '.join(parts)}. The reference's own noise adds about "
                     f"{noise:.2e} ({noise_off:.2e} off the light) to every MSE in its columns.")
    return lines


def machine():
    cpu = platform.processor() or "?"
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{cpu}, {os.cpu_count()} logical CPUs"


def penumbra_commit():
    try:
        out = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True, check=True)
        return out.stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "?"


def main(argv):
    a = parse_args(argv)
    if not os.access(a.penumbra, os.X_OK):
        raise RuntimeError(f"penumbra binary not found: {a.penumbra} (build it, or --penumbra)")
    if not shutil.which(a.blender):
        raise RuntimeError(f"blender not found: {a.blender} (compare.sh --install, or --blender)")
    os.makedirs(a.workdir, exist_ok=True)
    with open(a.scene, encoding="utf-8") as f:
        scene = json.load(f)
    regions = regionlib.load(a.regions)
    W, H = ((int(v) for v in a.resolution.lower().split("x")) if a.resolution
            else scene.get("render", {}).get("resolution", [256, 256]))
    tag = f"{W}x{H}-d{a.max_depth}"
    ctag = tag if a.cycles_bounces is None else f"{W}x{H}-d{a.cycles_bounces}"
    extra = shlex.split(a.penumbra_args)
    path = lambda name: os.path.join(a.workdir, name)  # noqa: E731

    # 1. The regions must lie inside their surfaces in this camera view.
    print(f"checking {len(regions)} regions on first-hit renders ...", file=sys.stderr)
    penumbra_render(a, path(f"albedo-{tag}.pfm"), "raycast:mode=albedo", 16, 0)
    penumbra_render(a, path(f"normal-{tag}.pfm"), "raycast:mode=normal", 16, 0)
    albedo = image_io.read_pfm(path(f"albedo-{tag}.pfm"))
    image_io.write_png(path("regions.png"),
                       regionlib.outline(image_io.srgb8(albedo), regions))
    problems = regionlib.validate(regions, scene, albedo,
                                  image_io.read_pfm(path(f"normal-{tag}.pfm")))
    if problems:
        raise RuntimeError("regions do not lie inside their surfaces (see "
                           f"{path('regions.png')}; edit {a.regions}):\n  " + "\n  ".join(problems))

    # 2. The timed renders, equal spp and threads.
    integ = a.integrator.replace(":", "_").replace(",", "_").replace("=", "-")
    runs = {f"penumbra {a.integrator}": {"spp": a.spp, "images": [], "times": []},
            "Cycles": {"spp": a.spp, "images": [], "times": []}}
    for k in range(a.repeats):
        seed = a.seed + k
        print(f"penumbra {a.integrator}, {a.spp} spp, seed {seed} ...", file=sys.stderr)
        out = path(f"penumbra-{integ}-{tag}-spp{a.spp}-seed{seed}.pfm")
        runs[f"penumbra {a.integrator}"]["times"].append(
            penumbra_render(a, out, a.integrator, a.spp, seed, extra))
        runs[f"penumbra {a.integrator}"]["images"].append(image_io.read_pfm(out))
        print(f"Cycles, {a.spp} spp, seed {seed} ...", file=sys.stderr)
        out = path(f"cycles-{ctag}-spp{a.spp}-seed{seed}.pfm")
        blend = path(f"cycles-{ctag}.blend") if k == 0 else None
        runs["Cycles"]["times"].append(cycles_render(a, out, a.spp, seed, blend))
        runs["Cycles"]["images"].append(image_io.read_pfm(out))

    # 3. The references (another seed, so that they share no samples with the timed renders).
    refs, ref_seed = {}, a.seed + 1000
    if a.reference in ("penumbra", "both"):
        out = path(f"ref-penumbra-{integ}-{tag}-spp{a.ref_spp}-seed{ref_seed}.pfm")
        print(f"penumbra reference, {a.ref_spp} spp ...", file=sys.stderr)
        key = [binary_key(a.penumbra), file_key(a.scene), a.integrator, a.penumbra_args]
        t = cached(a, out, key, lambda: penumbra_render(a, out, a.integrator, a.ref_spp,
                                                        ref_seed, extra))
        refs["penumbra"] = {"image": image_io.read_pfm(out).astype(np.float64), "times": t}
    if a.reference in ("cycles", "both"):
        out = path(f"ref-cycles-{ctag}-spp{a.ref_spp}-seed{ref_seed}.pfm")
        print(f"Cycles reference, {a.ref_spp} spp ...", file=sys.stderr)
        key = [binary_key(a.blender), file_key(a.scene), a.cycles_pattern,
               file_key(os.path.join(HERE, "penumbra_to_blender.py")),
               file_key(os.path.join(HERE, "scene_geometry.py"))]
        t = cached(a, out, key, lambda: cycles_render(a, out, a.ref_spp, ref_seed))
        refs["Cycles"] = {"image": image_io.read_pfm(out).astype(np.float64), "times": t}

    # 4. Previews and the report.
    pen, cyc = runs[f"penumbra {a.integrator}"]["images"][0], runs["Cycles"]["images"][0]
    diff = np.abs(pen - cyc) * 4.0
    image_io.write_png(path("side-by-side.png"), image_io.srgb8(np.concatenate(
        [pen, np.ones((H, 2, 3), np.float32), cyc, np.ones((H, 2, 3), np.float32), diff], 1)))
    errors(runs, refs, off_emitters(albedo))
    report = build_report(a, W, H, regions, runs, refs)
    text = "\n".join(report) + "\n"
    print(text)
    if a.out:
        with open(a.out, "w", encoding="utf-8") as f:
            f.write(text)
        print(f"wrote {a.out}", file=sys.stderr)


def build_report(a, W, H, regions, runs, refs):
    pen_name = f"penumbra {a.integrator}"
    blender = runs["Cycles"]["times"][0]["blender"]
    err_src = ("spread of the region means over the seeds"
               if a.repeats >= regionlib.MIN_SEEDS_FOR_SPREAD else
               "adjacent-pixel differences within the region (of the mean image over the seeds)")
    lines = [f"## penumbra vs Cycles: {os.path.basename(a.scene)}", "",
             f"{W}×{H}, {a.spp} spp, {a.threads} threads, max depth {a.max_depth}, "
             f"{'' if a.cycles_bounces is None else f'Cycles bounces {a.cycles_bounces}, '}"
             f"seeds {a.seed}…{a.seed + a.repeats - 1}; penumbra `{a.integrator}` "
             f"{a.penumbra_args or ''}(commit {penumbra_commit()}), Blender {blender} Cycles "
             f"(CPU, {a.cycles_pattern} sampling, 1-px box filter); {machine()}; "
             f"{datetime.date.today().isoformat()}.", "",
             f"Standard errors: {err_src}.", ""]
    if a.integrator.startswith(("distribution", "whitted", "raycast")) and a.cycles_bounces is None:
        lines += [f"**Not like for like:** `{a.integrator}` computes no diffuse interreflection "
                  "while Cycles follows every bounce; use `--cycles-bounces 0` to compare direct "
                  "light, or the `path` integrator.", ""]
    lines += region_table(regions, f"Regions at {a.spp} spp", pen_name,
                          runs[pen_name]["images"], "Cycles", runs["Cycles"]["images"])
    if len(refs) == 2:
        lines += [""] + region_table(
            regions, f"Regions of the references at {a.ref_spp} spp", "penumbra ref",
            [refs["penumbra"]["image"]], "Cycles ref", [refs["Cycles"]["image"]])
    lines += ["", "**Times** (means over the seeds)", ""] + time_table(a, runs)
    if refs:
        lines += ["", f"**Error at equal spp and threads** (references: {a.ref_spp} spp, seed "
                  f"{a.seed + 1000}; render × MSE: lower is better)", ""]
        lines += error_table(runs, refs)
    notes = ["Render time: penumbra's `render` line on stderr (0.1 s resolution; scene load and "
             "BVH build excluded); Cycles: Blender's `Time` minus `Saving` (shader compile, sync, "
             "BVH and sampling), of which sampling from `Sample 0/N` to `Finished`. Startup: "
             "process start to the scene script (Cycles) or to the render (penumbra, including "
             "scene load)."]
    notes += [f"Reference {name}: render {ref['times']['render_s']:.1f} s."
              for name, ref in refs.items()]
    notes += efficiency_lines(a, runs, refs, pen_name)
    return lines + [""] + [f"- {n}" for n in notes]


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except (RuntimeError, OSError, KeyError, ValueError) as e:
        print(f"compare.sh: {e}", file=sys.stderr)
        sys.exit(1)
