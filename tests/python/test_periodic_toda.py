"""Periodic chains and the Toda lattice: forces against the equations written out with numpy,
derivatives against finite differences, conservation laws (energy, momentum, the Toda chain's
Lax invariants), Toda against FPUT-alpha-beta at small amplitude, and the refusals."""
import numpy as np
import pytest

import fputlab
from fputlab import Lattice

POLY_MODELS = ["homogeneous", "hamiltonian", "nonlinear"]
ALL_MODELS = POLY_MODELS + ["toda"]


def make(model, N=9, alpha=0.5, beta=0.0, boundary="periodic"):
    dis = dict(tau=15.0, seed=4) if model in ("hamiltonian", "nonlinear") else {}
    return Lattice(N, alpha, model, beta=beta, boundary=boundary, **dis)


def ring_acceleration(model, x, v, a, b):
    """x'' of the ring written out with numpy: bond j joins particles j-1 and j (mod N)."""
    d = x - np.roll(x, 1)
    r = v * x - np.roll(v * x, 1)
    if model == "toda":
        bond = np.expm1(2 * a * d) / (2 * a)
    else:
        g = lambda lin, nl: lin + a * nl**2 + b * nl**3
        bond = {"homogeneous": g(d, d), "hamiltonian": g(r, r), "nonlinear": g(d, r)}[model]
    return np.roll(bond, -1) - bond


def toda_fixed_acceleration(x, a):
    X = np.concatenate([[0.0], x, [0.0]])
    bond = np.expm1(2 * a * np.diff(X)) / (2 * a)
    return np.diff(bond)


def central_jacobian(f, y, h=1e-6):
    cols = []
    for i in range(y.size):
        e = np.zeros_like(y)
        e[i] = h
        cols.append((f(y + e) - f(y - e)) / (2 * h))
    return np.array(cols).T


@pytest.mark.parametrize("model", ALL_MODELS)
@pytest.mark.parametrize("N", [2, 3, 9])
def test_ring_force_matches_equations(model, N, rng):
    beta = 0.0 if model == "toda" else 0.2
    lat = make(model, N=N, beta=beta)
    x = 0.4 * rng.standard_normal(N)
    mass = lat.v if model == "hamiltonian" else np.ones(N)
    np.testing.assert_allclose(lat.force(x), mass * ring_acceleration(model, x, lat.v, 0.5, beta),
                               rtol=1e-12, atol=1e-14)


def test_toda_fixed_force_matches_equations(rng):
    lat = Lattice(7, 0.7, "toda")
    x = 0.5 * rng.standard_normal(7)
    np.testing.assert_allclose(lat.force(x), toda_fixed_acceleration(x, 0.7), rtol=1e-12,
                               atol=1e-14)


@pytest.mark.parametrize("model,boundary", [(m, "periodic") for m in ALL_MODELS]
                         + [("toda", "fixed")])
def test_jacobian_with_deviation_vector_matches_finite_differences(model, boundary, rng):
    beta = 0.0 if model == "toda" else 0.3
    lat = make(model, N=6, beta=beta, boundary=boundary)
    y = 0.3 * rng.standard_normal(2 * 2 * 6)   # orbit + one deviation vector
    np.testing.assert_allclose(lat.jacobian(y), central_jacobian(lat.rhs, y), atol=2e-8)
    # tangent force = J dx, and the dense force Jacobian of the orbit
    x, dx = y[:6], y[12:18]
    J = central_jacobian(lat.force, x)
    np.testing.assert_allclose(lat.tangent_force(x, dx), J @ dx, atol=2e-8)
    np.testing.assert_allclose(lat.force_jacobian(x, dense=True), J, atol=2e-8)


@pytest.mark.parametrize("model,boundary", [("homogeneous", "periodic"), ("hamiltonian", "periodic"),
                                            ("toda", "periodic"), ("toda", "fixed")])
def test_force_is_minus_energy_gradient(model, boundary, rng):
    lat = make(model, N=7, beta=0.0 if model == "toda" else 0.2, boundary=boundary)
    y = 0.3 * rng.standard_normal(14)
    grad = central_jacobian(lambda z: np.atleast_1d(lat.energy(z)), y)[0, :7]
    np.testing.assert_allclose(lat.force(y[:7]), -grad, atol=1e-9)


def test_ring_two_particles_share_both_bonds(rng):
    """N = 2: bonds 0 and 1 both join the two particles, d_1 = -d_0."""
    lat = Lattice(2, 0.5, boundary="periodic")
    x = np.array([0.3, -0.1])
    d = x[1] - x[0]
    phi = lambda s: s + 0.5 * s**2
    assert lat.force(x)[0] == pytest.approx(phi(d) - phi(-d))
    assert lat.energy(np.r_[x, 0, 0]) == pytest.approx(d**2)   # V(d) + V(-d)


@pytest.mark.parametrize("model", ALL_MODELS)
@pytest.mark.parametrize("method", ["yoshida4", "aba864", "dprkn8", "dop853", "cvode-bdf",
                                    "gsl-rk8pd"])
def test_ring_conserves_energy_and_momentum(model, method, rng):
    """Hamiltonian rings conserve H, every ring conserves sum x' (forces sum to zero per s)."""
    lat = make(model, beta=0.0 if model == "toda" else 0.2)
    y0 = 0.3 * rng.standard_normal(18)
    fixed_step = method in ("yoshida4", "aba864", "dprkn8")
    kw = dict(dt=0.005) if fixed_step else dict(rtol=1e-11, atol=1e-13)
    y = Integrator_advance(lat, y0, method, 20.0, **kw)
    if model != "nonlinear":
        tol = 1e-6 if method == "cvode-bdf" else 1e-9
        assert abs(lat.energy(y) - lat.energy(y0)) < tol
    assert abs(lat.velocity(y).sum() - lat.velocity(y0).sum()) < 1e-12


def Integrator_advance(lat, y0, method, t, **kw):
    return fputlab.Integrator(lat, y0, method=method, **kw).advance(t).ravel()


@pytest.mark.parametrize("beta", [0.0, 0.3])
def test_fused_ring_stepper_matches_generic_kick(beta, rng):
    """Model 1's fused ring stepper against model 3's generic ring kick with v = 1 (the same
    equations), orbit and deviation vectors, to round-off."""
    y0 = 0.3 * rng.standard_normal((3, 2 * 11))
    out = []
    for model in ("homogeneous", "nonlinear"):
        lat = Lattice(11, 0.5, model, beta=beta, boundary="periodic")
        out.append(fputlab.Integrator(lat, y0, method="yoshida4").advance(20.0))
    np.testing.assert_allclose(out[0], out[1], rtol=0, atol=1e-12)


def test_ring_scheme_order_against_dop853(rng):
    """The ring under a splitting scheme converges to the adaptive reference at its order."""
    lat = Lattice(8, 0.5, beta=0.1, boundary="periodic")
    y0 = 0.4 * rng.standard_normal(16)
    ref = Integrator_advance(lat, y0, "dop853", 5.0, rtol=1e-13, atol=1e-14)
    errs = [np.abs(Integrator_advance(lat, y0, "yoshida4", 5.0, dt=dt) - ref).max()
            for dt in (0.04, 0.02)]
    assert 12 < errs[0] / errs[1] < 20   # 2^4


def lax_traces(y, N, alpha, ks=(3, 4)):
    """tr L^k of the periodic Toda chain's Lax matrix (Flaschka): in these variables
    L = diag(p) + c_j (E_{j,j+1} + E_{j+1,j}), c_j = -e^{alpha r_j}/(2 alpha), r_j = x_{j+1} - x_j
    (indices mod N), so that tr L^2 = 2H + const."""
    x, p = y[:N], y[N:]
    c = -np.exp(alpha * (np.roll(x, -1) - x)) / (2 * alpha)
    L = np.diag(p)
    j = np.arange(N)
    L[j, (j + 1) % N] += c
    L[(j + 1) % N, j] += c
    return np.array([np.trace(np.linalg.matrix_power(L, k)) for k in ks])


def test_toda_lax_invariants_conserved_while_fput_drifts(rng):
    N, alpha = 8, 1.0
    y0 = np.r_[0.5 * rng.standard_normal(N), 0.6 * rng.standard_normal(N)]
    times = np.linspace(10.0, 200.0, 20)
    drift = {}
    for model, beta in (("toda", 0.0), ("homogeneous", 2 * alpha**2 / 3)):
        lat = Lattice(N, alpha, model, beta=beta, boundary="periodic")
        it = fputlab.Integrator(lat, y0, method="dop853", rtol=1e-12, atol=1e-14)
        _, st, _, _ = it.sample(times, states=True, mode_energies=False, energies=False)
        inv0 = lax_traces(y0, N, alpha)
        inv = np.array([lax_traces(s[0], N, alpha) for s in st])
        drift[model] = np.abs(inv - inv0).max(axis=0) / np.abs(inv0)
    assert drift["toda"].max() < 1e-8
    assert drift["homogeneous"].min() > 1e-3
    # tr L^2 is 2H + N/(2 alpha^2) (the linear terms of V sum to zero on a ring)
    lat = Lattice(N, alpha, "toda", boundary="periodic")
    tr2 = lax_traces(y0, N, alpha, ks=(2,))[0]
    assert tr2 == pytest.approx(2 * lat.energy(y0) + N / (2 * alpha**2), rel=1e-12)


@pytest.mark.parametrize("boundary", ["fixed", "periodic"])
def test_toda_is_fput_alpha_beta_to_fourth_order(boundary, rng):
    """V_Toda - V_FPUT(beta = 2 alpha^2/3) = O(r^5): the forces differ by O(eps^4) and a short
    trajectory by a relative O(eps^3)."""
    alpha, N = 0.8, 10
    toda = Lattice(N, alpha, "toda", boundary=boundary)
    fput = Lattice(N, alpha, beta=2 * alpha**2 / 3, boundary=boundary)
    x = rng.standard_normal(N)
    diffs = [np.abs(toda.force(e * x) - fput.force(e * x)).max() for e in (1e-2, 5e-3)]
    assert diffs[0] / diffs[1] == pytest.approx(16, rel=0.05)
    # trajectories: relative distance O(eps^3) (the O(eps^4) force difference over the O(eps)
    # force), so halving eps divides it by ~8
    rel = []
    for eps in (0.04, 0.02):
        y0 = np.r_[eps * x, np.zeros(N)]
        a = Integrator_advance(toda, y0, "dop853", 10.0, rtol=1e-13, atol=1e-16)
        b = Integrator_advance(fput, y0, "dop853", 10.0, rtol=1e-13, atol=1e-16)
        rel.append(np.abs(a - b).max() / eps)
    assert 6 < rel[0] / rel[1] < 10


def test_toda_mle_decays_like_one_over_t():
    """An integrable chain: a deviation vector grows linearly, |w| ~ b t, so the finite-time mLE
    is lambda(t) = ln(b t)/t and lambda t - ln t tends to the constant ln b; the FPUT-alpha-beta
    chain from the same (strongly nonlinear) state is chaotic, lambda t grows linearly."""
    N, alpha = 8, 1.0
    y0 = np.r_[2.0 * np.sin(2 * np.pi * np.arange(N) / N + 0.3), np.zeros(N)]
    y0[N] = 0.5   # a kick off the symmetric orbit
    out = {}
    for model, beta in (("toda", 0.0), ("homogeneous", 2 * alpha**2 / 3)):
        lat = Lattice(N, alpha, model, beta=beta, boundary="periodic")
        res = fputlab.chaos.lyapunov(lat, 2000.0, y0=y0, n_dev=1, n_samples=40, seed=3)
        t, lam = np.asarray(res.t), np.asarray(res.mle)
        late = t > 200
        out[model] = (lam[-1], lam[late] * t[late] - np.log(t[late]))
    lam_end, log_b = out["toda"]
    assert np.ptp(log_b) < 1.0 and lam_end < 0.01
    lam_end, growth = out["homogeneous"]
    assert lam_end > 0.03 and np.ptp(growth) > 50


@pytest.mark.parametrize("bad,match", [
    (dict(model="toda", beta=0.1), "beta"),
    (dict(model="toda", alpha=0.0), "alpha"),
    (dict(model="toda", v=np.linspace(0.9, 1.1, 6)), "v"),
    (dict(model="toda", tau=5.0, seed=1), "tau"),
    (dict(boundary="ring"), "boundary"),
])
def test_bad_arguments_name_the_parameter(bad, match):
    kw = dict(N=6, alpha=0.5) | bad
    with pytest.raises(ValueError, match=match):
        Lattice(**kw)
    with pytest.raises(TypeError, match="boundary"):
        Lattice(6, boundary=1)


def test_unsupported_combinations_refuse_with_a_message():
    ring = Lattice(8, 0.25, boundary="periodic")
    with pytest.raises(ValueError, match="boundary"):
        fputlab.Integrator(ring, ring.mode_state(1, 0.1), method="aba864-harmonic")
    with pytest.raises(ValueError, match="dense"):
        ring.force_jacobian(np.zeros(8))
    toda = Lattice(8, 0.25, "toda")
    with pytest.raises(ValueError, match="model"):
        fputlab.Integrator(toda, toda.mode_state(1, 0.1), method="aba864-harmonic")
    # the batch kernel takes rings and the Toda lattice (issue 22), one boundary and model a batch
    with pytest.raises(ValueError, match="boundary"):
        fputlab.chaos.lyapunov_batch([ring, Lattice(8, 0.25)], 1.0)
    with pytest.raises(ValueError, match="model"):
        fputlab.chaos.lyapunov_batch([toda, Lattice(8, 0.25)], 1.0)


@pytest.mark.parametrize("model", ALL_MODELS)
def test_lattice_pickles_with_its_boundary(model):
    import pickle
    lat = make(model, beta=0.0)
    back = pickle.loads(pickle.dumps(lat))
    assert back.boundary == "periodic" and back.model == model
    np.testing.assert_array_equal(back.v, lat.v)
    assert "periodic" in repr(lat)


def test_reductions_refuse_rings_and_toda():
    from fputlab import reduction
    ring = Lattice(8, 0.25, boundary="periodic")
    with pytest.raises(ValueError, match="boundary"):
        reduction.Galerkin(ring, 2)
    with pytest.raises(ValueError, match="sine modes"):
        reduction.two_mode_coefficients(ring)
    with pytest.raises(ValueError, match="model"):
        reduction.Galerkin(Lattice(8, 0.25, "toda"), 2)
    with pytest.raises(ValueError, match="model"):
        reduction.two_mode_coefficients(Lattice(8, 0.25, "toda"))


def test_results_file_records_the_boundary(tmp_path):
    """A ring's results file says so, and a fixed-end run cannot resume it."""
    import h5py
    from fputlab import io
    ring = Lattice(8, 0.25, boundary="periodic")
    path = tmp_path / "ring.h5"
    ck = tmp_path / "ring.ck"
    io.simulate_to_file(ring, 2.0, path, y0=ring.mode_state(1, 0.3), checkpoint=ck,
                        sample_every=0.5)
    with h5py.File(path) as f:
        assert f.attrs["boundary"] in ("periodic", b"periodic")
        np.testing.assert_array_equal(f["mode"][:], np.arange(8))
    run = io.load(path)
    np.testing.assert_allclose(run.mode_energies[0], ring.mode_energies(ring.mode_state(1, 0.3)),
                               rtol=1e-12)
    with pytest.raises(Exception, match="boundar"):
        io.simulate_to_file(Lattice(8, 0.25), 4.0, path, checkpoint=ck, resume=True)
