"""The result of a chaos-indicator run and the classification of an orbit (made by
`fputlab.chaos.single` and `fputlab.chaos.batch`; public as `fputlab.chaos.ChaosResult`,
`fputlab.chaos.classify_orbit` and `fputlab.chaos.CLASSES`)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import _lowlevel as ll
from .._display import ResultMixin
from .._validate import _real

__all__ = ["ChaosResult", "classify_orbit", "CLASSES"]

#: the classes of an orbit, exactly these (C: fpl_orbit_class)
CLASSES = ("chaotic", "regular", "blow-up", "undecided")


def classify_orbit(t, mle, *, chaotic: bool, t_chaotic: float, blew_up: bool, t_blowup: float,
                   t_final: float, t_eval: float | None = None) -> str:
    """The class of an orbit at time t_eval (default t_final) from its log-spaced samples: the C
    rule fpl_chaos_classify, the only one. 'blow-up' if it blew up by t_eval; 'chaotic' if SALI
    fell below the threshold on the finite orbit by t_eval (never at or after a blow-up);
    'regular' if the run reached t_eval and lambda(t) follows the 1/t law over the last decade;
    otherwise 'undecided'."""
    t = np.ascontiguousarray(t, dtype=float)
    mle = np.ascontiguousarray(mle, dtype=float)
    if t.shape != mle.shape or t.ndim != 1:
        raise ValueError(f"t and mle must be 1-D of one length (got {t.shape}, {mle.shape})")
    te = math.nan if t_eval is None else _real(t_eval, "t_eval")
    return ll.chaos_classify(bool(chaotic), float(t_chaotic), bool(blew_up), float(t_blowup),
                             float(t_final), t, mle, te)


@dataclass(repr=False)
class ChaosResult(ResultMixin):
    """lambda(t), SALI(t), GALI(t) and MEGNO <Y>(t) at log-spaced times for one orbit.

    The orbit's class (`classify`) is exactly one of 'chaotic', 'regular', 'blow-up',
    'undecided'. A blow-up is decided by a stopping criterion, the bond-stretch check
    (`blowup_stretch`) or a non-finite state; 'chaotic' only by SALI < threshold on a finite
    orbit before any blow-up."""
    t: np.ndarray
    mle: np.ndarray
    sali: np.ndarray
    gali: np.ndarray
    chaotic: bool              # SALI fell below the threshold on the finite orbit
    t_chaotic: float           # when it did (NaN if never)
    t_final: float
    steps: int
    method: str
    completed: bool = True     # t_end reached, or stopped chaotic
    message: str = ""          # why the run ended early (blow-up: when and why)
    params: dict = field(default_factory=dict)
    blew_up: bool = False      # the run ended in a blow-up
    t_blowup: float = math.nan
    megno: np.ndarray | None = None   # MEGNO <Y>(t) at the samples (None: not computed, e.g.
                                      # the batched lanes of fputlab.chaos_batch)

    @property
    def megno_final(self) -> float:
        """MEGNO <Y> at the last sample (NaN if not computed)."""
        m = self.megno
        return float(m[-1]) if m is not None and m.size else float("nan")

    @property
    def mle_final(self) -> float:
        return float(self.mle[-1]) if self.mle.size else float("nan")

    def classify(self, t_eval: float | None = None) -> str:
        """The class at time t_eval (default: the end of the run): 'chaotic', 'regular',
        'blow-up' or 'undecided' (see `classify_orbit`)."""
        return classify_orbit(self.t, self.mle, chaotic=self.chaotic, t_chaotic=self.t_chaotic,
                              blew_up=self.blew_up, t_blowup=self.t_blowup,
                              t_final=self.t_final, t_eval=t_eval)
