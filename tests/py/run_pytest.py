#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Runs the Python module's pytest suite; exits 77 (meson's SKIP) when pytest, NumPy or the
module cannot be imported, so that a build without the 'python' feature skips, never passes."""
import os
import sys

def main():
    missing = []
    for name in ("pytest", "numpy", "infocus"):
        try:
            __import__(name)
        except ImportError as e:
            missing.append(f"{name} ({e})")
    if missing:
        print("skipped: cannot import " + ", ".join(missing) +
              "; install python3-pytest and python3-numpy and build with -Dpython=enabled",
              file=sys.stderr)
        return 77
    import pytest
    args = [os.path.dirname(os.path.abspath(__file__)), "-q", "-p", "no:cacheprovider", "-rs"]
    return pytest.main(args + sys.argv[1:])

if __name__ == "__main__":
    sys.exit(main())
