"""Project metadata: licence, citation, changelog and version agree with each other, and the
user-facing documentation stands alone (no links into a directory users do not have)."""
import importlib.metadata
import os
import re
from pathlib import Path

import pytest

import fputlab

ROOT = Path(__file__).resolve().parents[2]


def meson_project_version():
    text = (ROOT / "meson.build").read_text()
    m = re.search(r"project\([^)]*?version:\s*'([^']+)'", text, re.S)
    assert m, "meson.build: project(version: ...) not found"
    return m.group(1)


def test_version_is_defined_once_in_meson_build():
    version = meson_project_version()
    assert fputlab.__version__ == version                       # from the C library
    assert importlib.metadata.version("fputlab") == version     # from the wheel's metadata
    # pyproject.toml must take it from Meson, not state it again.
    pyproject = (ROOT / "pyproject.toml").read_text()
    assert re.search(r'^dynamic\s*=\s*\[[^]]*"version"', pyproject, re.M)
    assert not re.search(r"^version\s*=", pyproject, re.M)
    assert not re.search(r"^version\s*:", (ROOT / "CITATION.cff").read_text(), re.M)


def test_changelog_has_the_current_version():
    changelog = (ROOT / "CHANGELOG.md").read_text()
    released = re.findall(r"^## \[(\d[^]]*)\]", changelog, re.M)
    assert released and released[0] == meson_project_version()


def test_licence_is_gpl3_or_later_everywhere():
    licence = (ROOT / "LICENSE").read_text()
    assert "GNU GENERAL PUBLIC LICENSE" in licence and "Version 3, 29 June 2007" in licence
    assert "license: 'GPL-3.0-or-later'" in (ROOT / "meson.build").read_text()
    assert 'license = { text = "GPL-3.0-or-later" }' in (ROOT / "pyproject.toml").read_text()
    assert re.search(r"^license:\s*GPL-3.0-or-later\s*$", (ROOT / "CITATION.cff").read_text(), re.M)


def test_citation_names_the_paper():
    cff = (ROOT / "CITATION.cff").read_text()
    assert re.search(r"^cff-version:\s*1\.2\.0", cff, re.M)
    assert "Energy-recurrence Breakdown and Chaos in Disordered Fermi-Pasta-Ulam-Tsingou Lattices" in cff
    for name in ("Zulkarnain", "Susanto", "Antonopoulos"):
        assert f"family-names: {name}" in cff
    yaml = pytest.importorskip("yaml")
    data = yaml.safe_load(cff)
    assert data["preferred-citation"]["type"] == "article"


def user_docs():
    """README, CHANGELOG, CITATION, everything under docs/, and every other Markdown file of
    the repository (benchmarks/README.md, ...); build trees and the venv left out."""
    skip = {".venv", ".git", "_build", "_generated", "node_modules"}
    docs = [ROOT / "README.md", ROOT / "CHANGELOG.md", ROOT / "CITATION.cff"]
    docs += sorted(p for p in (ROOT / "docs").rglob("*")
                   if p.is_file() and p.suffix in {".md", ".rst", ".txt", ".py", ".cff"}
                   and not skip & set(p.parts))
    # pruned while walking, not filtered after: the build trees can be large (build-wheel/ holds
    # a whole Debian root, with /proc mounted in it while ./dev test-wheel runs)
    found = []
    for dirpath, dirnames, filenames in os.walk(ROOT):
        top = Path(dirpath) == ROOT
        dirnames[:] = [d for d in dirnames
                       if d not in skip and not (top and d.startswith("build"))]
        found += [Path(dirpath) / f for f in filenames if f.endswith(".md")]
    docs += sorted(p for p in found if p not in docs)
    return docs


@pytest.mark.parametrize("path", user_docs(), ids=lambda p: str(p.relative_to(ROOT)))
def test_user_docs_stand_alone(path):
    text = path.read_text()
    for bad in ("../shared", "shared/spec", "/work/"):
        assert bad not in text, f"{path.relative_to(ROOT)} points outside the repository: {bad!r}"
