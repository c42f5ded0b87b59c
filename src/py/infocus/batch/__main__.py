# SPDX-License-Identifier: MIT
"""python3 -m infocus.batch: see infocus.batch."""
import sys

from .run import main

if __name__ == "__main__":
    sys.exit(main())
