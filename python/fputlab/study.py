"""Deprecated alias of `fputlab.chaos.study` (the chaos code is one subpackage now); removed in
the next release."""
import warnings

from .chaos.study import HORIZONS, ChaosStudy, StudySpec, migrate_legacy  # noqa: F401

__all__ = ["ChaosStudy", "StudySpec", "HORIZONS"]

warnings.warn("fputlab.study is deprecated: use fputlab.chaos.study", DeprecationWarning,
              stacklevel=2)
