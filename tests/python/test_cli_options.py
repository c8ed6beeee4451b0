"""The command line's options (issue 16 item 6, issue 14 item 5): every option shows its
default, one name per idea (old spellings hidden but working), the defaults are the Python
API's (read here from the signatures), ensemble records are named."""
import argparse
import inspect
import json

import h5py
import numpy as np
import pytest

import fputlab
from fputlab import blowup, chaos, ensemble
from fputlab.cli import build_parser, main, parse_args


def signature_defaults(fn):
    return {n: p.default for n, p in inspect.signature(fn).parameters.items()
            if p.default is not inspect.Parameter.empty}


LATTICE = signature_defaults(fputlab.Lattice.__init__)
INTEGRATE = signature_defaults(fputlab.integrate)
LYAPUNOV = signature_defaults(chaos.lyapunov)
BLOWUP_TIME = signature_defaults(blowup.blowup_time)
BLOWUP_SWEEP = signature_defaults(blowup.blowup_sweep)
FRACTION = signature_defaults(chaos.chaotic_fraction)
RUN_SWEEP = signature_defaults(ensemble.run_sweep)


def subparsers():
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices


# ---- --help --------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", [n for n in subparsers() if n != "demo"])
def test_every_option_shows_its_default_in_help(name, capsys):
    sp = subparsers()[name]
    with pytest.raises(SystemExit) as e:
        main([name, "--help"])
    assert e.value.code == 0
    assert "usage: fputlab" in capsys.readouterr().out
    for action in sp._actions:
        if action.dest == "help" or action.help == argparse.SUPPRESS:
            continue
        fmt = sp._get_formatter()             # the option's own entry, as --help shows it
        fmt.add_argument(action)
        entry = " ".join(fmt.format_help().split())
        assert "default" in entry, (name, entry)


def test_demo_options_show_their_defaults(capsys):
    with pytest.raises(SystemExit):
        main(["demo", "--help"])
    lines = [ln for ln in capsys.readouterr().out.splitlines() if ln.strip().startswith("--")]
    assert {ln.split()[0] for ln in lines} >= {"--out", "--N", "--alpha", "--t-end", "--dt"}
    for ln in lines:
        assert "default" in ln, ln


# ---- one name per idea, old spellings hidden and working -----------------------------------------

ALIASES = [  # (subcommand, old argv, new argv, dest)
    ("simulate", ["--t-max", "5"], ["--t-end", "5"], "t_end"),
    ("chaos", ["--t-max", "5"], ["--t-end", "5"], "t_end"),
    ("chaos", ["--Ns", "4", "8"], ["--N", "4", "8"], "N"),
    ("blowup", ["--t-max", "5", "--tau", "3"], ["--t-end", "5", "--tau", "3"], "t_end"),
    ("blowup", ["--taus", "3", "4"], ["--tau", "3", "4"], "tau"),
    ("sweep", ["--t-max", "5"], ["--t-end", "5"], "t_end"),
    ("sweep", ["--Ns", "4", "8"], ["--N", "4", "8"], "N"),
    ("sweep", ["--taus", "3", "4"], ["--tau", "3", "4"], "tau"),
    ("sweep", ["--first-seed", "7"], ["--seed", "7"], "seed"),
    ("coefficients", ["--taus", "3", "4"], ["--tau", "3", "4"], "tau"),
    ("tauc", ["--R", "7"], ["--realisations", "7"], "realisations"),
    ("tauc", ["--first-seed", "7"], ["--seed", "7"], "seed"),
    ("figures", ["--out", "some/dir"], ["--out-dir", "some/dir"], "out_dir"),
]


@pytest.mark.parametrize("cmd, old, new, dest", ALIASES, ids=lambda x: str(x))
def test_old_spellings_still_work_hidden_and_deprecated(cmd, old, new, dest, capsys):
    a_new = parse_args([cmd, *new])
    assert capsys.readouterr().err == ""
    a_old = parse_args([cmd, *old])
    assert getattr(a_old, dest) == getattr(a_new, dest)
    assert vars(a_old) == vars(a_new)
    err = capsys.readouterr().err
    assert f"{old[0]} is deprecated; use {new[0]}" in err and err.count("\n") == 1
    helptext = subparsers()[cmd].format_help()
    assert f"{old[0]} " not in helptext.replace(f"{old[0]}-", "") and new[0] in helptext


def test_time_size_and_tau_options_have_one_name_everywhere():
    """The final time is --t-end, sizes --N, variabilities --tau, realisations --realisations,
    seeds --seed in every subcommand that has the idea; --out is a file, --out-dir a folder."""
    seen = {}
    for name, sp in subparsers().items():
        for action in sp._actions:
            if action.help != argparse.SUPPRESS:
                for opt in action.option_strings:
                    seen.setdefault(opt, set()).add(name)
    for old in ("--t-max", "--Ns", "--taus", "--R", "--first-seed"):
        assert old not in seen, (old, seen.get(old))
    assert seen["--t-end"] >= {"simulate", "chaos", "blowup", "sweep", "figures"}
    assert seen["--realisations"] >= {"chaos", "blowup", "sweep", "tauc"}
    assert "figures" not in seen["--out"] and seen["--out-dir"] == {"figures"}


def test_figures_out_dir_is_used(tmp_path, capsys):
    assert main(["figures", "--out-dir", str(tmp_path / "f"), "--only", "7"]) == 0
    assert (tmp_path / "f" / "fig07_bifurcation.png").stat().st_size > 10_000
    assert main(["figures", "--out", str(tmp_path / "g"), "--only", "7"]) == 0   # deprecated
    assert (tmp_path / "g" / "fig07_bifurcation.png").is_file()
    assert "--out is deprecated" in capsys.readouterr().err


# ---- defaults agree with Python ------------------------------------------------------------------

def test_single_lattice_commands_default_to_Lattice():
    for argv, fn in ((["simulate"], INTEGRATE), (["chaos"], LYAPUNOV)):
        a = parse_args(argv)
        assert (a.N, a.alpha, a.model, a.tau, a.beta, a.disorder) == (
            LATTICE["N"], LATTICE["alpha"], LATTICE["model"], LATTICE["tau"], LATTICE["beta"],
            LATTICE["disorder"]), argv
        assert (a.method, a.dt) == (fn["method"], fn["dt"]), argv
        assert a.model == "homogeneous" and a.tau == 0.0
    assert parse_args(["chaos"]).t_end == FRACTION["t_end"]


def test_blowup_defaults_are_blowup_sweeps():
    one = parse_args(["blowup", "--tau", "20"])
    assert not one.sweep and one.tau == 20.0 and one.realisations == 1
    assert (one.model, one.alpha, one.t_end, one.method) == (
        BLOWUP_SWEEP["model"], BLOWUP_SWEEP["alpha"], BLOWUP_SWEEP["t_end"],
        BLOWUP_SWEEP["method"])
    assert one.method == BLOWUP_TIME["method"] and one.dt == BLOWUP_TIME["dt"]
    assert [one.N] == list(BLOWUP_SWEEP["Ns"]) and one.N == LATTICE["N"]
    many = parse_args(["blowup", "--tau", "0", "20"])
    assert many.sweep and many.realisations == BLOWUP_SWEEP["realisations"]
    assert many.N == list(BLOWUP_SWEEP["Ns"]) and many.seed == BLOWUP_SWEEP["first_seed"]
    assert (many.model, many.alpha, many.t_end, many.method, many.dt) == (
        BLOWUP_SWEEP["model"], BLOWUP_SWEEP["alpha"], BLOWUP_SWEEP["t_end"],
        BLOWUP_SWEEP["method"], None)
    assert parse_args(["blowup", "--tau", "20", "--realisations", "3"]).sweep


def test_chaos_ensemble_defaults_are_chaotic_fractions():
    for argv in (["chaos", "--realisations", "5"], ["chaos", "--N", "4", "8"]):
        a = parse_args(argv)
        assert a.fraction
        assert (a.model, a.tau, a.alpha, a.t_end, a.method, a.seed) == (
            FRACTION["model"], FRACTION["tau"], FRACTION["alpha"], FRACTION["t_end"],
            FRACTION["method"], FRACTION["first_seed"])
        assert a.dt is None                      # chaotic_fraction's own: srkn14a6 at dt = 0.5
    assert parse_args(["chaos", "--realisations", "5"]).N == list(FRACTION["Ns"])
    assert parse_args(["chaos", "--N", "4", "8"]).realisations == FRACTION["realisations"]


@pytest.mark.parametrize("kind, fn", [("blowup", BLOWUP_SWEEP), ("chaos", FRACTION)])
def test_sweep_defaults_are_run_sweeps(kind, fn):
    a = parse_args(["sweep", "--kind", kind])
    assert (a.model, a.alpha, a.seed, a.method) == (
        RUN_SWEEP["model"], RUN_SWEEP["alpha"], RUN_SWEEP["first_seed"], RUN_SWEEP["method"])
    assert a.N == list(fn["Ns"]) and a.realisations == fn["realisations"]
    assert a.t_end == fn["t_end"]
    if kind == "chaos":
        assert a.tau == [FRACTION["tau"]]


def test_forms_that_need_disorder_say_so(capsys):
    assert main(["blowup"]) == 2
    err = capsys.readouterr().err
    assert "--tau is required" in err and err.count("\n") == 1
    assert main(["chaos", "--tau", "10", "--t-end", "1"]) == 2     # one orbit: homogeneous
    assert "homogeneous model has no disorder" in capsys.readouterr().err
    assert main(["blowup", "--tau", "20", "--N", "8", "--t-end", "1", "--model", "homogeneous"]) == 2
    assert "homogeneous model has no disorder" in capsys.readouterr().err
    for argv in (["blowup", "--tau", "20"], ["chaos"]):          # one run: no cluster
        assert main(argv + ["--t-end", "1", "--scheduler", "tcp://127.0.0.1:9"]) == 2
        assert "--scheduler: only for" in capsys.readouterr().err


def test_simulate_without_options_runs_Lattice(tmp_path, capsys):
    assert main(["simulate", "--N", "8", "--t-end", "20", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    ref = fputlab.Lattice(8).integrate(20.0, sample_every=0.02)
    assert out["lattice"] == repr(fputlab.Lattice(8)) and out["samples"] == ref.t.size
    assert out["max_relative_energy_error"] == pytest.approx(ref.relative_energy_error.max(),
                                                             rel=1e-9, abs=1e-15)


# ---- named records -------------------------------------------------------------------------------

def test_blowup_sweep_records_are_named_and_keep_their_file_layout(tmp_path, capsys):
    path = tmp_path / "b.h5"
    assert main(["blowup", "--tau", "0", "40", "--N", "8", "--realisations", "2", "--t-end",
                 "300", "--workers", "1", "--out", str(path), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    with h5py.File(path) as f:
        rows = f["records"][...]
    assert rows.dtype == float and rows.shape == (4, 6)
    for row, rec in zip(rows, summary["records"]):
        tau, N, seed, blew_up, time, tau_c = row
        assert rec["tau"] == tau and rec["N"] == N == 8 and rec["seed"] == seed
        assert rec["blew_up"] == bool(blew_up)
        # each record against its own run
        ref = blowup.blowup_time(fputlab.Lattice(8, 0.25, "nonlinear", tau=tau, seed=int(seed)),
                                 300.0)
        assert bool(blew_up) == ref.blew_up
        assert (np.isnan(time) and np.isnan(ref.time)) or time == ref.time
        assert tau_c == pytest.approx(blowup.realisation_tau_c(8, int(seed)), nan_ok=True)
    assert [(r["tau"], r["seed"]) for r in summary["records"]] == [(0, 1), (0, 2), (40, 1), (40, 2)]


def test_blowup_record_fields_and_arrays():
    out = blowup.blowup_sweep([0.0, 40.0], Ns=[8], realisations=1, t_end=200.0, workers=1)
    recs = out["records"]
    assert all(isinstance(r, blowup.BlowupRecord) for r in recs)
    assert blowup.BlowupRecord._fields == ("tau", "N", "seed", "blew_up", "time", "tau_c")
    assert [r.tau for r in recs] == [0.0, 40.0] and all(r.N == 8 and r.seed == 1 for r in recs)
    flat = np.array(recs, dtype=float)
    assert flat.shape == (2, 6) and flat[1, 0] == 40.0
    arr = blowup.BlowupRecord.to_array(recs)
    assert arr.dtype.names == blowup.BlowupRecord._fields
    assert list(arr["tau"]) == [0.0, 40.0] and arr["N"].dtype.kind == "i"
    assert list(arr["blew_up"]) == [r.blew_up for r in recs]
    assert out["probability"][:, 0].tolist() == [float(r.blew_up) for r in recs]


def test_chaos_fraction_file_is_the_labelled_result(tmp_path, capsys):
    xr = pytest.importorskip("xarray")
    path = tmp_path / "c.nc"
    assert main(["chaos", "--realisations", "2", "--N", "4", "--t-end", "200", "--samples",
                 "10", "--workers", "1", "--out", str(path), "--json"]) == 0
    capsys.readouterr()
    with xr.open_dataset(path) as ds:
        assert ds["orbit_class"].dims == ("N", "tau", "seed")
        assert ds["mle_t"].dims == ("N", "tau", "seed", "sample")
        assert ds["tau"].attrs["units"] == "percent" and "long_name" in ds["mle"].attrs
        assert list(ds["seed"].values) == [1, 2] and list(ds["tau"].values) == [10.0]
        for seed in (1, 2):
            o = ds.sel(N=4, tau=10.0, seed=seed)
            lat = fputlab.Lattice(4, 0.25, "nonlinear", tau=10.0, seed=seed)
            ref = chaos.lyapunov(lat, 200.0, method=chaos.ENSEMBLE_METHOD, dt=chaos.ENSEMBLE_DT,
                                 n_samples=10, stop_when_chaotic=True)
            assert float(o["t_final"]) == ref.t_final
            assert float(o["mle"]) == pytest.approx(ref.mle_final, rel=1e-12)
            assert float(o["sali"]) == pytest.approx(float(ref.sali[-1]), rel=1e-12)
            assert str(o["orbit_class"].values) == ref.classify()


def test_orbit_records_are_named():
    rec = chaos._one_realisation((4, 10.0, 3, "nonlinear", 0.25, 50.0, "yoshida4",
                                  {"n_samples": 5}))
    assert isinstance(rec, chaos.OrbitRecord) and (rec.N, rec.seed) == (4, 3)
    ref = chaos.lyapunov(fputlab.Lattice(4, 0.25, "nonlinear", tau=10.0, seed=3), 50.0,
                         n_samples=5)
    assert rec.result.mle.tobytes() == ref.mle.tobytes()
