"""Every Python block in README.md and the Markdown guides (docs/*.md) runs as written.

A block fenced ```python is run; the blocks of one file run in order in one fresh interpreter (a
later block may use the names of an earlier one, as a reader would), in an empty temporary
directory. A block that must not run (an excerpt, a sketch of a long job) is fenced
```python notest: shown as Python, not run. Other languages (sh, c, text) are not run here
(the README's `fputlab ...` commands are run by test_readme_commands.py)."""
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FENCE = re.compile(r"^```([^\n`]*)\n(.*?)^```\s*$", re.S | re.M)
RUN, SKIP = "python", "python notest"


def documents() -> list[Path]:
    docs = [p for p in sorted((ROOT / "docs").glob("*.md")) if p.name != "README.md"]
    return [ROOT / "README.md", *docs]


def blocks(path: Path) -> list[tuple[str, str]]:
    """(info string, code) of every fenced block."""
    return [(m.group(1).strip(), m.group(2)) for m in FENCE.finditer(path.read_text())]


def python_blocks(path: Path) -> list[str]:
    return [code for info, code in blocks(path) if info == RUN]


DOCS_WITH_PYTHON = [p for p in documents() if python_blocks(p)]


def test_the_readme_quick_start_is_among_the_run_blocks():
    assert ROOT / "README.md" in DOCS_WITH_PYTHON
    quick_start = "\n".join(python_blocks(ROOT / "README.md"))
    assert "with_deviation_vectors" in quick_start and "Integrator" in quick_start


@pytest.mark.parametrize("path", documents(), ids=lambda p: p.name)
def test_python_blocks_are_marked_run_or_notest(path):
    # a Python-looking block under another info string would silently escape this test
    for info, code in blocks(path):
        if info.startswith("python") or info in ("py", "pycon", "ipython"):
            assert info in (RUN, SKIP), f"{path.name}: fence info {info!r}: use {RUN!r} or {SKIP!r}"
        elif info == "":
            assert not re.search(r"^(import fputlab|from fputlab)", code, re.M), \
                f"{path.name}: an unmarked block imports fputlab: fence it {RUN!r} or {SKIP!r}"


@pytest.mark.parametrize("path", DOCS_WITH_PYTHON, ids=lambda p: p.name)
def test_python_blocks_run_as_written(path, tmp_path):
    code = "\n\n".join(python_blocks(path))
    script = tmp_path / f"{path.stem}_blocks.py"
    script.write_text("import matplotlib\nmatplotlib.use('Agg')\n" + code)
    proc = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, f"{path.name}:\n{proc.stderr[-3000:]}"
