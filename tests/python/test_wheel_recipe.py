"""The wheel recipe (tools/build-wheel.sh, tools/test-wheel.sh, `./dev wheel`, `./dev test-wheel`)
is consistent with its how-to (docs/wheels.md). Building and testing the wheel itself takes
minutes to an hour and needs root, so it is not run here: `./dev test-wheel` does that."""
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD = ROOT / "tools" / "build-wheel.sh"


def pinned():
    """(name, version, Debian source package, tarball, SHA-256) of each vendored library."""
    block = re.search(r"^VENDORED=\((.*?)^\)", BUILD.read_text(), re.S | re.M).group(1)
    return [tuple(line.split("|")[:5]) for line in re.findall(r'"([^"]+)"', block)]


def test_every_vendored_library_is_pinned_by_sha256():
    libs = pinned()
    assert {name for name, *_ in libs} == {"zlib", "HDF5", "GSL", "SUNDIALS"}
    for name, version, package, tarball, sha256 in libs:
        assert re.fullmatch(r"[0-9a-f]{64}", sha256), name
        assert tarball.startswith(f"{package}_") and ".orig.tar." in tarball, name
    assert dict((n, v) for n, v, *_ in libs)["SUNDIALS"].startswith("7.")


def test_the_howto_names_the_pinned_versions():
    doc = (ROOT / "docs" / "wheels.md").read_text()
    for name, version, *_ in pinned():
        assert re.search(rf"^\| {name} \| {re.escape(version)} \|", doc, re.M), name


@pytest.mark.skipif(shutil.which("bash") is None, reason="needs bash")
@pytest.mark.parametrize("script", ["build-wheel.sh", "test-wheel.sh", "debian-mirror.sh"])
def test_scripts_parse(script):
    subprocess.run(["bash", "-n", str(ROOT / "tools" / script)], check=True)


def test_dev_lists_the_wheel_commands():
    dev = (ROOT / "dev").read_text()
    for cmd in ("wheel", "test-wheel"):
        assert re.search(rf"^#   \./dev {cmd} ", dev, re.M), cmd
        assert re.search(rf"^  {cmd}\)$", dev, re.M), cmd
