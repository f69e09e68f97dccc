#!/usr/bin/env python3
# How predictable is builtin's error from per-contact quantities? (docs/research.md, "What a
# residual predictor has to learn"). For every contact of a `deepcontact generate` data set
# in steps >= FIRST whose previous step is in the file, the correction Δ = λ*_n − λ_prev,n
# (λ_prev matched by body pair: circle scenes, one contact per pair; 0 for new contacts) is
# fitted by linear least squares on the simulations' first 70 % and R² is reported on the
# rest, for a few feature sets; also ‖Δ‖/‖λ*‖ per part of the window.
#   /usr/bin/python3 research/scripts/correction-r2.py DATA.h5 [FIRST=195]
import h5py, numpy as np, sys
f = h5py.File(sys.argv[1], 'r')
first = int(sys.argv[2]) if len(sys.argv) > 2 else 195
S = f['samples']; C = f['contacts']; B = f['bodies']
step = S['step'][:]; sim = S['sim'][:]; cb = S['contact_begin'][:]; cc = S['contact_count'][:]
bb = S['body_begin'][:]; bc = S['body_count'][:]
A = C['body_a'][:]; Bb = C['body_b'][:]; L = C['lambda_star'][:]; N = C['normal'][:]; G = C['gap'][:]
V = B['velocity'][:]; M = B['mass'][:]
rows = []
for s in range(1, len(step)):
    if step[s] < first or sim[s] != sim[s-1] or step[s-1] != step[s]-1: continue
    p0, p1 = cb[s-1], cb[s-1]+cc[s-1]
    prev = {(int(a), int(b)): L[k] for k, a, b in zip(range(p0, p1), A[p0:p1], Bb[p0:p1])}
    q0, q1 = cb[s], cb[s]+cc[s]
    v = V[bb[s]:bb[s]+bc[s]]; m = M[bb[s]:bb[s]+bc[s]]
    for k in range(q0, q1):
        a, b = int(A[k]), int(Bb[k])
        lp = prev.get((a, b), np.zeros(2))
        va = v[a] if a >= 0 else np.zeros(2)
        vb = v[b] if b >= 0 else np.zeros(2)
        vn = float(np.dot(vb - va, N[k]))
        ma = m[a] if a >= 0 else np.inf; mb = m[b] if b >= 0 else np.inf
        meff = 1.0 / (1.0/ma + 1.0/mb)
        rows.append((step[s], sim[s], L[k][0], lp[0], vn, meff, G[k], (a, b) in prev))
r = np.array(rows, dtype=float)
st, ls, lp, vn, meff, gap, had = r[:, 0], r[:, 2], r[:, 3], r[:, 4], r[:, 5], r[:, 6], r[:, 7]
d = ls - lp
print(f"contacts {len(r)}, window steps >= {first}; |lambda*| median {np.median(np.abs(ls)):.3g} N, "
      f"|delta| median {np.median(np.abs(d)):.3g} N, ||delta||/||lambda*|| = {np.linalg.norm(d)/np.linalg.norm(ls):.3f}, new {1-had.mean():.3f}")
# Feature sets, each fit by least squares on the first 70 % of simulations, R² on the rest.
sims = np.unique(r[:, 1]); train = np.isin(r[:, 1], sims[:int(0.7*len(sims))])
def r2(X, name):
    X = np.column_stack([np.ones(len(X))] + [X])
    w, *_ = np.linalg.lstsq(X[train], d[train], rcond=None)
    e = d[~train] - X[~train] @ w
    print(f"  {name:40s} R2(held-out sims) = {1 - e.var()/d[~train].var():.3f}")
impulse = -np.minimum(vn, 0) * meff   # momentum to stop the approach [N s]
r2(np.column_stack([lp]), "lambda_prev")
r2(np.column_stack([impulse]), "m_eff * approach speed")
r2(np.column_stack([lp, impulse, vn, meff, gap, had]), "lambda_prev, impulse, vn, m_eff, gap, had")
for lo, hi in [(195, 215), (215, 225), (225, 260)]:
    sel = (st >= lo) & (st < hi)
    print(f"  steps {lo}-{hi}: ||delta||/||lambda*|| = {np.linalg.norm(d[sel])/np.linalg.norm(ls[sel]):.3f}, "
          f"median |delta| {np.median(np.abs(d[sel])):.3g}, median lambda* {np.median(ls[sel]):.3g}")
