"""Shared fixtures: the `rattle` command the package is held equal to.

The command is `$RATTLE_BIN` when set (`.ci/python` sets it), else the repository's
`target/release/rattle`, built with `cargo build --release -p rattle-compare --bin rattle`
when missing.
"""

import json
import os
import subprocess
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parents[3]
SCENES = REPOSITORY / "data" / "scenes"


def _command():
    given = os.environ.get("RATTLE_BIN")
    if given:
        return Path(given)
    built = REPOSITORY / "target" / "release" / "rattle"
    if not built.exists():
        subprocess.run(
            ["cargo", "build", "--release", "-p", "rattle-compare", "--bin", "rattle"],
            cwd=REPOSITORY,
            check=True,
        )
    return built


class Command:
    """Runs the `rattle` command."""

    def __init__(self, path):
        self.path = path

    def run(self, *args):
        """Exit code, standard output and standard error of `rattle ARGS`."""
        done = subprocess.run(
            [str(self.path), *map(str, args)], capture_output=True, text=True, check=False
        )
        return done.returncode, done.stdout, done.stderr

    def json(self, *args):
        """The JSON document `rattle ARGS --json` prints."""
        code, out, err = self.run(*args, "--json")
        assert code == 0, err
        return json.loads(out)

    def error(self, *args):
        """The message of a failing `rattle ARGS`, without the `rattle: ` prefix."""
        code, _, err = self.run(*args)
        assert code != 0
        assert err.startswith("rattle: "), err
        return err[len("rattle: ") :].rstrip("\n")


@pytest.fixture(scope="session")
def rattle_cli():
    """The `rattle` command."""
    return Command(_command())
