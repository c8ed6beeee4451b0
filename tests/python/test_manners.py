"""What a scipy/xarray user expects of a package: submodules reachable after `import fputlab`
(loaded on first use, PEP 562), `__all__` in every public module, one-line reprs cut only between
whole parts, never the arrays themselves."""
import ast
import importlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import fputlab
from fputlab._display import join_parts, shorten

PACKAGE = Path(fputlab.__file__).parent
PUBLIC_MODULES = sorted(
    ".".join(("fputlab",) + p.relative_to(PACKAGE).with_suffix("").parts).removesuffix(".__init__")
    for p in PACKAGE.rglob("*.py")
    if not any(part.startswith("_") for part in p.relative_to(PACKAGE).parts[:-1])
    and (not p.name.startswith("_") or p.name == "__init__.py") and p.name != "__main__.py")


def test_submodules_load_on_first_use():
    code = ("import sys, fputlab\n"
            "lazy = ['fputlab.plotting', 'fputlab.chaos', 'fputlab.io', 'h5py', 'matplotlib']\n"
            "before = [m for m in lazy if m in sys.modules]\n"
            "assert fputlab.plotting.plot_mode_energies and fputlab.chaos.study.ChaosStudy\n"
            "assert fputlab.load is fputlab.io.load\n"
            "assert 'plotting' in dir(fputlab) and 'np' not in dir(fputlab)\n"
            "print(before)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"
    with pytest.raises(AttributeError, match="no attribute 'plotings'"):
        fputlab.plotings


# the command line's API is its parser (docs/cli.rst), not Python names
@pytest.mark.parametrize("name", [m for m in PUBLIC_MODULES
                                  if m != "fputlab.cli" and not m.startswith("fputlab.cli.")])
def test_every_public_module_has_all(name):
    module = importlib.import_module(name)
    assert isinstance(getattr(module, "__all__", None), list), f"{name} has no __all__"
    missing = [n for n in module.__all__ if not hasattr(module, n)]
    assert missing == [] and len(set(module.__all__)) == len(module.__all__)
    # no helper modules re-exported by accident
    assert not {"np", "os", "sys", "time", "math", "ll"} & set(module.__all__)


def test_public_modules_are_found():
    assert {"fputlab.chaos", "fputlab.io.files", "fputlab.reduction.modal",
            "fputlab.plotting"} <= set(PUBLIC_MODULES)


def test_shorten_cuts_at_word_boundaries():
    text = "the state became NaN between t = 2545 and t = 2546 (a blow-up)"
    assert shorten(text, 200) == text
    short = shorten(text, 30)
    assert len(short) <= 30 and short.endswith("...")
    assert text.startswith(short[:-3]) and text[len(short) - 3] == " "
    assert shorten("x" * 50, 10) == "x" * 7 + "..."         # one long word: cut anyway


def test_join_parts_keeps_whole_parts():
    parts = ["N=64", "model='nonlinear'", "method='yoshida4'", "state[128]"]
    assert join_parts("Blowup", parts) == "Blowup(" + ", ".join(parts) + ")"
    for width in range(12, 60):
        text = join_parts("Blowup", parts, width)
        assert len(text) <= width or text == "Blowup(...)"
        inner = text[len("Blowup("):-1].split(", ")
        assert inner[-1] == "..." and inner[:-1] == parts[:len(inner) - 1]


def test_result_reprs_are_whole_parts_and_hold_no_arrays(tmp_path):
    lat = fputlab.Lattice(64, 0.25, "nonlinear", tau=20, seed=1)
    b = fputlab.blowup.blowup_time(lat, 1e4)
    run = fputlab.Lattice(8).integrate(10.0)
    chaos = fputlab.chaos.lyapunov(fputlab.Lattice(8), 50.0)
    fputlab.io.simulate_to_file(lat, 50.0, tmp_path / "r.h5")
    res = fputlab.load(tmp_path / "r.h5")
    for obj in (b, run, chaos, res):
        text = repr(obj)
        assert "\n" not in text and len(text) <= 220, text
        assert "array(" not in text and "[1." not in text, text
        # a cut repr ends in a whole part followed by ', ...)'
        assert not text.endswith("...)") or text.endswith(", ...)"), text
    text = repr(res)
    assert text.startswith(f"Results({os.fspath(tmp_path / 'r.h5')!r}, N=64, model='nonlinear'")
    assert "tau=20" in text and "seed=1" in text and "mode_energies[" in text
    assert str(np.round(lat.v[0], 4)) not in text
