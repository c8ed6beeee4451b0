"""Bad input: a clear error naming the parameter, never a crash or silent garbage."""
import numpy as np
import pytest

from fputlab import Lattice, draw_disorder, integrate


@pytest.mark.parametrize("kwargs,exc,word", [
    (dict(N=1), ValueError, "N"),
    (dict(N=-3), ValueError, "N"),
    (dict(N=4.5), TypeError, "N"),
    (dict(N=8, alpha=float("nan")), ValueError, "alpha"),
    (dict(N=8, alpha="big"), TypeError, "alpha"),
    (dict(N=8, beta=float("inf")), ValueError, "beta"),
    (dict(N=8, model="quartic"), ValueError, "model"),
    (dict(N=8, model=5), ValueError, "model"),
    (dict(N=8, model="nonlinear", tau=-1.0, seed=1), ValueError, "tau"),
    (dict(N=8, model="nonlinear", tau=float("nan"), seed=1), ValueError, "tau"),
    (dict(N=8, model="homogeneous", tau=5.0, seed=1), ValueError, "tau"),
    (dict(N=8, model="nonlinear", tau=5.0, seed=-1), ValueError, "seed"),
    (dict(N=8, model="nonlinear", tau=5.0, seed=1, disorder="cauchy"), ValueError, "disorder"),
    (dict(N=4, model="hamiltonian", v=[1, 1, 0, 1]), ValueError, "v[2]"),
    (dict(N=4, model="hamiltonian", v=[1, 1, 1]), ValueError, "v"),
    (dict(N=4, model="hamiltonian", v=["a"] * 4), TypeError, "v"),
])
def test_bad_lattice_parameters(kwargs, exc, word):
    with pytest.raises(exc, match=word.replace("[", r"\[").replace("]", r"\]")):
        Lattice(**kwargs)


def test_bad_arrays():
    lat = Lattice(4)
    with pytest.raises(ValueError, match="x has shape"):
        lat.force(np.zeros(5))
    with pytest.raises(ValueError, match=r"x\[1\]"):
        lat.force([0.0, np.nan, 0.0, 0.0])
    with pytest.raises(TypeError, match="real numeric"):
        lat.force(np.zeros(4, dtype=complex))
    with pytest.raises(ValueError, match="y has shape"):
        lat.rhs(np.zeros(9))
    with pytest.raises(ValueError, match="dx has shape"):
        lat.tangent_force(np.zeros(4), np.zeros((2, 3)))
    with pytest.raises(ValueError, match="mode k"):
        lat.mode_state(0)
    # non-contiguous input is accepted (copied), not misread
    x = np.zeros((4, 2))
    x[:, 0] = [0.1, 0.2, 0.3, 0.4]
    np.testing.assert_array_equal(lat.force(x[:, 0]), lat.force(np.array([0.1, 0.2, 0.3, 0.4])))


@pytest.mark.parametrize("kwargs,exc,word", [
    (dict(dt=0.0), ValueError, "dt"),
    (dict(dt=-0.01), ValueError, "dt"),
    (dict(dt=float("nan")), ValueError, "dt"),
    (dict(method="rk45"), ValueError, "rk45"),
    (dict(method=4), TypeError, "method"),
    (dict(sample_every=-1.0), ValueError, "sample_every"),
    (dict(times=[1.0, 0.5]), ValueError, "t_samples"),
    (dict(y0=np.zeros(3)), ValueError, "y0"),
    (dict(y0=[np.nan] * 8), ValueError, "y0"),
    (dict(on_failure="ignore"), ValueError, "on_failure"),
])
def test_bad_integration_arguments(kwargs, exc, word):
    with pytest.raises(exc, match=word):
        integrate(Lattice(4), 1.0, **kwargs)


def test_bad_end_time_and_disorder():
    with pytest.raises(ValueError, match="t_end"):
        integrate(Lattice(4), -1.0)
    with pytest.raises(TypeError, match="lattice"):
        integrate("lattice", 1.0)
    with pytest.raises(ValueError, match="tau"):
        draw_disorder(8, 100.0, 1, kind="uniform")
