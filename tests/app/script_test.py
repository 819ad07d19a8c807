"""Helpers of the CTests that run the Python scripts under bench/ (ab_accel_test.py,
issue19_test.py): a failure message and exit, and a script run with its output captured."""

import subprocess
import sys


def fail(msg):
    print(f"FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def run(script, *args):
    return subprocess.run([sys.executable, script, *args], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True)
