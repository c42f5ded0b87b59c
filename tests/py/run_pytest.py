#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Runs a pytest suite of the Python package (this folder's, or the one --tests names); exits 77
(meson's SKIP) when pytest, NumPy, the package or a module --need names cannot be imported, so
that a build without the 'python' feature, or a machine without Dask, skips, never passes.
Usage: run_pytest.py [--tests DIR] [--need MODULE]... [pytest arguments]"""
import os
import sys

HINTS = {"distributed": "python3-distributed"}


def main():
    args = sys.argv[1:]
    tests = os.path.dirname(os.path.abspath(__file__))
    needed = ["pytest", "numpy", "infocus"]
    while args and args[0] in ("--tests", "--need") and len(args) > 1:
        if args[0] == "--tests":
            tests = args[1]
        else:
            needed.append(args[1])
        args = args[2:]
    missing = []
    for name in needed:
        try:
            __import__(name)
        except ImportError as e:
            missing.append(f"{name} ({e})")
    if missing:
        extra = "".join(f", {HINTS[n]}" for n in needed if n in HINTS)
        print("skipped: cannot import " + ", ".join(missing) +
              f"; install python3-pytest, python3-numpy{extra} and build with -Dpython=enabled",
              file=sys.stderr)
        return 77
    import pytest
    return pytest.main([tests, "-q", "-p", "no:cacheprovider", "-rs"] + args)


if __name__ == "__main__":
    sys.exit(main())
