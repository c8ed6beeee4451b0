"""Bad input: a clear error naming the parameter, never a crash or silent garbage."""
import numpy as np
import pytest

from fputlab import FputlabError, IntegrationError, Integrator, Lattice, draw_disorder, integrate


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


def test_harmonic_split_refuses_varying_linear_couplings():
    # model 2's linear part is not the sine-transform chain: a clear refusal naming the method
    # and the alternative, from the run API, the Integrator and the chaos indicators alike
    lat = Lattice(8, 0.25, "hamiltonian", tau=10.0, seed=1)
    with pytest.raises(ValueError, match="aba864-harmonic.*use 'aba864'"):
        integrate(lat, 1.0, method="aba864-harmonic", dt=0.1)
    with pytest.raises(ValueError, match="aba864-harmonic"):
        Integrator(lat, lat.mode_state(), method="aba864-harmonic", dt=0.1)
    from fputlab import chaos
    with pytest.raises(ValueError, match="aba864-harmonic"):
        chaos.lyapunov(lat, 10.0, method="aba864-harmonic", dt=0.1)
    # the models it applies to run
    for model in ("homogeneous", "nonlinear"):
        lat = Lattice(8, 0.25, model, **({} if model == "homogeneous" else dict(tau=10, seed=1)))
        assert integrate(lat, 1.0, method="aba864-harmonic", dt=0.1).t[-1] == 1.0


def test_bad_end_time_and_disorder():
    with pytest.raises(ValueError, match="t_end"):
        integrate(Lattice(4), -1.0)
    with pytest.raises(TypeError, match="lattice"):
        integrate("lattice", 1.0)
    with pytest.raises(ValueError, match="tau"):
        draw_disorder(8, 100.0, 1, kind="uniform")


ADAPTIVE = ["dop853", "cvode-adams", "gsl-rk8pd"]
BAD_TOLERANCES = [
    (dict(rtol=0.0), "rtol"),
    (dict(rtol=-1e-8), "rtol"),
    (dict(rtol=float("nan")), "rtol"),
    (dict(rtol=float("inf")), "rtol"),
    (dict(atol=0.0), "atol"),
    (dict(atol=-1e-12), "atol"),
    (dict(atol=float("nan")), "atol"),
]


@pytest.mark.parametrize("method", ADAPTIVE)
@pytest.mark.parametrize("kwargs,word", BAD_TOLERANCES)
def test_bad_tolerances(kwargs, word, method):
    lat = Lattice(4)
    with pytest.raises(ValueError, match=rf"{word} must be finite and > 0"):
        Integrator(lat, lat.mode_state(), method=method, **kwargs)
    with pytest.raises(ValueError, match=rf"{word} must be finite and > 0"):
        integrate(lat, 1.0, method=method, **kwargs)


@pytest.mark.parametrize("method", ["yoshida4", "dop853", "cvode-adams"])
@pytest.mark.parametrize("t0", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_start_time(t0, method):
    lat = Lattice(4)
    with pytest.raises(ValueError, match="t0 must be finite"):
        Integrator(lat, lat.mode_state(), method=method, t0=t0)


@pytest.mark.parametrize("t0", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_start_time_integrate(t0):
    with pytest.raises(ValueError):
        integrate(Lattice(4), 1.0, t0=t0)


@pytest.mark.parametrize("t0", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_start_time_integrate_names_t0(t0):
    with pytest.raises(ValueError, match="t0 must be finite"):
        integrate(Lattice(4), 1.0, t0=t0)


@pytest.mark.parametrize("method,package,flag", [
    ("dop853", "ARKODE", "ARK_TOO_MUCH_WORK"),
    ("dopri5", "ARKODE", "ARK_TOO_MUCH_WORK"),
    ("cvode-adams", "CVODE", "CV_TOO_MUCH_WORK"),
    ("cvode-bdf", "CVODE", "CV_TOO_MUCH_WORK"),
])
def test_too_much_work_carries_the_sundials_flag(method, package, flag):
    lat = Lattice(4)
    integ = Integrator(lat, lat.mode_state(), method=method, max_steps=5)
    with pytest.raises(FputlabError) as info:
        integ.advance(1e3)
    err = info.value
    # a back-end failure, not a blow-up (the state is finite): not an IntegrationError
    assert not isinstance(err, IntegrationError)
    assert err.status == -5                                     # FPL_ERR_BACKEND
    msg = str(err)
    assert f"{package} {method} failed at t = " in msg
    assert f"flag -1 ({flag})" in msg                           # SUNDIALS' flag and its name
    assert "mxstep steps taken before reaching tout" in msg     # and SUNDIALS' own message
    t_fail = float(msg.split("failed at t = ")[1].split(":")[0])
    assert 0.0 < t_fail < 1e3
    assert np.all(np.isfinite(integ.state))


def test_too_much_work_gsl():
    lat = Lattice(4)
    with pytest.raises(FputlabError, match=r"GSL gsl-rk8pd failed at t = .*max_steps = 5 steps"):
        Integrator(lat, lat.mode_state(), method="gsl-rk8pd", max_steps=5).advance(1e3)
