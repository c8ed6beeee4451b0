"""The API reference: numpydoc docstrings list every parameter of the main public functions,
Lattice.integrate spells out fputlab.integrate's parameters, the C API page covers every exported
function, and the package is marked typed. (`./dev docs` builds the HTML with warnings as
errors; .ci/run runs it.)"""
import importlib.util
import inspect
import re
import subprocess
import sys
from pathlib import Path

import pytest

import fputlab
from fputlab import (analysis, blowup, chaos, ensemble, figures, figures_reduction, io, plotting,
                     reduction)

ROOT = Path(__file__).resolve().parents[2]

MAIN = [fputlab.Lattice, fputlab.Lattice.integrate, fputlab.integrate, fputlab.Integrator,
        fputlab.iter_samples, chaos.lyapunov, blowup.blowup_time, blowup.blowup_sweep,
        plotting.plot_mode_energies, plotting.envelope, plotting.plot_envelope, plotting.plot_mle,
        plotting.plot_sali, plotting.plot_two_mode, plotting.plot_blowup_sweep,
        plotting.plot_bifurcation, plotting.plot_bifurcation_curves,
        figures.fig1, figures.fig2, figures.fig3, reduction.two_mode_coefficients,
        reduction.critical_tolerance, reduction.two_mode_run, reduction.envelope_run,
        chaos.chaotic_fraction, analysis.recurrences, analysis.energy_share,
        analysis.spectral_entropy, analysis.effective_modes, analysis.normalised_entropy,
        ensemble.run_sweep, ensemble.load_sweep, ensemble.run_calls, ensemble.run_task,
        ensemble.run_chaos_group, ensemble.check_ensemble, ensemble.process_pool,
        plotting.plot_blowup_sweep_figure, io.simulate_to_file, io.chaos_to_file, io.load,
        io.write_checkpoint, io.load_checkpoint, io.checkpoint_time, io.ResultsFile,
        chaos.lyapunov_spectrum, chaos.covariant_lyapunov_vectors, chaos.lyapunov_spectra,
        plotting.plot_spectrum,
        plotting.plot_spectrum_convergence, plotting.plot_megno, plotting.plot_clv_localisation]
# every public function of the reduction modules
MAIN += [obj for mod in (reduction.coefficients, reduction.statistics, reduction.modal,
                         reduction.envelope, reduction.reduced)
         for name, obj in vars(mod).items()
         if inspect.isfunction(obj) and not name.startswith("_") and obj.__module__ == mod.__name__]


@pytest.mark.parametrize("obj", [chaos.chaotic_fraction, analysis.recurrences,
                                 analysis.energy_share, ensemble.run_sweep, ensemble.run_calls,
                                 ensemble.load_sweep, ensemble.check_ensemble],
                         ids=lambda o: o.__qualname__)
def test_ensemble_and_analysis_docstrings_have_returns_and_raises(obj):
    doc = inspect.getdoc(obj)
    assert re.search(r"\n(Returns|Yields)\n-+\n", doc), obj
    assert re.search(r"\nRaises\n-+\n", doc) or obj is ensemble.run_calls, obj


def documented_parameters(doc: str) -> list[str]:
    """Names in the numpydoc Parameters section ("a, b : type" documents a and b)."""
    m = re.search(r"\n\s*Parameters\n\s*-+\n(.*?)(\n\s*\n\s*[A-Z][a-z ]+\n\s*-+\n|\Z)", doc, re.S)
    assert m, "no numpydoc Parameters section"
    names = []
    for line in m.group(1).split("\n"):
        head = re.match(r"^(\*{0,2}\w+(?:, \*{0,2}\w+)*)(?: :|$)", line)
        if head:
            names += [n.strip().lstrip("*") for n in head.group(1).split(",")]
    return names


@pytest.mark.parametrize("obj", MAIN, ids=lambda o: o.__qualname__)
def test_every_parameter_is_documented(obj):
    target = obj.__init__ if inspect.isclass(obj) else obj
    wanted = [p.name for p in inspect.signature(target).parameters.values() if p.name != "self"]
    assert sorted(documented_parameters(inspect.getdoc(obj))) == sorted(wanted)


def test_lattice_integrate_has_the_parameters_of_integrate():
    method = inspect.signature(fputlab.Lattice.integrate).parameters
    function = inspect.signature(fputlab.integrate).parameters
    assert [(p.name, p.default, p.kind) for p in list(method.values())[1:]] == \
        [(p.name, p.default, p.kind) for p in list(function.values())[1:]]


def test_c_api_page_covers_every_exported_function(tmp_path):
    out = tmp_path / "c_api.rst"
    subprocess.run([sys.executable, str(ROOT / "tools" / "gen_c_api_docs.py"), "--output", str(out)],
                   check=True)
    page = out.read_text()
    exported = set()
    for header in (ROOT / "include" / "fputlab").glob("*.h"):
        text = re.sub(r"/\*.*?\*/", "", header.read_text(), flags=re.S)
        exported |= set(re.findall(r"FPL_API[^;(]*?\b(fpl_\w+)\s*\(", text))
    assert len(exported) > 80
    missing = sorted(n for n in exported if f"``{n}``" not in page)
    assert missing == []


def test_package_is_typed():
    spec = importlib.util.find_spec("fputlab")
    assert (Path(spec.origin).parent / "py.typed").is_file()
