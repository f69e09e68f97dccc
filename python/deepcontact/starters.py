"""Warm starters written in Python that other code builds on.

``previous_lambda_by_key(view)`` is builtin's rule in Python — each contact of this step
gets the solved λ of the previous step's contact with the same key (body pair and feature),
0 for a new contact — and ``PyBuiltin`` is the starter made of it. The test suite checks
that ``PyBuiltin`` gives exactly the C++ ``builtin``'s sweeps in a paired bench
(tests/python/test_warmstart.py); benchmarks/scripts/python-starter-overhead.py uses it to time the
cost of a Python starter; examples/custom_warm_starter.py extends the rule.
"""
from __future__ import annotations

import numpy as np

from . import StepView, WarmStarter  # noqa: F401  (StepView: annotations)


def previous_lambda_by_key(view: StepView) -> tuple[np.typing.NDArray[np.float64], np.typing.NDArray[np.bool_]]:
    """λ⁰ by builtin's rule and the mask of contacts that had no previous match.

    Returns ``(lam0, new)``: ``lam0`` has one float per LCP row of ``view.world`` (the
    previous step's solved λ_n on each contact's normal row and λ_t on its tangent row, 0 for
    a contact without a match), ``new`` one bool per contact (True: no previous contact with
    this key). Cost: one dict of the previous contacts, O(contacts) lookups.
    """
    w = view.world
    cur, prev = w.contacts, w.previous_contacts
    old = {tuple(k): lam for k, lam in zip(prev.key.tolist(), prev["lambda"].tolist())}
    lam0 = np.zeros(w.rows)
    new = np.ones(len(cur.normal_row), dtype=bool)
    for c, key in enumerate(cur.key.tolist()):
        hit = old.get(tuple(key))
        if hit is not None:
            new[c] = False
            lam0[cur.normal_row[c]] = hit[0]
            if cur.tangent_row[c] >= 0:
                lam0[cur.tangent_row[c]] = hit[1]
    return lam0, new


class PyBuiltin(WarmStarter):
    """``builtin`` in Python: the previous step's solved λ of the contact with the same key."""

    def name(self) -> str:
        """``"py-builtin"``."""
        return "py-builtin"

    def initial_guess(self, view: StepView) -> np.typing.NDArray[np.float64]:
        """The previous step's solved λ by contact key (0 for new contacts)."""
        return previous_lambda_by_key(view)[0]
