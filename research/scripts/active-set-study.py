#!/usr/bin/python3
"""How predictable is the active set that PGS must find? (docs/research.md
"How complete the active set must be")

For each step of a family window, per contact, the mode (separating, sticking, sliding +/-)
of three things is compared with the mode of this step's λ* (tight oracle):
  * builtin's guess (last step's λ* by key, projected), i.e. builtin-active's active set;
  * the PGS iterate after k sweeps from builtin (k = 10 ... 1000): when does PGS know it?
  * a softmax-regression classifier on per-contact features of builtin's guess (its mode,
    |λ_t|/μλ_n, λ_n, gap, approach velocity, and w = Aλ_b + b at the contact's rows), trained
    on training seeds and scored on held-out seeds — the best a purely local, per-contact
    predictor of this kind does.
It also solves each held-out step tightly twice more (Newton from builtin, PGS from zero) to
see whether λ*'s active set is the only one near builtin's (a statically indeterminate pile
has many solutions).
Scores: the share of contacts whose mode is wrong, and the recall of the mode CHANGES
(contacts where builtin's mode is wrong: the share the predictor gets right; compare with
copy-active:F, which needs F ≈ 1 to pay).

The trajectory follows the bench's paired mode: --warmup steps of PGS from builtin (sweeps
3000, tol 1e-2), then every step is solved tightly and integrated with λ*.

    PYTHONPATH=build/python /usr/bin/python3 research/scripts/active-set-study.py \
        --scene scenes/impact.toml --train 1000..1003 --test 1..2 --warmup 195 --steps 260
"""
import argparse
import sys
import time
from types import SimpleNamespace

import numpy as np

import deepcontact as dc

SEP, STICK, SLIDE_P, SLIDE_M = 0, 1, 2, 3
NAMES = ["separating", "sticking", "sliding+", "sliding-"]
SWEEPS = (10, 30, 100, 300, 1000)
N_LOCAL = 15  # columns of features(): the contact's own state (checked in run())


def seeds(text):
    a, _, b = text.partition("..")
    return list(range(int(a), int(b or a) + 1))


def modes(lam, nrow, trow, mu):
    """The mode of each contact in λ (the C++ contact_mode rule)."""
    ln = lam[nrow]
    lt = np.where(trow >= 0, lam[np.maximum(trow, 0)], 0.0)
    m = np.full(len(nrow), STICK)
    slide = (trow >= 0) & (np.abs(lt) >= mu * ln * (1 - 1e-9))
    m[slide & (lt > 0)] = SLIDE_P
    m[slide & (lt <= 0)] = SLIDE_M
    m[~(ln > 0)] = SEP
    return m


def builtin_guess(w):
    """Last step's solved λ by contact key (the package's rule for builtin; a World stands in
    for the bench's view) and the new-contact flags; projected by the caller."""
    return dc.previous_lambda_by_key(SimpleNamespace(world=w))


def project(lam, nrow, trow, mu):
    out = lam.copy()
    out[nrow] = np.maximum(out[nrow], 0.0)
    t = trow >= 0
    cap = mu[t] * out[nrow[t]]
    out[trow[t]] = np.clip(out[trow[t]], -cap, cap)
    return out


def features(lam_b, new, w_b, cur, nrow, trow, mu):
    """Per-contact features of builtin's guess (one row per contact)."""
    ln = lam_b[nrow]
    lt = np.where(trow >= 0, lam_b[np.maximum(trow, 0)], 0.0)
    ratio = np.where(ln > 0, lt / np.maximum(mu * ln, 1e-300), 0.0)
    wn = w_b[nrow]
    wt = np.where(trow >= 0, w_b[np.maximum(trow, 0)], 0.0)
    m = modes(lam_b, nrow, trow, mu)
    onehot = np.eye(4)[m]
    gap = cur["gap"]
    vn = cur["approach_velocity"]
    f = np.column_stack([onehot, new.astype(float), ratio, np.abs(ratio), np.arcsinh(ln), np.arcsinh(lt),
                         gap * 100.0, vn, np.arcsinh(wn * 100.0), np.arcsinh(wt * 100.0),
                         np.sign(wt) * np.sign(lt), (wn < 0) * (ln <= 0)])
    return f, m


def with_neighbours(f, cur):
    """f plus the mean of f over the other contacts of the contact's bodies (walls have no
    neighbourhood): the context a grid CNN would see, at the contacts' own resolution."""
    a = np.asarray(cur["body_a"])
    b = np.asarray(cur["body_b"])
    n = int(max(a.max(initial=-1), b.max(initial=-1))) + 1
    S = np.zeros((n, f.shape[1]))
    cnt = np.zeros(n)
    for side in (a, b):
        ok = side >= 0
        np.add.at(S, side[ok], f[ok])
        np.add.at(cnt, side[ok], 1.0)
    tot = np.zeros_like(f)
    num = np.zeros(len(f))
    for side in (a, b):
        ok = side >= 0
        tot[ok] += S[side[ok]] - f[ok]
        num[ok] += cnt[side[ok]] - 1
    return np.column_stack([f, tot / np.maximum(num, 1)[:, None], num])


def run(scene, seed, warmup, steps, with_sweeps, overrides=None):
    """Per-contact records of steps [warmup, steps) of one seed; `overrides` adds --set keys."""
    w = dc.World(scene=scene, set={**(overrides or {}), "bodies.seed": seed})
    for _ in range(warmup):
        w.step(solver="pgs", warmstart="builtin", sweeps=3000, tol=1e-2)
    rows = []
    for s in range(warmup, steps):
        w.collide()
        p = w.assemble()
        if w.rows == 0:
            w.integrate(np.zeros(0))
            continue
        cur = w.contacts
        nrow = np.asarray(cur.normal_row)
        trow = np.asarray(cur.tangent_row)
        mu = np.where(trow >= 0, np.asarray(p.mu)[np.maximum(trow, 0)], 0.0)  # μ sits on the tangent row
        lam_b, new = builtin_guess(w)
        lam_b = project(lam_b, nrow, trow, mu)
        r = dc.solve(p, solver="pgs", sweeps=20000, tol=1e-7, lambda0=lam_b, record_theta=False)
        star = r.lam
        if r.residual > 1e-6:
            r2 = dc.solve(p, solver="newton", sweeps=200, tol=1e-9, lambda0=star, record_theta=False)
            if r2.residual < r.residual:
                star = r2.lam
        m_star = modes(star, nrow, trow, mu)
        f, m_b = features(lam_b, new, p.velocity(lam_b), cur, nrow, trow, mu)
        assert f.shape[1] == N_LOCAL
        f = with_neighbours(f, cur)
        after, other = {}, {}
        if with_sweeps:
            # Other tight solutions: is λ*'s active set the only one near builtin's?
            for name, solver, start in (("newton from builtin", "newton", lam_b), ("PGS from zero", "pgs", None)):
                o = dc.solve(p, solver=solver, sweeps=500 if solver == "newton" else 30000, tol=1e-8, lambda0=start,
                             record_theta=False)
                if o.residual <= max(1e-6, 10 * r.residual):
                    other[name] = (modes(o.lam, nrow, trow, mu), np.linalg.norm(o.lam - star) / max(np.linalg.norm(star), 1e-300))
            lam = lam_b
            done = 0
            for k in SWEEPS:
                lam = dc.solve(p, solver="pgs", sweeps=k - done, tol=0.0, lambda0=lam, record_theta=False).lam
                done = k
                after[k] = modes(lam, nrow, trow, mu)
        rows.append(dict(step=s, f=f, m_b=m_b, m_star=m_star, after=after, other=other))
        w.integrate(star)
    return rows


def fit_softmax(x, y, classes=4, l2=1e-3, iters=300, lr=0.5):
    """Multinomial logistic regression by full-batch gradient descent (standardised inputs)."""
    mean, std = x.mean(0), x.std(0) + 1e-9
    z = (x - mean) / std
    z = np.column_stack([z, np.ones(len(z))])
    W = np.zeros((z.shape[1], classes))
    Y = np.eye(classes)[y]
    for _ in range(iters):
        s = z @ W
        s -= s.max(1, keepdims=True)
        P = np.exp(s)
        P /= P.sum(1, keepdims=True)
        g = z.T @ (P - Y) / len(z) + l2 * W
        W -= lr * g
    return lambda q: np.argmax(np.column_stack([(q - mean) / std, np.ones(len(q))]) @ W, 1)


def fit_mlp(x, y, classes=4, hidden=64, epochs=12, batch=512, lr=2e-3, seed=1):
    """A two-hidden-layer ReLU network with a softmax output, Adam, standardised inputs."""
    rng = np.random.default_rng(seed)
    mean, std = x.mean(0), x.std(0) + 1e-9
    z = (x - mean) / std
    sizes = [z.shape[1], hidden, hidden, classes]
    P = []
    for i in range(3):
        P += [rng.normal(0, np.sqrt(2.0 / sizes[i]), (sizes[i], sizes[i + 1])), np.zeros(sizes[i + 1])]
    M = [np.zeros_like(q) for q in P]
    V = [np.zeros_like(q) for q in P]
    Y = np.eye(classes)[y]
    t = 0
    for _ in range(epochs):
        order = rng.permutation(len(z))
        for k in range(0, len(z), batch):
            idx = order[k:k + batch]
            h0 = z[idx]
            a1 = h0 @ P[0] + P[1]
            h1 = np.maximum(a1, 0)
            a2 = h1 @ P[2] + P[3]
            h2 = np.maximum(a2, 0)
            o = h2 @ P[4] + P[5]
            o -= o.max(1, keepdims=True)
            pr = np.exp(o)
            pr /= pr.sum(1, keepdims=True)
            d = (pr - Y[idx]) / len(idx)
            g = [None] * 6
            g[4], g[5] = h2.T @ d, d.sum(0)
            d2 = (d @ P[4].T) * (a2 > 0)
            g[2], g[3] = h1.T @ d2, d2.sum(0)
            d1 = (d2 @ P[2].T) * (a1 > 0)
            g[0], g[1] = h0.T @ d1, d1.sum(0)
            t += 1
            for i in range(6):
                M[i] = 0.9 * M[i] + 0.1 * g[i]
                V[i] = 0.999 * V[i] + 0.001 * g[i] ** 2
                P[i] -= lr * (M[i] / (1 - 0.9 ** t)) / (np.sqrt(V[i] / (1 - 0.999 ** t)) + 1e-8)

    def predict(q):
        h = np.maximum(((q - mean) / std) @ P[0] + P[1], 0)
        h = np.maximum(h @ P[2] + P[3], 0)
        return np.argmax(h @ P[4] + P[5], 1)

    return predict


def score(pred, m_star, m_b):
    wrong = pred != m_star
    changed = m_b != m_star
    recall = 1.0 - wrong[changed].mean() if changed.any() else float("nan")
    broke = (wrong & ~changed).mean()  # contacts builtin had right, the predictor got wrong
    return wrong.mean(), recall, broke


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", required=True)
    ap.add_argument("--train", default="1000..1003")
    ap.add_argument("--test", default="1..2")
    ap.add_argument("--warmup", type=int, default=195)
    ap.add_argument("--steps", type=int, default=260)
    a = ap.parse_args()
    t0 = time.time()
    train = [r for s in seeds(a.train) for r in run(a.scene, s, a.warmup, a.steps, False)]
    test = [r for s in seeds(a.test) for r in run(a.scene, s, a.warmup, a.steps, True)]
    cat = lambda rs, k: np.concatenate([r[k] for r in rs])
    local = N_LOCAL  # the first columns: the contact's own features
    clf = fit_softmax(cat(train, "f")[:, :local], cat(train, "m_star"))
    mlp_local = fit_mlp(cat(train, "f")[:, :local], cat(train, "m_star"))
    mlp_nb = fit_mlp(cat(train, "f"), cat(train, "m_star"))
    m_star, m_b, f = cat(test, "m_star"), cat(test, "m_b"), cat(test, "f")
    print(f"scene {a.scene}: train seeds {a.train} ({len(cat(train, 'm_star'))} contacts), test seeds {a.test} "
          f"({len(m_star)} contacts, {len(test)} steps), steps {a.warmup}-{a.steps - 1}; {time.time() - t0:.0f} s")
    share = np.array([(r["m_b"] != r["m_star"]).mean() for r in test])
    print(f"builtin's mode wrong: {np.mean(m_b != m_star):.3f} of contacts (per-step median {np.median(share):.3f}, "
          f"p10-p90 {np.percentile(share, 10):.3f}-{np.percentile(share, 90):.3f})")
    trans = np.zeros((4, 4), dtype=int)
    np.add.at(trans, (m_b, m_star), 1)
    print("builtin mode (rows) -> lambda* mode (columns):", " ".join(NAMES))
    for i in range(4):
        print(f"  {NAMES[i]:>10}: " + " ".join(f"{v:8d}" for v in trans[i]))
    print(f"{'predictor':>28} {'wrong':>7} {'recall of changes':>18} {'newly wrong':>12}")
    for name, pred in [("builtin (no change)", m_b), ("softmax on local features", clf(f[:, :local])),
                       ("MLP on local features", mlp_local(f[:, :local])),
                       ("MLP, local + neighbours", mlp_nb(f))] + \
            [(f"PGS after {k} sweeps", np.concatenate([r["after"][k] for r in test]))
             for k in SWEEPS]:
        wr, rec, br = score(pred, m_star, m_b)
        print(f"{name:>28} {wr:7.3f} {rec:18.3f} {br:12.3f}")
    print("other tight solutions (residual <= max(1e-6 N, 10x lambda*'s)): modes != lambda*'s, |lambda - lambda*| / |lambda*|")
    for name in ("newton from builtin", "PGS from zero"):
        got = [r["other"][name] for r in test if name in r["other"]]
        if not got:
            print(f"  {name:>22}: never that tight")
            continue
        diff = np.array([np.mean(m != r["m_star"]) for (m, _), r in zip(got, [r for r in test if name in r["other"]])])
        dist = np.array([d for _, d in got])
        print(f"  {name:>22}: {len(got)} of {len(test)} steps; modes differ median {np.median(diff):.4f} "
              f"(p90 {np.percentile(diff, 90):.4f}); distance median {np.median(dist):.3f} (p90 {np.percentile(dist, 90):.3f})")


if __name__ == "__main__":
    sys.exit(main())
