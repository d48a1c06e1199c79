#!/usr/bin/env python3
"""Summary of a benchmarks/run_peers.sh CSV: per scene and core count, the best and the median
particle-steps/s of each code over the rounds, granule's ratios to each peer (best to best and
median to median), and whether the end states are comparable (contacts and mean overlap within
1 % of granule's).

Usage: summarise.py peers.csv
"""
import csv
import statistics
import sys
from collections import defaultdict


def main(path):
    rates = defaultdict(list)
    ends = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            try:
                rate = float(row["particle_steps_per_s"])
            except ValueError:
                continue
            key = (row["scene"], int(row["cores"]))
            rates[key + (row["code"],)].append(rate)
            ends[key + (row["code"],)] = (row["contacts"], row["mean_overlap"])
    keys = sorted({k[:2] for k in rates})
    codes = sorted({k[2] for k in rates}, key=lambda c: (c == "granule", c))
    print("scene cores code      rounds  best        median      granule/code best  median  end state (contacts, mean overlap)")
    for scene, cores in keys:
        g = rates.get((scene, cores, "granule"))
        for code in codes:
            r = rates.get((scene, cores, code))
            if not r:
                continue
            best, med = max(r), statistics.median(r)
            ratio = ""
            if g and code != "granule":
                ratio = f"{max(g) / best:5.2f}             {statistics.median(g) / med:5.2f}"
            contacts, overlap = ends[(scene, cores, code)]
            note = ""
            ge = ends.get((scene, cores, "granule"))
            if ge and code != "granule":
                try:
                    dc = abs(float(contacts) / float(ge[0]) - 1.0)
                    do = abs(float(overlap) / float(ge[1]) - 1.0)
                    note = "  ok" if dc < 0.01 and do < 0.01 else f"  DIFFERS ({dc:.2%}, {do:.2%})"
                except ValueError:
                    note = "  (no end state)"
            print(f"{scene:5} {cores:5} {code:9} {len(r):6}  {best:.3e}   {med:.3e}   {ratio:26} {contacts}, {overlap}{note}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
