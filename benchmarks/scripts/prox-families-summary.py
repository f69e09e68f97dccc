#!/usr/bin/env python3
"""Summary of build/bin/prox_families output (docs/solvers.md "prox-newton").

Reads one or more prox_families outputs (files or stdin; several files = several runs, e.g. the
before and after binaries alternated round by round, each labelled by its file name) and prints
per label and variant: steps, reached, median / p90 / max of ms_to_R (an unreached step counts as
its whole cpu_ms, marked by the reached count), the median of pgs_ms (the pgs+builtin reference,
measured in the same process), the ratio of the medians, and fact_to_R median / p99 / max.
With --per-step, each step's ms_to_R and fact_to_R per label side by side (medians over the
rounds of a label).

  prox-families-summary.py before.txt after.txt [--label-by-stem] [--per-step]
"""
import argparse
import math
import os
import re
import statistics
import sys
from collections import defaultdict


def quantile(xs, q):
    xs = sorted(xs)
    if not xs:
        return math.nan
    k = q * (len(xs) - 1)
    lo, hi = math.floor(k), math.ceil(k)
    return xs[lo] + (xs[hi] - xs[lo]) * (k - lo)


def parse(stream):
    rows = []
    for line in stream:
        if not line[:1].isdigit():
            continue
        head = line.split('"')[0].split()
        if len(head) < 16:
            continue
        seed, step, nrows, variant, reached = int(head[0]), int(head[1]), int(head[2]), head[3], int(head[4])
        r = dict(seed=seed, step=step, rows=nrows, variant=variant, reached=reached, acc=float(head[5]),
                 fact=int(head[6]), lead=int(head[7]), newton=int(head[8]), finish=int(head[9]),
                 cpu=float(head[11]), to_r=float(head[12]), it_to_r=int(head[13]), pgs=float(head[14]),
                 fact_to_r=int(head[15]))
        m = re.search(r'"(.*)"', line)
        r['message'] = m.group(1) if m else ''
        rows.append(r)
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('files', nargs='*')
    ap.add_argument('--label-by-stem', action='store_true',
                    help='label = file name up to the first "." or "-r<N>" (rounds of one binary pooled)')
    ap.add_argument('--per-step', action='store_true')
    a = ap.parse_args()
    data = defaultdict(list)  # (label, variant) -> rows
    sources = [(f, open(f)) for f in a.files] or [('stdin', sys.stdin)]
    for name, s in sources:
        label = os.path.basename(name)
        if a.label_by_stem:
            label = re.split(r'\.|-r\d+', label)[0]
        for r in parse(s):
            data[(label, r['variant'])].append(r)
    print(f"{'label':<22}{'variant':<12}{'n':>4}{'reach':>6}{'med_ms':>9}{'p90_ms':>9}{'max_ms':>9}"
          f"{'pgs_med':>9}{'ratio':>7}{'f_med':>6}{'f_p99':>7}{'f_max':>6}{'lead_med':>9}")
    for (label, variant), rows in sorted(data.items()):
        t = [r['to_r'] if r['to_r'] >= 0 else r['cpu'] for r in rows]
        f = [r['fact_to_r'] for r in rows]
        pgs = statistics.median(r['pgs'] for r in rows)
        med = statistics.median(t)
        print(f"{label:<22}{variant:<12}{len(rows):>4}{sum(r['reached'] for r in rows):>6}{med:>9.3f}"
              f"{quantile(t, 0.9):>9.3f}{max(t):>9.3f}{pgs:>9.3f}{med / pgs:>7.2f}"
              f"{statistics.median(f):>6.1f}{quantile(f, 0.99):>7.1f}{max(f):>6}"
              f"{statistics.median(r['lead'] for r in rows):>9.0f}")
    if a.per_step:
        labels = sorted({k for k in data})
        steps = sorted({(r['seed'], r['step']) for rows in data.values() for r in rows})
        print('seed step ' + ' '.join(f'{l}:{v}(ms,f,lead)' for l, v in labels) + ' pgs_med')
        for s in steps:
            cells, pg = [], []
            for k in labels:
                rs = [r for r in data[k] if (r['seed'], r['step']) == s]
                if not rs:
                    cells.append('-')
                    continue
                t = statistics.median(r['to_r'] if r['to_r'] >= 0 else r['cpu'] for r in rs)
                cells.append(f"{t:.3f},{rs[0]['fact_to_r']},{rs[0]['lead']}{'' if rs[0]['reached'] else '!'}")
                pg += [r['pgs'] for r in rs]
            print(f"{s[0]} {s[1]} " + ' '.join(cells) + f" {statistics.median(pg):.3f}")


if __name__ == '__main__':
    main()
