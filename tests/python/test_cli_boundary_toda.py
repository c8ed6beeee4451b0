"""`--boundary fixed|periodic` and `--model toda` in `fputlab simulate` and `fputlab chaos`: the
lattice the command builds is the one Lattice(...) builds, the Toda chain's beta = 0 rule and the
ensembles' refusal are one line and exit 2, a bad boundary is one line and exit 2."""
import json

import numpy as np
import pytest

from fputlab import Lattice
from fputlab.cli import main, parse_args
from fputlab.cli._common import _lattice


@pytest.mark.parametrize("cmd", ["simulate", "chaos"])
@pytest.mark.parametrize("model, boundary", [("toda", "periodic"), ("toda", "fixed"),
                                             ("homogeneous", "periodic"),
                                             ("hamiltonian", "periodic")])
def test_the_command_builds_the_lattice_of_the_python_api(cmd, model, boundary):
    extra = ["--tau", "5", "--seed", "3"] if model == "hamiltonian" else []
    a = parse_args([cmd, "--N", "8", "--alpha", "0.5", "--model", model, "--boundary", boundary,
                    *extra])
    lat = _lattice(a)
    kw = {"tau": 5.0, "seed": 3} if model == "hamiltonian" else {}
    ref = Lattice(8, 0.5, model, boundary=boundary, **kw)
    assert (lat.model, lat.boundary, lat.N, lat.alpha) == (model, boundary, 8, 0.5)
    y = np.random.default_rng(1).normal(scale=0.1, size=16)
    np.testing.assert_array_equal(lat.energy(y), ref.energy(y))


def test_simulate_and_chaos_run_a_periodic_toda_chain(capsys):
    assert main(["simulate", "--N", "8", "--model", "toda", "--alpha", "1", "--boundary",
                 "periodic", "--t-end", "50", "--dt", "0.05", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert "model='toda'" in out["lattice"] and "boundary='periodic'" in out["lattice"]
    assert out["completed"] and out["max_relative_energy_error"] < 1e-4
    assert main(["chaos", "--N", "8", "--model", "toda", "--boundary", "periodic", "--t-end",
                 "200", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["class"] in ("regular", "undecided") and out["t_final"] == 200.0


@pytest.mark.parametrize("argv, words", [
    (["simulate", "--boundary", "ring"], ["--boundary", "'ring'", "periodic"]),
    (["chaos", "--boundary", "Periodic"], ["--boundary", "'Periodic'"]),
    (["simulate", "--model", "toda", "--beta", "0.1"], ["--beta", "Toda"]),
    (["chaos", "--model", "toda", "--beta", "0.1"], ["--beta", "Toda"]),
    (["simulate", "--model", "toda", "--tau", "5"], ["--tau", "toda", "no disorder"]),
    (["simulate", "--model", "toda", "--seed", "2"], ["--seed", "toda"]),
    (["chaos", "--N", "8", "16", "--model", "toda"], ["one orbit only"]),
    (["chaos", "--N", "8", "16", "--boundary", "periodic"], ["one orbit only"]),
])
def test_bad_values_are_one_line_and_exit_2(argv, words, capsys):
    assert main([*argv, "--t-end", "10"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("fputlab: error:")
    for w in words:
        assert w in err
