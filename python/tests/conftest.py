"""Shared fixtures: small scenes, and the command-line binary for comparisons with the CLI."""

import os
import shutil
from pathlib import Path

import pytest

import pushmog

REPOSITORY = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def scene():
    """The paper's setting: 34 objects of the built-in set, seed 7."""
    return pushmog.generate_scene(34, seed=7)


@pytest.fixture(scope="session")
def small_scene():
    return pushmog.generate_scene(8, seed=3)


@pytest.fixture(scope="session")
def cli():
    """The `pushmog` binary: $PUSHMOG_CLI (CI sets it; then it must exist), else one built in target/."""
    configured = os.environ.get("PUSHMOG_CLI")
    if configured:
        path = Path(configured)
        if not path.is_absolute():
            path = REPOSITORY / path
        assert path.exists(), f"PUSHMOG_CLI={configured} does not exist"
        return path
    for candidate in (REPOSITORY / "target/release/pushmog", REPOSITORY / "target/debug/pushmog"):
        if candidate.exists():
            return candidate
    found = shutil.which("pushmog")
    if found:
        return Path(found)
    pytest.skip("no pushmog binary: build it with `cargo build` or set PUSHMOG_CLI")
