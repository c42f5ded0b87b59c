# SPDX-License-Identifier: MIT
"""Where the suite finds the infocus executable and the real photographs (set by meson)."""
import os

import pytest


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("INFOCUS")
    if not path or not os.access(path, os.X_OK):
        pytest.skip("INFOCUS does not name the infocus executable")
    return path


@pytest.fixture(scope="session")
def data_dir():
    path = os.environ.get("INFOCUS_DATA_DIR", "")
    if not os.path.isdir(path):
        pytest.skip(f"the real photographs are not at '{path}'")
    return path
