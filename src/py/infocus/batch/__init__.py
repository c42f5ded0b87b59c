# SPDX-License-Identifier: MIT
"""Batch analysis of archives on Dask distributed, results in SQLite (docs/batch.md):
`python3 -m infocus.batch SOURCE... -o RESULTS.sqlite`, also installed as `infocus-batch`."""
from .run import main  # noqa: F401
