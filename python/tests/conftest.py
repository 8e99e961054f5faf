"""Shared fixtures of the Python tests (docs/python.md, "Tests").

The package is imported from PYTHONPATH (scripts/test.sh sets it to
build/release/python). FULCRUM_CLI names the `fulcrum` command for the tests
that compare with it; by default the one of the Release build.
"""
import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def repo():
    return REPO


@pytest.fixture(scope="session")
def cli():
    path = pathlib.Path(os.environ.get("FULCRUM_CLI", REPO / "build" / "release" / "apps" / "fulcrum" / "fulcrum"))
    if not path.exists():
        pytest.fail(f"the fulcrum command is not at {path}: build it (fulcrum_cli) or set FULCRUM_CLI")
    return path
