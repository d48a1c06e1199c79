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


def read_text_table(path):
    """(provenance, rows): the first "# ..." line without its "# " ("provenance unknown" if the
    file has none), and the rows as dicts of text keyed by the column name without its unit."""
    with open(path, newline="", encoding="utf-8") as f:
        lines = f.read().splitlines()
    prov = lines[0].lstrip("# ").strip() if lines and lines[0].startswith("#") else "provenance unknown"
    rows = list(csv.reader(line for line in lines if not line.startswith("#")))
    names = [h.split(" [")[0] for h in rows[0]]
    return prov, [dict(zip(names, r)) for r in rows[1:]]
