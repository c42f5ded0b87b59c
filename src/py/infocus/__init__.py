# SPDX-License-Identifier: MIT
"""Per-region sharpness and blur width of camera frames, and the thin-lens optics that turn blur
into distance (the library behind the `infocus` command).

The measurements are the extension `infocus._infocus`; `infocus.batch` runs them over archives
on a Dask cluster."""
from ._infocus import *  # noqa: F401,F403  (the API: analyze, open, stack, Lens, ...)
from ._infocus import __version__  # noqa: F401
