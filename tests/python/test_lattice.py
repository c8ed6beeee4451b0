"""Lattice evaluation API against finite differences, the paper's equations and closed forms."""
import numpy as np
import pytest

import fputlab
from fputlab import Lattice

MODELS = ["homogeneous", "hamiltonian", "nonlinear"]


def paper_acceleration(model, x, v, a, b=0.0):
    """Eqs. (eqnmotions), (dis1), (varnonlin) written out with numpy, plus beta s^3."""
    X = np.concatenate([[0.0], x, [0.0]])
    V = np.concatenate([[1.0], v, [1.0]])
    d = np.diff(X)
    r = np.diff(V * X)
    g = lambda lin, nl: lin + a * nl**2 + b * nl**3
    bond = {"homogeneous": g(d, d), "hamiltonian": g(r, r), "nonlinear": g(d, r)}[model]
    return np.diff(bond)


def central_jacobian(f, y, h=1e-6):
    cols = []
    for i in range(y.size):
        e = np.zeros_like(y)
        e[i] = h
        cols.append((f(y + e) - f(y - e)) / (2 * h))
    return np.array(cols).T


@pytest.mark.parametrize("model", MODELS)
@pytest.mark.parametrize("beta", [0.0, 0.2])
def test_force_matches_paper_equations(model, beta, rng):
    N = 12
    lat = Lattice(N, 0.25, model, beta=beta, tau=15.0, seed=3) if model != "homogeneous" \
        else Lattice(N, 0.25, model, beta=beta)
    x = 0.4 * rng.standard_normal(N)
    mass = lat.v if model == "hamiltonian" else np.ones(N)
    np.testing.assert_allclose(lat.force(x), mass * paper_acceleration(model, x, lat.v, 0.25, beta),
                               rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("model", MODELS)
def test_jacobian_and_tangent_against_finite_differences(model, rng):
    N, k = 9, 2
    v = 1 + 0.2 * rng.uniform(-1, 1, N)
    lat = Lattice(N, 0.25, model, beta=0.1, v=v)
    y = 0.4 * rng.standard_normal(2 * N * (1 + k))
    np.testing.assert_allclose(lat.jacobian(y), central_jacobian(lat.rhs, y), atol=1e-8)
    x = y[:N]
    np.testing.assert_allclose(lat.force_jacobian(x, dense=True), central_jacobian(lat.force, x),
                               atol=1e-8)
    dx = rng.standard_normal((3, N))
    fd = np.array([(lat.force(x + 1e-6 * w) - lat.force(x - 1e-6 * w)) / 2e-6 for w in dx])
    np.testing.assert_allclose(lat.tangent_force(x, dx), fd, atol=1e-8)
    # rhs carries the variational equations
    ydot = lat.rhs(y.reshape(1 + k, 2 * N))
    assert ydot.shape == (1 + k, 2 * N)
    J = lat.force_jacobian(x, dense=True)
    for m in range(1, k + 1):
        np.testing.assert_allclose(ydot[m, N:], J @ y.reshape(1 + k, 2 * N)[m, :N], atol=1e-13)


def test_model2_is_hamiltonian(rng):
    N = 10
    lat = Lattice(N, 0.25, "hamiltonian", tau=20.0, seed=8)
    y = 0.3 * rng.standard_normal(2 * N)
    grad = np.array([(lat.energy(y + e) - lat.energy(y - e)) / 2e-6 for e in 1e-6 * np.eye(2 * N)])
    ydot = lat.rhs(y)
    np.testing.assert_allclose(ydot[N:], -grad[:N], atol=1e-8)   # p' = -dH/dx
    np.testing.assert_allclose(ydot[:N], grad[N:], atol=1e-8)    # x' = dH/dp = p/v


def test_unit_variability_models_agree(rng):
    x = 0.5 * rng.standard_normal(16)
    forces = [Lattice(16, 0.25, m, beta=0.05, v=np.ones(16)).force(x) for m in MODELS]
    np.testing.assert_array_equal(forces[0], forces[1])
    np.testing.assert_array_equal(forces[0], forces[2])


@pytest.mark.parametrize("N", [2, 7, 64, 255])
def test_mode_transform_is_the_orthogonal_matrix(N, rng):
    A = fputlab.mode_matrix(N)
    np.testing.assert_allclose(A @ A.T, np.eye(N), atol=1e-12)
    lat = Lattice(N)
    x = rng.standard_normal((3, N))
    np.testing.assert_allclose(lat.to_modes(x), x @ A.T, atol=1e-12)
    np.testing.assert_allclose(lat.from_modes(lat.to_modes(x)), x, atol=1e-12)


def test_mode_energies_sum_to_harmonic_energy(rng):
    N = 40
    lat = Lattice(N, 0.25, "nonlinear", tau=10, seed=1)
    y = 0.2 * rng.standard_normal(2 * N)
    X = np.concatenate([[0.0], y[:N], [0.0]])
    harmonic = 0.5 * np.sum(y[N:] ** 2) + 0.5 * np.sum(np.diff(X) ** 2)
    E = lat.mode_energies(y)
    assert E.shape == (N,)
    assert E.sum() == pytest.approx(harmonic, rel=1e-13)
    Q = fputlab.mode_matrix(N) @ y[:N]
    P = fputlab.mode_matrix(N) @ y[N:]
    np.testing.assert_allclose(E, 0.5 * (P**2 + fputlab.omega(N) ** 2 * Q**2), rtol=1e-10, atol=1e-16)


def test_mode_one_initial_condition():
    N = 64
    lat = Lattice(N)
    y = lat.mode_state(1, 2.5)
    Q = lat.to_modes(y[:N])
    assert Q[0] == pytest.approx(2.5 * np.sqrt((N + 1) / 2), rel=1e-14)
    np.testing.assert_allclose(Q[1:], 0.0, atol=1e-12)
    assert np.all(y[N:] == 0)
    assert lat.energy(lat.mode_state()) == pytest.approx(0.03795, abs=5e-6)  # paper, Sec. 2
    np.testing.assert_allclose(fputlab.omega(N), 2 * np.sin(np.arange(1, N + 1) * np.pi / (2 * (N + 1))))


def test_disorder_is_reproducible_and_has_the_paper_statistics():
    v1 = fputlab.draw_disorder(64, 10.0, seed=42)
    v2 = Lattice(64, 0.25, "nonlinear", tau=10.0, seed=42).v
    np.testing.assert_array_equal(v1, v2)
    assert not np.array_equal(v1, fputlab.draw_disorder(64, 10.0, seed=43))
    big = fputlab.draw_disorder(200_000, 30.0, seed=1)
    assert big.mean() == pytest.approx(1.0, abs=4 * 0.1 / np.sqrt(2e5))
    assert big.std() == pytest.approx(0.1, rel=0.01)          # sigma = tau/300
    trunc = fputlab.draw_disorder(100_000, 30.0, seed=1, kind="truncated")
    assert np.abs(trunc - 1).max() <= 0.3
    uni = fputlab.draw_disorder(100_000, 30.0, seed=1, kind="uniform")
    assert np.abs(uni - 1).max() <= 0.3 and uni.std() == pytest.approx(0.3 / np.sqrt(3), rel=0.01)
    # the same standard draws scale linearly with tau
    np.testing.assert_allclose(fputlab.draw_disorder(32, 20.0, 5) - 1,
                               2 * (fputlab.draw_disorder(32, 10.0, 5) - 1), rtol=1e-12)


def test_lattice_pickles_with_its_disorder():
    import pickle
    lat = Lattice(16, 0.25, "hamiltonian", tau=10, seed=9)
    back = pickle.loads(pickle.dumps(lat))
    np.testing.assert_array_equal(back.v, lat.v)
    assert (back.seed, back.model, back.tau) == (9, "hamiltonian", 10.0)


def paper_energy(x, p, a, b=0.0):
    """Eq. (Hamilt) written out with numpy: 1/2 sum p^2 + sum over the N + 1 bonds of
    V(d) = d^2/2 + a d^3/3 + b d^4/4, d_j = x_{j+1} - x_j, fixed ends x_0 = x_{N+1} = 0."""
    d = np.diff(np.concatenate([[0.0], x, [0.0]]))
    return 0.5 * np.sum(p**2) + np.sum(d**2 / 2 + a * d**3 / 3 + b * d**4 / 4)


@pytest.mark.parametrize("beta", [0.0, 0.3])
@pytest.mark.parametrize("N", [2, 13, 64])
def test_model3_energy_is_the_paper_hamiltonian(N, beta, rng):
    # model 3 (Eq. varnonlin) is not Hamiltonian; its "energy" is Eq. (Hamilt) evaluated on the
    # state, independent of the disorder v
    lat = Lattice(N, 0.25, "nonlinear", beta=beta, tau=20.0, seed=5)
    assert np.std(lat.v) > 0.01
    ys = 0.5 * rng.standard_normal((4, 2 * N))
    expected = np.array([paper_energy(y[:N], y[N:], 0.25, beta) for y in ys])
    np.testing.assert_allclose(lat.energy(ys), expected, rtol=1e-13, atol=1e-15)
    assert lat.energy(ys[0]) == pytest.approx(expected[0], rel=1e-13)
    # the same state on the homogeneous chain (model 1) has the same energy
    np.testing.assert_allclose(Lattice(N, 0.25, beta=beta).energy(ys), expected, rtol=1e-13)
    # closed form: only x_1 = s displaced, bonds d_0 = s, d_1 = -s (cubic terms cancel)
    for s in (0.7, -0.7):
        y = np.zeros(2 * N)
        y[0] = s
        assert lat.energy(y) == pytest.approx(s**2 + beta * s**4 / 2, rel=1e-14)
    # x_1 = s, x_2 = 2s, p_1 = 0.2: bonds s, s, -2s, energy 0.02 + 3 s^2 - 2 alpha s^3 + 4.5 beta s^4
    for s in (0.3, -0.3):
        y = np.zeros(2 * N)
        y[0], y[1], y[N] = s, 2 * s, 0.2
        assert lat.energy(y) == pytest.approx(0.02 + 3 * s**2 - 0.5 * s**3 + 4.5 * beta * s**4,
                                              rel=1e-14)


def test_with_deviation_vectors_are_the_chaos_start_vectors():
    lat = fputlab.Lattice(N=8, alpha=0.25)
    y0 = lat.mode_state(1)
    y = lat.with_deviation_vectors(y0, 3, seed=5)
    assert y.shape == (4, 16) and np.array_equal(y[0], y0)
    # independently: the same GSL stream through the disorder draw, v = 1 + (3/300) z
    z = (fputlab.draw_disorder(3 * 16, 3.0, 5) - 1.0) * 100.0
    w = z.reshape(3, 16)
    np.testing.assert_allclose(y[1:], w / np.linalg.norm(w, axis=1, keepdims=True), rtol=0,
                               atol=1e-13)
    # and lyapunov started from them is lyapunov with the same seed
    a = fputlab.chaos.lyapunov(lat, 20.0, n_dev=3, w0=y[1:])
    b = fputlab.chaos.lyapunov(lat, 20.0, n_dev=3, seed=5)
    np.testing.assert_allclose(a.mle, b.mle, rtol=1e-12)
    # the streaming integrator takes the (1+k, 2N) state as it is
    state = fputlab.Integrator(lat, y, method="yoshida4", dt=0.01).advance(1.0)
    assert state.shape == (4, 16)
    assert not np.array_equal(lat.with_deviation_vectors(y0, 3, seed=6)[1:], y[1:])


@pytest.mark.parametrize("kwargs, name", [({"k": 0}, "k"), ({"seed": -1}, "seed"),
                                          ({"y": np.zeros(5)}, "y"), ({"k": 1.5}, "k")])
def test_with_deviation_vectors_rejects_bad_input(kwargs, name):
    lat = fputlab.Lattice(N=8)
    args = {"y": lat.mode_state(1), "k": 2, **kwargs}
    with pytest.raises((ValueError, TypeError), match=name):
        lat.with_deviation_vectors(args.pop("y"), args.pop("k"), **args)
