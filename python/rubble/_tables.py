"""Tables returned by rubble.compare, rubble.solvers and rubble.sweep: pandas frames when pandas
is installed, else dicts of NumPy arrays (both carry ``attrs``)."""

from __future__ import annotations

from typing import Any, Dict, Optional

import numpy as np


class Table(dict):
    """Columns as NumPy arrays, in order, with ``attrs`` for what goes with them."""

    def __init__(self, columns: Dict[str, np.ndarray], attrs: Optional[Dict[str, Any]] = None):
        super().__init__(columns)
        self.attrs: Dict[str, Any] = dict(attrs or {})


def have_pandas() -> bool:
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True


def make_table(columns: Dict[str, np.ndarray], attrs: Optional[Dict[str, Any]] = None,
               as_frame: Optional[bool] = None):
    """A pandas DataFrame when as_frame is True, or None and pandas is there; else a Table."""
    if as_frame is None:
        as_frame = have_pandas()
    if as_frame:
        import pandas as pd

        frame = pd.DataFrame(columns)
        frame.attrs.update(attrs or {})
        return frame
    return Table(columns, attrs)
