"""Deprecated alias of `fputlab.chaos.batch` (the chaos code is one subpackage now); removed in
the next release."""
import warnings

from .chaos.batch import BATCH_METHODS, lyapunov_batch  # noqa: F401

__all__ = ["BATCH_METHODS", "lyapunov_batch"]

warnings.warn("fputlab.chaos_batch is deprecated: use fputlab.chaos.batch (or fputlab.chaos)",
              DeprecationWarning, stacklevel=2)
