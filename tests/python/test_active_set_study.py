"""research/scripts/active-set-study.py (docs/research.md "How complete the active set must be"): its
mode rule is the C++ one, and on a small pile PGS's active set approaches λ*'s as it sweeps."""
import importlib.util

import numpy as np

from conftest import SOURCE


def load_study():
    spec = importlib.util.spec_from_file_location("active_set_study", SOURCE / "research" / "scripts" / "active-set-study.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_modes_follow_the_contact_mode_rule():
    s = load_study()
    # Four contacts: separating (λ_n = 0), sticking, sliding + and − (|λ_t| = μ λ_n), and a
    # frictionless one (no tangent row) that touches: sticking.
    lam = np.array([0.0, 0.0, 2.0, 0.5, 1.0, 0.5, 1.0, -0.5, 3.0])
    nrow = np.array([0, 2, 4, 6, 8])
    trow = np.array([1, 3, 5, 7, -1])
    mu = np.array([0.5, 0.5, 0.5, 0.5, 0.0])
    assert s.modes(lam, nrow, trow, mu).tolist() == [s.SEP, s.STICK, s.SLIDE_P, s.SLIDE_M, s.STICK]


def test_pgs_finds_the_active_set_as_it_sweeps():
    s = load_study()
    # 60 circles of the small scene, steps 60–69: a pile whose modes change from step to step.
    rows = s.run(str(SOURCE / "scenes" / "small.toml"), 1, 60, 70, True, {"bodies.count": 60})
    assert len(rows) == 10
    m_star = np.concatenate([r["m_star"] for r in rows])
    wrong = {k: np.mean(np.concatenate([r["after"][k] for r in rows]) != m_star) for k in s.SWEEPS}
    builtin = np.mean(np.concatenate([r["m_b"] for r in rows]) != m_star)
    assert builtin > 0.01  # builtin's remembered modes are wrong somewhere
    assert wrong[1000] <= wrong[10]
    assert wrong[1000] < builtin
    # One feature row per contact.
    assert sum(len(r["f"]) for r in rows) == len(m_star)
