"""A command's Parquet table against its CSV table (``results.files.write_table``)."""

from __future__ import annotations

import csv
import math
from pathlib import Path


def assert_same_table(csv_path: Path, parquet_path: Path, *, skip: tuple[str, ...] = ()) -> None:
    """The Parquet file, read back with pyarrow alone, holds the CSV's table: the same
    columns in order, and every cell the same (a number equal to the CSV's text read as
    one, nan to nan; an empty cell of a numeric column null; text equal). Columns in
    ``skip`` (a measured time) are compared by name and type only.

    Returns the Parquet schema for further checks."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    with open(csv_path, newline="", encoding="utf-8") as fh:
        header, *rows = list(csv.reader(fh))
    table = pq.read_table(parquet_path)
    assert table.column_names == header
    assert table.num_rows == len(rows)
    for j, name in enumerate(header):
        field = table.schema.field(name)
        assert field.type in (pa.int64(), pa.float64(), pa.string()), (name, field.type)
        if name in skip:
            continue
        for cell, value in zip((r[j] for r in rows), table.column(name).to_pylist(), strict=True):
            if field.type == pa.string():
                assert value == cell, (name, cell, value)
            elif cell == "":
                assert value is None, (name, value)
            elif field.type == pa.int64():
                assert value == int(cell), (name, cell, value)
            else:
                expected = float(cell)
                assert value == expected or (math.isnan(expected) and math.isnan(value)), (
                    name, cell, value,
                )  # fmt: skip
    return table.schema
