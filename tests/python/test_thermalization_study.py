"""The thermalization study kind and its driver: one orbit against an independent integration
(scipy's DOP853 and the explicit sine-mode matrix), bit-for-bit continuation to a larger t_end
against one straight run, the labelled dataset, T_eq of a synthetic ensemble with a known
crossing (closed-form entropy), the migration of a study of the old driver (numbers
unchanged), growth of a study and the CLI's one-line errors."""
import json
import math
from dataclasses import replace

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import solve_ivp

from fputlab import initial_states as ist
from fputlab.cli import main
from fputlab.engine import KINDS, run_study
from fputlab.integrate import Integrator
from fputlab.modes import mode_matrix
from fputlab.thermalization import equipartition_time, first_crossing
from fputlab.thermalization_study import (STUDIES, ThermalizationStudy, _point_result,
                                          check_spec, migrate_legacy, sample_times)

TINY = STUDIES["tiny"]
SETTINGS = TINY.settings(0)


def _fput_rhs(alpha, N):
    def f(t, y):
        x, v = y[:N], y[N:]
        r = np.diff(np.concatenate([[0.0], x, [0.0]]))
        g = r + alpha * r**2
        return np.concatenate([v, g[1:] - g[:-1]])
    return f


def test_kind_is_registered_and_one_orbit_matches_an_independent_integration():
    assert KINDS["thermalization"].endswith(":THERMALIZATION_KIND")
    # the default window (two periods of the slowest mode), computed independently below
    ds = run_study("thermalization", {"eps": [0.2], "orbit": [1]}, {**SETTINGS, "window": None},
                   40.0, workers=1).to_xarray()
    from fputlab import Lattice
    lat = Lattice(TINY.N, TINY.alpha)
    y0 = ist.random_phases(lat, energy=TINY.energy(0.2), modes=TINY.band,
                           seed=TINY.seed * 1_000_003 + 1)
    N = TINY.N
    w = 2 * 2 * math.pi / (2 * math.sin(math.pi / (N + 1) / 2))
    back = w * (np.arange(TINY.sub_samples) + 1.0) / TINY.sub_samples
    A = mode_matrix(N)
    om = 2 * np.sin(np.arange(1, N + 1) * np.pi / (2 * (N + 1)))
    t = ds["t"].values
    assert t[0] == 0.0 and t[-1] <= 40.0
    sol = solve_ivp(_fput_rhs(TINY.alpha, N), (0, t[-1]), y0, method="DOP853",
                    rtol=1e-12, atol=1e-14, dense_output=True)
    e_run = ds["wave_energy"].values[0, 0]
    for ti, e in zip(t, e_run):
        ys = sol.sol(np.maximum(ti - w + back, 0.0))
        Q, P = A @ ys[:N], A @ ys[N:]
        ref = (0.5 * (P**2 + (om[:, None] * Q) ** 2)).mean(axis=1)
        np.testing.assert_allclose(e, ref, rtol=1e-6, atol=1e-9 * ref.sum())
    E0 = float(ds["E0"].values[0, 0])
    assert E0 == pytest.approx(TINY.energy(0.2), rel=1e-12)
    assert np.max(np.abs(ds["energy_max"].values / E0 - 1)) < 1e-8


def test_larger_t_end_continues_bit_for_bit_and_the_dataset_is_labelled(tmp_path):
    grid = {"eps": [0.2, 0.15], "orbit": [0, 1, 2]}
    straight = run_study("thermalization", grid, SETTINGS, 700.0, workers=1).to_xarray()
    for t_end in (37.0, 130.5, 333.3, 700.0):          # cuts inside sample windows
        pieces = run_study("thermalization", grid, SETTINGS, t_end, work_dir=tmp_path / "w",
                           workers=1)
    cont = pieces.to_xarray()
    for name in ("wave_energy", "entropy", "n_eff", "energy_max", "energy_min", "steps", "E0"):
        np.testing.assert_array_equal(straight[name].values, cont[name].values)
    assert dict(cont.sizes) == {"eps": 2, "orbit": 3, "sample": len(sample_times(
        json.loads(cont.attrs["settings"]), 700.0)), "mode": TINY.N}
    assert cont.attrs["kind"] == "thermalization" and cont.attrs["t_end"] == 700.0
    np.testing.assert_array_equal(cont["t"].values, sample_times(SETTINGS, 700.0))
    assert cont["wave_energy"].attrs["long_name"].startswith("harmonic wave energy")
    assert list(cont["mode"].values) == list(range(1, TINY.N + 1))
    # the per-orbit entropy and n_eff are those of the orbit's spectrum
    e = cont["wave_energy"].values
    f = e.shape[-1] * e / e.sum(-1, keepdims=True)
    from scipy.special import xlogy                  # 0 ln 0 = 0 (the empty modes at t = 0)
    np.testing.assert_allclose(cont["entropy"].values, xlogy(f, f).sum(-1), rtol=1e-12)
    np.testing.assert_allclose(cont["n_eff"].values, np.exp(-cont["entropy"].values / TINY.N),
                               rtol=1e-14)
    # the merged netCDF on disk is the same dataset
    on_disk = xr.open_dataset(tmp_path / "w" / "result.nc", engine="h5netcdf")
    np.testing.assert_array_equal(on_disk["wave_energy"].values, e)


def _closed_form_entropy(M, A):
    """S of the spectrum (1 + A, 1, ..., 1) (M modes) in closed form."""
    f1 = M * (1 + A) / (M + A)
    f = M / (M + A)
    return f1 * math.log(f1) + (M - 1) * f * math.log(f)


def test_equipartition_time_of_a_synthetic_ensemble_with_a_known_crossing():
    M, S = 7, 30
    t = np.concatenate([[0.0], np.geomspace(1, 1e4, S - 1)])
    A = 40.0 * np.exp(-t / 300.0)                 # the excess of mode 1 decays
    spec = np.ones((S, M))
    spec[:, 0] += A
    R = 5
    e = np.broadcast_to(spec, (R, S, M)).copy()
    e[3, 10:] = np.nan                           # a failed orbit leaves the ensemble
    failed = np.zeros(R, bool)
    failed[3] = True
    reached = np.full(R, 1e4)
    reached[4] = np.nan                           # an orbit not started
    e[4] = np.nan
    ds = xr.Dataset({"wave_energy": (("orbit", "sample", "mode"), e),
                     "failed": (("orbit",), failed), "t_reached": (("orbit",), reached),
                     "E0": (("orbit",), np.full(R, float(M + 40))),
                     "energy_max": (("orbit", "sample"), np.full((R, S), M + 40.0)),
                     "energy_min": (("orbit", "sample"), np.full((R, S), M + 40.0))},
                    coords={"t": ("sample", t)})
    row = _point_result(ds, threshold=0.1, n_boot=50, seed=1)
    eta = np.array([_closed_form_entropy(M, a) for a in A]) / _closed_form_entropy(M, A[0])
    expected = first_crossing(t, eta, 0.1)
    assert 300 < expected < 3000
    assert row["t_eq"] == pytest.approx(expected, rel=1e-9)
    assert row["orbits"] == 3 and row["failed"] == 1
    assert row["interval"][0] == pytest.approx(expected, rel=1e-9)   # identical orbits
    assert row["interval"][1] == pytest.approx(expected, rel=1e-9)
    assert row["energy_error"] == 0.0


def _write_legacy(old, spec: dict, data: dict):
    """A study of the driver before the engine: study.json and p<point>/o<orbit>_s<seg>.npz."""
    old.mkdir()
    (old / "study.json").write_text(json.dumps({"format": "fputlab-thermalization-study-1",
                                                **spec}))
    for (p, o, s), arrays in data.items():
        (old / f"p{p:02d}").mkdir(exist_ok=True)
        np.savez(old / f"p{p:02d}" / f"o{o:04d}_s{s:02d}.npz", **arrays)


def test_migration_keeps_the_numbers_and_the_orbits_continue(tmp_path):
    N, orbits, eps = 8, 4, (0.2, 0.15)
    spec = {"label": "legacy", "model": "homogeneous", "boundary": "fixed", "N": N,
            "alpha": 1.0, "beta": 0.0, "tau": 0.0, "eps_kind": "alpha", "eps": list(eps),
            "band": [1], "orbits": orbits, "seed": 7, "method": "srkn14a6", "dt": 0.2,
            "t_first": 50.0, "t_max": 100.0, "samples_per_segment": 4, "sub_samples": 4,
            "window": None, "threshold": 0.3, "n_boot": 60, "earlier_t_max": []}
    rng = np.random.default_rng(5)
    data, raw = {}, {}
    from fputlab import Lattice
    lat = Lattice(N, 1.0)
    seg_t = [np.array([0.0, 6.25, 12.5, 25.0, 50.0]), np.geomspace(50, 100, 5)[1:]]
    for p, ep in enumerate(eps):
        E = N * ep**2
        for o in range(orbits):
            y0 = ist.random_phases(lat, energy=E, modes=[1], seed=7 * 1_000_003 + 1009 * p + o)
            it = Integrator(lat, y0, method="srkn14a6", dt=0.2)
            es = []
            for s, ts in enumerate(seg_t):
                st = it.advance(ts[-1])                  # the segment's end state
                e = rng.exponential(size=(ts.size, N))   # spectra: any numbers migrate as such
                e[0] *= 0.0 if (s == 0) else 1.0
                if s == 0:
                    e[0, 0] = 1.0                        # one mode at t = 0
                if p == 0:
                    e[:, 0] += 50.0                      # eps = 0.2 never crosses: it goes on
                es.append(e)
                data[(p, o, s)] = {"t": ts, "e": e, "energy": np.full(ts.size, E),
                                   "energy_min": np.full(ts.size, E), "E0": np.float64(E),
                                   "steps": np.int64(it.steps), "t_end": np.float64(it.t),
                                   "state": it.state, "failed": np.bool_(False),
                                   "message": np.array(""), "wall": np.float64(0.5),
                                   "cpu": np.float64(0.25)}
            raw[(p, o)] = np.concatenate(es)
    _write_legacy(tmp_path / "old", spec, data)
    study = migrate_legacy(tmp_path / "old", tmp_path / "new")
    res = study.results()
    t = np.concatenate(seg_t)
    boots = []
    for p, row in enumerate(res["points"]):
        e = np.stack([raw[(p, o)] for o in range(orbits)])
        ref = equipartition_time(t, e, threshold=0.3, n_boot=60, seed=7 + p)
        assert row["t_eq"] == ref["t_eq"] or (math.isnan(row["t_eq"]) and
                                              math.isnan(ref["t_eq"]))
        np.testing.assert_array_equal(row["boot"], ref["boot"])
        np.testing.assert_array_equal(row["eta"], ref["eta"])
        assert row["cpu"] == pytest.approx(orbits * 0.5) and row["orbits"] == orbits
        boots.append(ref)
    assert math.isnan(res["points"][0]["t_eq"]) and math.isfinite(res["points"][1]["t_eq"])
    with pytest.raises(ValueError, match="exists"):
        migrate_legacy(tmp_path / "old", tmp_path / "new")
    # a larger t_max continues every orbit from its migrated state: the samples so far stay,
    # and the orbit's state is that of one straight integration
    grown = ThermalizationStudy(tmp_path / "new", replace(study.spec, t_max=200.0))
    grown.run(points=[0])
    ds = grown.point_dataset(0)
    assert float(ds["t"].values[-1]) == pytest.approx(200.0)
    np.testing.assert_array_equal(ds["wave_energy"].values[0, 0, :t.size], raw[(0, 0)])
    from fputlab.io.store import StudyStore
    store = StudyStore.reader(tmp_path / "new" / "p00_eps0.2" / "b00")
    rep = store.read_task("eps0.2_orbit0", {"eps": 0.2, "orbit": 0})
    y0 = ist.random_phases(lat, energy=N * 0.2**2, modes=[1], seed=7 * 1_000_003)
    it = Integrator(lat, y0, method="srkn14a6", dt=0.2)
    it.advance(float(ds["t"].values[-1]))
    assert int(rep["state"]["steps"]) == it.steps
    np.testing.assert_array_equal(rep["state"]["y"], it.state[0])


def test_driver_stops_at_the_crossing_grows_and_refuses_other_studies(tmp_path):
    study = ThermalizationStudy(tmp_path / "s", TINY)
    assert study.run() is True
    res = study.results()
    for row in res["points"]:
        assert math.isfinite(row["t_eq"]) and row["t_reached"] < TINY.t_max
        assert row["orbits"] == TINY.orbits and row["cpu"] > 0
    # the T_eq reported is the one of the merged labelled result
    ds = study.dataset()
    assert set(ds.sizes) == {"eps", "orbit", "sample", "mode"}
    e = ds["wave_energy"].sel(eps=0.2).values
    t = ds["t_sample"].sel(eps=0.2).values
    n = int(np.sum(np.all(np.isfinite(e), axis=(0, 2))))
    ref = equipartition_time(t[:n], e[:, :n], threshold=TINY.threshold, n_boot=TINY.n_boot,
                             seed=TINY.seed)
    assert res["points"][0]["t_eq"] == ref["t_eq"]
    # more orbits: a new block, caught up to the time the others reached
    bigger = ThermalizationStudy(tmp_path / "s", replace(TINY, orbits=8))
    bigger.run(points=[0])
    assert bigger.results()["points"][0]["orbits"] == 8
    assert bigger.results()["points"][1]["orbits"] == 4
    with pytest.raises(ValueError, match="different study"):
        ThermalizationStudy(tmp_path / "s", replace(TINY, dt=0.1))
    with pytest.raises(ValueError, match="different study"):
        ThermalizationStudy(tmp_path / "s", replace(TINY, eps=(0.1,) + TINY.eps))
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "x.txt").write_text("mine")
    with pytest.raises(ValueError, match="not a study directory"):
        ThermalizationStudy(tmp_path / "other", TINY)
    with pytest.raises(ValueError, match="holds no study"):
        ThermalizationStudy(tmp_path / "empty")


def test_fits_use_only_the_points_the_averaging_window_resolves(tmp_path, monkeypatch):
    """The fit rule: a point enters a fit only if T_eq >= MIN_WINDOWS averaging windows; the
    window is two periods of the slowest mode by default (closed form), or the spec's."""
    from fputlab import thermalization_study as ts
    from fputlab.thermalization import fit_power_law
    # the default: fixed chain, N = 8: k1 = pi/9
    assert ts.window_of(replace(TINY, window=None)) == pytest.approx(
        2 * 2 * math.pi / (2 * math.sin(math.pi / 18)), rel=1e-12)
    w = ts.window_of(TINY)
    assert w == TINY.window
    assert ts.window_of(STUDIES["beta"]) == pytest.approx(2 * math.pi / math.sin(math.pi / 32))
    assert ts.window_of(STUDIES["beta-overlap"]) == 16.0
    assert ts.resolved(ts.MIN_WINDOWS * w, w) and not ts.resolved(ts.MIN_WINDOWS * w * 0.999, w)
    assert not ts.resolved(math.nan, w)
    study = ThermalizationStudy(tmp_path / "s", TINY)
    study.run()
    eps = [p["eps"] for p in study.results()["points"]]
    t = [p["t_eq"] for p in study.results()["points"]]
    assert all(map(math.isfinite, t)) and t[0] != t[1]
    # a rule between the two T_eq: only the later crossing counts, one point fits nothing
    monkeypatch.setattr(ts, "MIN_WINDOWS", math.sqrt(t[0] * t[1]) / w)
    res = study.results()
    assert [p["resolved"] for p in res["points"]] == [x > min(t) for x in t]
    assert res["fit"] is None and res["min_windows"] == ts.MIN_WINDOWS
    # a rule below both: both fitted, the exponent of two points in closed form
    monkeypatch.setattr(ts, "MIN_WINDOWS", 0.5 * min(t) / w)
    res = study.results()
    assert all(p["resolved"] for p in res["points"])
    a = -math.log(t[1] / t[0]) / math.log(eps[1] / eps[0])
    assert res["fit"]["exponent"] == pytest.approx(a, rel=1e-9)
    assert res["fit"]["exponent"] == pytest.approx(fit_power_law(eps, t)["exponent"])


@pytest.mark.parametrize("change, word", [
    (dict(eps=()), "eps"), (dict(eps=(-0.1,)), "eps"), (dict(orbits=1), "orbits"),
    (dict(orbits=6), "multiple"), (dict(t_max=1.0), "t_max"), (dict(threshold=1.5), "threshold"),
    (dict(method="dop853"), "adaptive"), (dict(eps_kind="gamma"), "eps_kind"),
    (dict(eps_kind="beta"), "beta"), (dict(model="quartic"), "model"),
])
def test_bad_specs_are_refused(change, word):
    with pytest.raises((ValueError, TypeError), match=word):
        check_spec(replace(TINY, **change))


def test_bad_grid_and_settings_of_the_kind_are_refused():
    with pytest.raises(ValueError, match="eps"):
        run_study("thermalization", {"eps": [0.0], "orbit": [0]}, SETTINGS, 10.0)
    with pytest.raises(ValueError, match="not a setting"):
        run_study("thermalization", {"eps": [0.1], "orbit": [0]}, {"gamma": 1.0}, 10.0)
    with pytest.raises(ValueError, match="orbit"):
        run_study("thermalization", {"eps": [0.1], "orbit": [5000]}, SETTINGS, 10.0)


def test_cli_runs_reports_and_refuses(tmp_path, capsys):
    work = str(tmp_path / "w")
    png = str(tmp_path / "teq.png")
    assert main(["thermalization", "tiny", "--work-dir", work, "--figure", png]) == 0
    out = capsys.readouterr().out
    assert "fit: T_eq ~ eps^-a" in out and "wrote" in out
    assert main(["thermalization", "tiny", "--work-dir", work, "--figure", png]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "exists" in err
    assert main(["thermalization", "tiny", "--work-dir", work, "--orbits", "3"]) == 2
    assert "multiple" in capsys.readouterr().err
    assert main(["thermalization", "tiny", "--work-dir", work, "--only-eps", "0.3"]) == 2
    assert "--only-eps" in capsys.readouterr().err
    assert main(["thermalization", "tiny", "--work-dir", work, "--report-only"]) == 0
    assert main(["thermalization", "tiny", "--work-dir", str(tmp_path / "x"),
                 "--t-until", "-1"]) == 2
    assert "--t-until" in capsys.readouterr().err


def test_example_draws_from_the_stores(tmp_path):
    import subprocess
    import sys
    from pathlib import Path
    study = ThermalizationStudy(tmp_path / "tiny", TINY)
    study.run()
    script = Path(__file__).resolve().parents[2] / "examples" / "thermalization_teq.py"
    out = subprocess.run([sys.executable, str(script), "--studies-dir", str(tmp_path),
                          "--studies", "tiny", "--out", str(tmp_path / "t.png")],
                         capture_output=True, text=True, check=True, timeout=120).stdout
    fit = study.results()["fit"]
    assert f"tiny: T_eq ~ eps^-{fit['exponent']:.2f}" in out
    assert (tmp_path / "t.png").stat().st_size > 10_000


def test_readme_and_docs_tables_are_the_stored_studies():
    """The exponent tables of the README and docs/thermalization.md are generated from the
    committed studies (studies/thermalization/<study>/, engine stores): their text equals the
    table computed from the stores now."""
    import re
    from pathlib import Path
    from fputlab.figures_thermalization import TABLE_ROWS, markdown_table
    root = Path(__file__).resolve().parents[2]
    res = {label: ThermalizationStudy(root / "studies" / "thermalization" / label).results()
           for label in {row[0] for row in TABLE_ROWS}}
    table = markdown_table(res)
    for page in ("README.md", "docs/thermalization.md"):
        blocks = re.findall(r"<!-- thermalization-table -->\n(.*?)\n<!-- end -->",
                            (root / page).read_text(), re.S)
        assert blocks, f"{page} has no generated thermalization table"
        for block in blocks:
            assert block.strip() == table
