#!/usr/bin/env python3
"""Compiles the translation units whose code depends on the instruction set (`#if defined(__AVX2__)`
and the like, directly or through a header) for every x86-64 level the project may meet, with
`-fsyntax-only`: the build uses -march=native, so each machine compiles other branches, and a
branch no development machine took can fail on the next one (2026-12-05: the Sobol' sampler did
not compile with AVX-512 and GFNI). Templates are instantiated, so their errors show too.

    scripts/check_isa.py [--cxx g++] [--jobs N] [--list]

Exits 1 naming each file and -march that failed, with the compiler's first lines.
"""
import argparse
import concurrent.futures
import os
import re
import subprocess
import sys

# SSE2 only; SSE4.2; AVX without AVX2; AVX2 and FMA; AVX-512 without GFNI; with GFNI; with FP16.
ARCHES = ["x86-64", "x86-64-v2", "sandybridge", "x86-64-v3", "skylake-avx512", "icelake-server",
          "sapphirerapids"]
ISA_MACRO = re.compile(r"__(SSE|AVX|FMA|GFNI|BMI|F16C|POPCNT|LZCNT)\w*__")
INCLUDE = re.compile(r'^\s*#\s*include\s+"(penumbra/[^"]+)"', re.M)
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# Headers whose ISA branches are plain inline functions, no templates: every selected file
# includes them, which checks them, so the files that include them are not selected for them
# alone (core/ray.h is included nearly everywhere).
NO_PROPAGATE = {"penumbra/core/ray.h"}


def sources():
    for top in ("src", "tests", "bench"):
        for d, _, names in os.walk(os.path.join(ROOT, top)):
            for n in names:
                if n.endswith((".h", ".cpp")):
                    yield os.path.join(d, n)


def select():
    """The .cpp files that contain an ISA condition or include, at any depth, a header that does."""
    text = {p: open(p, encoding="utf-8", errors="replace").read() for p in sources()}
    key = {os.path.relpath(p, os.path.join(ROOT, "src")): p for p in text}
    isa = {p for p, t in text.items() if ISA_MACRO.search(t)}
    stop = {key[h] for h in NO_PROPAGATE if h in key}
    includes = {p: [key.get(inc) for inc in INCLUDE.findall(t)] for p, t in text.items()}
    # Fixed point over the include graph: a file depends on the ISA if it includes one that does.
    changed = True
    while changed:
        changed = False
        for p, incs in includes.items():
            if p in isa:
                continue
            if any(inc in isa and inc not in stop for inc in incs):
                isa.add(p)
                changed = True
    return sorted(p for p in isa if p.endswith(".cpp"))


def compile_one(cxx, path, arch):
    cmd = [cxx, "-std=c++20", "-fsyntax-only", "-ffp-contract=off", f"-march={arch}",
           "-I", os.path.join(ROOT, "src"), "-isystem", "/usr/include/OpenEXR", "-isystem",
           "/usr/include/Imath", "-DPENUMBRA_TEST_DATA=\"\"", "-DPENUMBRA_SOURCE_DIR=\"\"",
           "-DPENUMBRA_CLI=\"\"", "-DPENUMBRA_TEST_ISA_LEVELS=\"\"", path]
    r = subprocess.run(cmd, capture_output=True, text=True)
    return path, arch, r.returncode, r.stderr


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cxx", default=os.environ.get("CXX", "g++"))
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--list", action="store_true", help="print the files and stop")
    a = ap.parse_args()
    files = select()
    if a.list:
        print("\n".join(os.path.relpath(f, ROOT) for f in files))
        return 0
    failed = []
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        jobs = [pool.submit(compile_one, a.cxx, f, arch) for arch in ARCHES for f in files]
        for j in concurrent.futures.as_completed(jobs):
            path, arch, rc, err = j.result()
            if rc != 0:
                failed.append((os.path.relpath(path, ROOT), arch, err))
    for path, arch, err in sorted(failed):
        print(f"check_isa: {path} does not compile with -march={arch}:", file=sys.stderr)
        print("\n".join(err.splitlines()[:12]), file=sys.stderr)
    print(f"check_isa: {len(files)} files x {len(ARCHES)} targets, {len(failed)} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
