#!/usr/bin/env python3
"""The objects of the structures compiled for other instruction-set levels (CMakeLists.txt,
PENUMBRA_ISA_DISPATCH) leave only their two entry points global: any other global symbol, an
inline function or a template instantiated there, could stand in at link time for the copy the
rest of the program compiled for its own target, and run instructions the CPU lacks.

usage: isa_objects_test.py NM OBJECT...  (objects named penumbra_accel_LEVEL.o)
"""
import os
import re
import subprocess
import sys


def main():
    nm, objects = sys.argv[1], sys.argv[2:]
    if not objects:
        print("no level objects given", file=sys.stderr)
        return 1
    failed = False
    for obj in objects:
        m = re.fullmatch(r"penumbra_accel_(\w+)\.o", os.path.basename(obj))
        if not m:
            print(f"{obj}: not a level object's name", file=sys.stderr)
            return 1
        level = m.group(1)
        out = subprocess.run([nm, "--defined-only", "-g", obj], check=True,
                             capture_output=True, text=True).stdout
        names = sorted(line.split()[-1] for line in out.splitlines() if line.strip())
        want = sorted([f"penumbra_isa_{level}_make", f"penumbra_isa_{level}_missing"])
        if names != want:
            extra = [n for n in names if n not in want]
            print(f"{obj}: global symbols {extra[:10]} ({len(extra)} beyond the entry points); "
                  f"missing {[n for n in want if n not in names]}", file=sys.stderr)
            failed = True
        local = subprocess.run([nm, "--defined-only", obj], check=True, capture_output=True,
                               text=True).stdout
        # The copy holds the structures' code (a wide BVH's traversal among it), made local.
        if "_ZNK8penumbra7WideBvhILi16ENS_8WideNodeILi16EEEE9intersect" not in local:
            print(f"{obj}: no WideBvh<16>::intersect in it", file=sys.stderr)
            failed = True
        print(f"{obj}: {len(local.splitlines())} symbols, global: {', '.join(names)}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
