"""The checks the study kinds share (fputlab.engine.normalise_disorder, grid_values,
complete_settings): a bad grid value or setting is a ValueError naming the parameter, the
same from every kind over (N, tau, seed); a good grid comes out as plain Python ints and
floats (written out here by hand); and the specs of the committed studies normalise to
themselves, with their stored key, so every stored study is still read and continued."""
import json
from pathlib import Path

import numpy as np
import pytest

from fputlab.engine import (KINDS, StudySpec, complete_settings, get_kind, grid_values,
                            normalise_disorder)

#: the kinds over disorder realisations and the settings each needs besides its defaults
DISORDER_KINDS = {"blowup": {}, "chaos": {}, "run": {"sample_every": 5.0}, "recurrence": {}}
GRID = {"N": [8, 16], "tau": [0.0, 20.0], "seed": [1, 2]}
STUDIES = Path(__file__).resolve().parents[2] / "studies"


def test_every_disorder_kind_has_the_dims_the_helper_checks():
    for kind in DISORDER_KINDS:
        assert get_kind(kind).dims == ("N", "tau", "seed")


@pytest.mark.parametrize("kind", sorted(DISORDER_KINDS))
@pytest.mark.parametrize("raw, expected", [
    ({"N": [8, 16], "tau": [0.0, 20.0], "seed": [1, 2]},
     {"N": [8, 16], "tau": [0.0, 20.0], "seed": [1, 2]}),
    # scalars become lists, numpy arrays and integral floats plain ints and floats
    ({"N": 8, "tau": 5, "seed": 3}, {"N": [8], "tau": [5.0], "seed": [3]}),
    ({"N": np.array([4, 8]), "tau": np.array([1.5]), "seed": np.arange(3)},
     {"N": [4, 8], "tau": [1.5], "seed": [0, 1, 2]}),
    ({"N": [8.0, 16.0], "tau": [2], "seed": [2**40]},
     {"N": [8, 16], "tau": [2.0], "seed": [2**40]}),
], ids=["lists", "scalars", "numpy", "integral floats"])
def test_a_good_grid_comes_out_as_plain_numbers_from_every_kind(kind, raw, expected):
    grid, _ = get_kind(kind).normalise(dict(raw), dict(DISORDER_KINDS[kind]))
    assert grid == expected
    assert [type(v) for d in ("N", "seed") for v in grid[d]] == \
        [int] * (len(expected["N"]) + len(expected["seed"]))
    assert all(type(v) is float for v in grid["tau"])
    defaults = {"model": "nonlinear"}
    assert normalise_disorder(dict(raw), {}, defaults, kind) == (expected, defaults)


@pytest.mark.parametrize("kind", sorted(DISORDER_KINDS))
@pytest.mark.parametrize("dim, values, name, words", [
    ("N", [1], "Ns", "finite and >= 2"),
    ("N", [8.5], "Ns", "must be integers"),
    ("N", [], "Ns", "must not be empty"),
    ("N", ["x"], "Ns", "must be numbers"),
    ("N", [8, 8], "Ns", "must not repeat"),
    ("tau", [-1.0], "tau", "finite and >= 0.0"),
    ("tau", [float("nan")], "tau", "finite and >= 0.0"),
    ("tau", [1.0, 1], "tau", "must not repeat"),
    ("tau", [[1, 2], [3]], "tau", "must be numbers"),
    ("seed", [-1], "seeds", "finite and >= 0"),
    ("seed", [1.5], "seeds", "must be integers"),
    ("seed", [2**64], "seeds", "out of range"),
])
def test_a_bad_grid_value_is_named_alike_by_every_kind(kind, dim, values, name, words):
    grid = {**GRID, dim: values}
    with pytest.raises(ValueError) as from_kind:
        get_kind(kind).normalise(dict(grid), dict(DISORDER_KINDS[kind]))
    text = str(from_kind.value)
    assert text.startswith(name + " ") and words in text
    with pytest.raises(ValueError) as from_helper:
        normalise_disorder(grid, {}, {"model": "nonlinear"}, kind)
    assert str(from_helper.value) == text


@pytest.mark.parametrize("kind, what", [("blowup", "blow-up"), ("chaos", "chaos"),
                                        ("run", "run"), ("recurrence", "recurrence")])
def test_an_unknown_setting_or_model_is_named(kind, what):
    k = get_kind(kind)
    with pytest.raises(ValueError, match=f"^colour, hue: not a setting of {what} studies "
                                         r"\(known: .*model"):
        k.normalise(dict(GRID), {**DISORDER_KINDS[kind], "colour": 1, "hue": 2})
    with pytest.raises(ValueError, match="^model 'bogus' is unknown "
                                         r"\(known: homogeneous, hamiltonian, nonlinear, toda\)"):
        k.normalise(dict(GRID), {**DISORDER_KINDS[kind], "model": "bogus"})
    # None is the default; the model is the kind's default unless given
    _, s = k.normalise(dict(GRID), {**DISORDER_KINDS[kind], "model": None})
    assert s["model"] == "nonlinear"
    _, s = k.normalise(dict(GRID), {**DISORDER_KINDS[kind], "model": "toda"})
    assert s["model"] == "toda"


def test_complete_settings_takes_the_defaults_and_refuses_what_it_does_not_know():
    defaults = {"a": 1, "b": None}
    assert complete_settings({"b": 2.5, "a": None}, defaults, "test") == {"a": 1, "b": 2.5}
    assert complete_settings({}, defaults, "test") == defaults
    with pytest.raises(ValueError, match=r"^c: not a setting of test studies \(known: a, b\)$"):
        complete_settings({"c": 0}, defaults, "test")


@pytest.mark.parametrize("values, kind, minimum, expected", [
    ([0.5, 2], float, 0.0, [0.5, 2.0]),
    (np.float32(0.25), float, 0.0, [0.25]),
    ([0, 3.0], int, 0, [0, 3]),
    # the largest 64-bit seed stays itself beside a float (no detour through float64)
    ([2**64 - 1, 4.0], int, 0, [2**64 - 1, 4]),
    (np.array([2**64 - 1], dtype=np.uint64), int, 0, [2**64 - 1]),
])
def test_grid_values_of_one_dimension(values, kind, minimum, expected):
    out = grid_values(values, "eps", kind, minimum)
    assert out == expected and all(type(v) is kind for v in out)


def _committed_specs():
    return sorted(p for p in STUDIES.rglob("study.json")
                  if "kind" in (doc := json.loads(p.read_text())) and doc["kind"] in KINDS
                  and "grid" in doc)


@pytest.mark.skipif(not STUDIES.is_dir(), reason="the committed studies are not here")
def test_the_committed_study_specs_normalise_to_themselves_with_their_key():
    """What a continued study is checked against: its stored spec normalised again must give
    the same grid, settings (values and types) and key, else the study could not go on."""
    paths = _committed_specs()
    kinds = set()
    for p in paths:
        doc = json.loads(p.read_text())
        k = get_kind(doc["kind"])
        grid, settings = k.normalise(dict(doc["grid"]), dict(doc["settings"]))
        assert {d: list(grid[d]) for d in k.dims} == doc["grid"], p
        assert json.dumps(settings, sort_keys=True) == json.dumps(doc["settings"],
                                                                  sort_keys=True), p
        assert StudySpec(doc["kind"], grid, settings, 1.0).key() == doc["key"], p
        kinds.add(doc["kind"])
    assert {"chaos", "recurrence", "thermalization"} <= kinds, kinds


def test_fraction_rows_count_the_started_tasks_per_n_and_tau():
    """Counted by hand: per (N, tau) the tasks with a finite t_reached, the hits among them
    (a hit that never started does not count), and the Wilson interval of that fraction."""
    xr = pytest.importorskip("xarray")
    from fputlab.engine import fraction_rows, wilson_interval
    reached = np.full((1, 2, 3), 10.0)
    reached[0, 1, 2] = np.nan                      # (N=8, tau=5): two of three started
    hit = np.array([[[True, False, False], [True, True, True]]])
    ds = xr.Dataset({"t_reached": (("N", "tau", "seed"), reached)},
                    coords={"N": [8], "tau": [0.0, 5.0], "seed": [1, 2, 3]})
    rows = fraction_rows(ds, hit, "blew_up", "probability")
    assert [list(r) for r in rows] == [["N", "tau", "n", "blew_up", "probability",
                                        "probability_low", "probability_high"]] * 2
    assert [(r["N"], r["tau"], r["n"], r["blew_up"], r["probability"]) for r in rows] == \
        [(8, 0.0, 3, 1, 1 / 3), (8, 5.0, 2, 2, 1.0)]
    assert (rows[1]["probability_low"], rows[1]["probability_high"]) == wilson_interval(2, 2)
    assert rows[1]["probability_high"] == 1.0
    reached[:] = np.nan                            # nothing started: NaN, not 0/0
    empty = fraction_rows(ds.assign(t_reached=(("N", "tau", "seed"), reached)), hit, "k", "f")
    assert empty[0]["n"] == 0 and np.isnan(empty[0]["f"]) and np.isnan(empty[0]["f_low"])


@pytest.mark.parametrize("kind", sorted(DISORDER_KINDS) + ["spectrum"])
def test_the_disorder_coordinates_are_labelled_alike_by_every_kind(kind):
    attrs = get_kind(kind).coord_attrs
    assert attrs["N"] == {"long_name": "number of particles", "units": "1"}
    assert attrs["tau"] == {"long_name": "variability of the disorder", "units": "percent"}
    assert attrs["seed"] == {"long_name": "disorder seed (realisation)", "units": "1"}
