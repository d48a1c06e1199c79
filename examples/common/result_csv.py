"""The result tables of the example studies: CSV files whose first line may be a "# ..."
provenance comment and whose column names carry their unit in brackets ("work [J]")."""
import csv
import re


def read_table(path):
    """Rows of a result CSV as dicts keyed by the column name without its unit; numbers as float,
    the rest as text; comment lines ("# ...") are skipped."""
    with open(path, newline="", encoding="utf-8") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    names = [re.sub(r"\s*\[.*\]$", "", h) for h in rows[0]]
    out = []
    for r in rows[1:]:
        d = {}
        for n, v in zip(names, r):
            try:
                d[n] = float(v)
            except ValueError:
                d[n] = v
        out.append(d)
    return out
