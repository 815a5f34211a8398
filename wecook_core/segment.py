"""The segmentation stage (DESIGN.md: ``segment.py``). The code lives in :mod:`wecook_core.segmentation`;
this module re-exports its public names (the one list is the package's ``__all__``)."""

from wecook_core.segmentation import *  # noqa: F403
from wecook_core.segmentation import __all__ as __all__
