"""Every example in examples/python/ runs (non-interactive matplotlib, output
into a temporary directory)."""
import os
import subprocess
import sys

import pytest

import fulcrum
from conftest import REPO

EXAMPLES = sorted((REPO / "examples" / "python").glob("*.py"))


def test_there_are_examples():
    assert {p.name for p in EXAMPLES} >= {"bouncing_ball.py", "pendulum.py", "pile.py", "cloth.py", "scene_file.py"}


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.name)
def test_example_runs(example, tmp_path):
    # The examples import the same fulcrum as the tests (PYTHONPATH may be relative).
    package_parent = os.path.dirname(os.path.dirname(os.path.abspath(fulcrum.__file__)))
    path = os.pathsep.join([package_parent] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])
    env = dict(os.environ, MPLBACKEND="Agg", MPLCONFIGDIR=str(tmp_path / "mpl"), PYTHONPATH=path)
    result = subprocess.run([sys.executable, str(example), "--out", str(tmp_path)], capture_output=True, text=True,
                            env=env, cwd=tmp_path, timeout=300)
    assert result.returncode == 0, result.stderr
    assert "wrote" in result.stdout
    written = [p for p in tmp_path.iterdir() if p.suffix in (".png", ".html", ".json")]
    assert written, "the example wrote no file"
