"""Results as tables: ``to_pandas()`` and ``to_polars()`` on results with one row per event,
point or value (pandas and polars are optional: ``pip install "./python[tables]"``)."""

from __future__ import annotations

from typing import Any


class Table:
    """A result whose ``_columns()`` gives named columns of equal length."""

    def _columns(self) -> dict[str, Any]:
        raise NotImplementedError

    def to_pandas(self) -> Any:
        """One row per entry, a column per field (2-D fields as one column per component,
        named ``field_1``, ``field_2``, …). Needs pandas."""
        import pandas as pd

        return pd.DataFrame(self._columns())

    def to_polars(self) -> Any:
        """:meth:`to_pandas` as a polars DataFrame. Needs polars."""
        import polars as pl

        return pl.DataFrame(self._columns())


def split(name: str, matrix: Any) -> dict[str, Any]:
    """A 2-D field as one column per component, ``name_1`` … ``name_N``."""
    return {f"{name}_{j + 1}": matrix[:, j] for j in range(matrix.shape[1])}
