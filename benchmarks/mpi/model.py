#!/usr/bin/env python3
"""Predicted parallel efficiency of granule's MPI policy at 16, 128 and 1024 ranks, from the
costs measured by benchmarks/mpi/scaling.sh (benchmarks/mpi/results/scaling.csv, best of its rounds),
for paper 001's lunar channel at paper size and for a 10-million-particle bed (docs/performance.md,
"Distributed runs"). Prints Markdown tables.

    python3 benchmarks/mpi/model.py [benchmarks/mpi/results/scaling.csv] [--alpha 2e-6] [--beta 10e9]

Per rank and step (n = N/P owned particles, g remote ghosts, m neighbour messages):
  compute    c1 n (1 + o) + c_g g     c1: one process, one thread (measured); o: the MPI policy's
                                      cost at one rank (measured); c_g = c1/2: a ghost's pairs
                                      with owned particles are evaluated on both ranks
  refresh    m alpha + 72 g / beta + t_g g    x, v, omega (9 doubles) per ghost; t_g: pack, copy,
                                      unpack and wait per ghost on this machine (measured, two
                                      ranks bound to cores)
  collective 4 alpha log2 P + 8 n_w P / beta  two allreduces (whether any rank changed its
                                      particles; the rebuild verdict) and the wall forces
                                      gathered on rank 0 and broadcast (n_w doubles per rank)
  rebuild    (t_mig + t_halo) n / n_2 / K + 2 (alpha log2 P + 2 P log2 P / beta) / K
                                      migration and halo build measured on two ranks (n_2
                                      particles each), and the two all-to-alls of message sizes
                                      (MPI_Alltoall of one int per rank: Bruck's algorithm, log2 P
                                      rounds of P/2 ints), every K steps
Ghosts: the volume of a sub-box grown by the halo width w on its cut faces, times the number
density; messages: the sub-boxes within w. The rank grid is the least cut area, as the engine
chooses it (parallel/decomposition.hpp). alpha and beta are a network's latency and bandwidth
(defaults: an InfiniBand-class cluster at the MPI level); they are assumptions, not measured here.
"""
import argparse
import csv
import math


def best_rows(path):
    best = {}
    for r in csv.DictReader(l for l in open(path) if not l.startswith('#')):
        k = (r['scene'], r['case'])
        if k not in best or float(r['s_per_particle_step']) < float(best[k]['s_per_particle_step']):
            best[k] = r
    return best


def grids(P):
    for px in range(1, P + 1):
        if P % px:
            continue
        for py in range(1, P // px + 1):
            if (P // px) % py:
                continue
            yield (px, py, P // px // py)


def choose_grid(P, L, periodic):
    """Least internal cut area; a periodic axis in p > 1 parts has p cuts, otherwise p - 1."""
    def area(g):
        a = 0.0
        for k in range(3):
            cuts = g[k] if (periodic[k] and g[k] > 1) else g[k] - 1
            a += cuts * L[(k + 1) % 3] * L[(k + 2) % 3]
        return a
    return min(grids(P), key=area)


def predict(N, L, periodic, r, phi, w, P, c, alpha, beta, K, n_w):
    g = choose_grid(P, L, periodic)
    a = [L[k] / g[k] for k in range(3)]
    vp = 4.0 / 3.0 * math.pi * r ** 3
    density = phi / vp
    cut = [g[k] > 1 for k in range(3)]
    grown = 1.0
    for k in range(3):
        grown *= a[k] + (2.0 * w if cut[k] else 0.0)
    ghosts = density * (grown - a[0] * a[1] * a[2])
    neighbours = 1
    for k in range(3):
        if cut[k]:
            neighbours *= min(g[k], 1 + 2 * math.ceil(w / a[k]))
    messages = neighbours - 1
    n = N / P
    t_comp = c['c1'] * n * (1.0 + c['o']) + 0.5 * c['c1'] * ghosts
    t_ref = messages * alpha + 72.0 * ghosts / beta + c['t_g'] * ghosts
    t_coll = 4.0 * alpha * math.log2(P) + 8.0 * n_w * P / beta
    t_reb = (c['t_rebuild'] * n / c['n2'] + 2.0 * (alpha * math.log2(P) + 2.0 * P * math.log2(P) / beta)) / K
    t = t_comp + t_ref + t_coll + t_reb
    return dict(grid='x'.join(map(str, g)), n=n, ghosts=ghosts, messages=messages, t=t,
                eff=c['c1'] * N / (P * t), core_ns=1e9 * P * t / N,
                parts={'compute': t_comp, 'refresh': t_ref, 'collective': t_coll, 'rebuild': t_reb})


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('csv', nargs='?', default='benchmarks/mpi/results/scaling.csv')
    ap.add_argument('--alpha', type=float, default=2e-6, help='latency per message [s]')
    ap.add_argument('--beta', type=float, default=10e9, help='bandwidth [B/s]')
    ap.add_argument('--rebuild-every', type=float, default=20.0, help='steps between rebuilds (flowing bed)')
    a = ap.parse_args()
    rows = best_rows(a.csv)
    header = open(a.csv).readline().strip('# \n')
    print('Measured costs (%s; best of the rounds):\n' % header)
    print('| scene | c1 [ns] | MPI policy at 1 rank | refresh per ghost [ns] | migration + halo build per rebuild, 2 ranks [ms] |')
    print('|---|---|---|---|---|')
    costs = {}
    for s in 'AB':
        f = lambda case, key: float(rows[(s, case)][key])
        c1 = f('single_1x1', 's_per_particle_step')
        o = f('mpi_1x1', 's_per_particle_step') / c1 - 1.0
        # Per ghost received from the other rank (bytes / 72 / ranks); scene A's ghosts_mean also
        # counts its periodic images, which are copied locally within the same refresh.
        remote = f('mpi_2x1', 'bytes_per_step') / 72.0 / f('mpi_2x1', 'ranks')
        t_g = f('mpi_2x1', 'refresh_s_per_step') / remote if remote else 0.0
        reb = rows[(s, 'rebuilds_mpi_2x1')]
        t_rebuild = float(reb['migration_s_per_rebuild']) + float(reb['halo_build_s_per_rebuild'])
        costs[s] = dict(c1=c1, o=max(o, 0.0), t_g=t_g, t_rebuild=t_rebuild, n2=float(reb['particles']) / 2)
        print('| %s | %.1f | %+.1f %% | %.1f | %.2f |' % (s, 1e9 * c1, 100 * o, 1e9 * t_g, 1e3 * t_rebuild))
    cases = [
        # Paper 001, table 5: 2 m x 20 cm, 2 cm wide (periodic), R = 1.25 mm, 575,410 grains.
        ('lunar channel (001, 2 m x 20 cm x 2 cm, 575,410 grains)', 'A', 575410, (0.02, 2.0, 0.2),
         (True, False, False), 1.25e-3, 0.5865, 5),
        # Scene B's box (000's material) grown to 10 million grains: S x S x 0.4 S.
        ('10-million bed (scene B, 0.56 x 0.56 x 0.22 m)', 'B', 10_000_000, None, (False, False, False), 1e-3, 0.60, 5),
    ]
    print('\nPredicted (alpha = %.3g s, beta = %.3g B/s, a rebuild every %g steps):\n' %
          (a.alpha, a.beta, a.rebuild_every))
    print('| system | ranks | grid | particles per rank | ghosts per rank | messages | compute / refresh / collective / rebuild [us] | efficiency | core-ns per particle-step |')
    print('|---|---|---|---|---|---|---|---|---|')
    for name, s, N, L, periodic, r, phi, walls in cases:
        if L is None:
            V = N * 4.0 / 3.0 * math.pi * r ** 3 / phi
            S = (V / 0.4) ** (1.0 / 3.0)
            L = (S, S, 0.4 * S)
        w = 2.0 * r * 1.1 + 0.2 * r  # 2 r_max (+-10 % radii) + skin
        for P in (16, 128, 1024):
            p = predict(N, L, periodic, r, phi, w, P, costs[s], a.alpha, a.beta, a.rebuild_every, 6 * walls)
            parts = ' / '.join('%.1f' % (1e6 * p['parts'][k]) for k in ('compute', 'refresh', 'collective', 'rebuild'))
            print('| %s | %d | %s | %.0f | %.0f | %d | %s | %.2f | %.0f |' % (
                name, P, p['grid'], p['n'], p['ghosts'], p['messages'], parts, p['eff'], p['core_ns']))
    published()


def published():
    # Paper 001 (shared/papers/001_..., section 2.7 and table 5): LIGGGHTS on one node of 128
    # cores (dual AMD EPYC 7763), 1.5 s simulated at dt = 1e-6 s (1.5e6 steps), v_p = 10 m/s,
    # output included. Rows: length [m], height [cm], particles, clock time [h].
    table5 = [(2, 20, 536180, 1.08), (2, 20, 575410, 1.12), (2, 20, 607953, 1.29), (2, 30, 814649, 1.51),
              (2, 10, 270641, 0.91), (1, 20, 267545, 0.83), (3, 20, 804763, 1.48), (4, 20, 1072258, 2.36)]
    print('\nPublished: LIGGGHTS, paper 001 table 5 (128 MPI ranks on one node, 1.5e6 steps, output included):\n')
    print('| channel | particles | particles per rank | clock time [h] | core-ns per particle-step |')
    print('|---|---|---|---|---|')
    for length, height, n, hours in table5:
        print('| %g m x %g cm | %d | %.0f | %.2f | %.0f |' % (length, height, n, n / 128, hours,
                                                          1e9 * 128 * hours * 3600 / (n * 1.5e6)))
    # LAMMPS's own benchmark logs (lammps/lammps, bench/log.15Jul25.chute.fixed.g++.1 and .4):
    # granular chute flow, 32,000 particles, 100 steps; loop time 0.155391 s on 1 rank,
    # 0.0451259 s on 4 (8000 particles per rank).
    t1, t4 = 0.155391, 0.0451259
    print('\nPublished: LAMMPS chute benchmark (bench/log.15Jul25.chute.fixed.g++.1/.4): 32,000 particles, '
          '4 ranks: speed-up %.2f, efficiency %.2f (8000 particles per rank).' % (t1 / t4, t1 / (4 * t4)))


if __name__ == '__main__':
    main()
