"""The open questions of the paper (issue 25): outcome statistics against closed forms, the
recurrence kind against the physics it measures, and the README's numbers against the stored
study they come from."""
import math
import re
from pathlib import Path

import numpy as np
import pytest

from fputlab.chaos.outcomes import (OrbitOutcomes, cumulative_incidence, monotonicity,
                                    outcome_table)
from fputlab.engine import run_study, wilson_interval
from fputlab.recurrence import recurrence_quality, recurrence_time

ROOT = Path(__file__).resolve().parents[2]
STUDIES = ROOT / "studies" / "open_questions"


def test_wilson_interval_closed_forms():
    z = 1.959963984540054
    lo, hi = wilson_interval(0, 10)             # k = 0: [0, z^2 / (n + z^2)]
    assert lo == 0.0 and hi == pytest.approx(z * z / (10 + z * z), rel=1e-12)
    lo, hi = wilson_interval(10, 10)            # k = n: the mirror image
    assert hi == pytest.approx(1.0, abs=1e-15) and lo == pytest.approx(10 / (10 + z * z), rel=1e-12)
    lo, hi = wilson_interval(50, 100)           # symmetric about 1/2
    assert lo + hi == pytest.approx(1.0, abs=1e-12) and hi - lo == pytest.approx(0.19, abs=0.005)
    assert all(math.isnan(v) for v in wilson_interval(0, 0))


def _synthetic():
    # N = 8: 10 orbits, 4 chaotic by t = 100, 1 blown up at 50; N = 16: 10 orbits, 2 chaotic
    # by 100 and 6 blown up by 20 (blow-ups first: they can not turn chaotic afterwards)
    nan = math.nan
    N = [8] * 10 + [16] * 10
    tc = [10, 20, 30, 90] + [nan] * 6 + [40, 80] + [nan] * 8
    tb = [nan] * 4 + [50] + [nan] * 5 + [nan, nan] + [5, 10, 15, 20, 20, 20] + [nan, nan]
    tr = [1e3] * 20
    return OrbitOutcomes(N, list(range(20)), tc, tb, tr)


def test_outcome_table_counts_and_competing_risks():
    rows = {r["N"]: r for r in outcome_table(_synthetic(), [100.0])}
    r8, r16 = rows[8], rows[16]
    assert (r8["chaotic"], r8["blow-up"], r8["regular"], r8["n"]) == (4, 1, 5, 10)
    assert (r16["chaotic"], r16["blow-up"], r16["regular"]) == (2, 6, 2)
    assert r16["fraction_chaotic"] == pytest.approx(0.2)
    assert r16["fraction_chaotic_given_no_blowup"] == pytest.approx(2 / 4)
    assert r8["fraction_chaotic_low"] == pytest.approx(wilson_interval(4, 10)[0])
    surv, chaos, blow = cumulative_incidence(_synthetic(), 16, [1.0, 12.0, 100.0])
    np.testing.assert_allclose(surv + chaos + blow, 1.0)
    np.testing.assert_allclose(blow, [0.0, 0.2, 0.6])
    np.testing.assert_allclose(chaos, [0.0, 0.0, 0.2])


def test_not_reached_is_not_counted():
    o = OrbitOutcomes([8, 8], [1, 2], [math.nan, 5.0], [math.nan, math.nan], [50.0, 5.0])
    r = outcome_table(o, [100.0])[0]
    assert (r["chaotic"], r["not reached"], r["n"]) == (1, 1, 1)


def test_monotonicity_finds_a_planted_decrease_only():
    def rows(counts):
        return [{"N": N, "n": n, "chaotic": k, "blow-up": 0} for N, k, n in counts]
    falls = monotonicity(rows([(8, 5, 100), (16, 60, 100), (32, 20, 100)]))
    assert not falls["monotone"]
    assert [(f["from_N"], f["to_N"]) for f in falls["significant_decreases"]] == [(16, 32)]
    assert monotonicity(rows([(8, 5, 100), (16, 60, 100), (32, 55, 100)]))["monotone"]


def test_recurrence_quality_on_a_known_signal():
    t = np.arange(0.0, 3001.0, 10.0)
    s1 = 0.5 + 0.5 * np.cos(2 * np.pi * t / 1000.0)         # returns fully at t = 1000
    share = np.stack([s1, 1 - s1, 0 * t, 0 * t], axis=1)
    assert recurrence_time(t, share) == pytest.approx(1000.0)
    peak, dip = recurrence_quality(t, share, 1000.0)
    assert peak == pytest.approx(1.0)                        # at t = 1000
    assert dip == pytest.approx(0.5 + 0.5 * np.cos(2 * np.pi * 0.49))    # last sample < t_r/2


def test_recurrence_kind_starts_in_mode_1_and_returns():
    """The paper's state is mode 1 exactly (share 1 at t = 0), and the ordered chain of N = 8
    at amplitude 1 gives energy away and takes most of it back (a recurrence)."""
    ds = run_study("recurrence", {"N": [8], "tau": [0.0], "seed": [1]},
                   {"model": "nonlinear", "sample_every": 5.0}, 1500.0, workers=1).to_xarray()
    share = ds["share"].values[0, 0, 0]
    assert share[0, 0] == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(share.sum(axis=1) <= 1.0 + 1e-12, True)
    t_r = recurrence_time(ds["t"].values, share)
    peak, dip = recurrence_quality(ds["t"].values, share, t_r)
    assert dip < 0.9 and peak > 0.9 and not bool(ds["blew_up"].values.any())


@pytest.mark.skipif(not (STUDIES / "monotone").is_dir(), reason="no stored study")
def test_readme_tables_are_the_stored_study():
    """The generated tables of the open-questions studies in the README and
    docs/open_questions.md (monotone and model 2 at each time shown, how far every study got)
    equal the ones computed from the stored studies now (tools/update-open-tables.py)."""
    from fputlab.figures_open import GENERATED, generated_tables
    for page in ("README.md", "docs/open_questions.md"):
        text = (ROOT / page).read_text()
        blocks = GENERATED.findall(text)
        assert blocks, f"{page} has no generated open-questions table"
        assert generated_tables(text, STUDIES) == text, (
            f"{page}: a generated table differs from the stored study "
            "(run tools/update-open-tables.py)")
    readme = (ROOT / "README.md").read_text()
    assert {b[0] or "monotone" for b in GENERATED.findall(readme)} >= {"monotone", "reached"}
