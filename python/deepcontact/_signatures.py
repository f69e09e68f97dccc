"""``inspect.signature`` for the functions of the C++ core.

pybind11 writes a function's signature as the first line of its docstring
(``solve(problem: deepcontact._core.Problem, solver: str = 'pgs', …) -> deepcontact._core.Result``),
which ``inspect`` cannot read from a builtin. ``signed(fn)`` returns a thin Python function that
calls ``fn`` and carries that signature as ``__signature__`` (annotations as the strings pybind11
gives, with the module prefix dropped).
"""
import ast
import functools
import inspect
import re


class _Default:
    """A default value pybind11 shows as text only (repr is that text)."""

    def __init__(self, text):
        self.text = text

    def __repr__(self):
        return self.text


def split_top(text, sep=","):
    """Split ``text`` at ``sep`` outside brackets and quotes."""
    out, depth, quote, cur = [], 0, None, ""
    for ch in text:
        if quote:
            cur += ch
            if ch == quote:
                quote = None
            continue
        if ch in "'\"":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        if ch == sep and depth == 0:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    if cur.strip():
        out.append(cur.strip())
    return out


def clean_type(text):
    """A pybind11 type name as a stub type: no module prefix, numpy arrays as NDArray, object as Any."""
    text = re.sub(r"deepcontact\._core\.", "", text)
    text = re.sub(r"numpy\.ndarray\[([\w.]+)\]", r"numpy.typing.NDArray[\1]", text)
    text = re.sub(r"\bobject\b", "Any", text)
    return text


def pybind_signature(name, doc):
    """The inspect.Signature of the first docstring line 'name(a: T = d, …) -> R', or None."""
    first = doc.strip().splitlines()[0] if doc and doc.strip() else ""
    m = re.match(r"^\s*" + re.escape(name) + r"\((.*)\)\s*->\s*(.+)$", first)
    if not m:
        return None
    params = []
    for p in split_top(m.group(1)):
        head, eq, default_text = p.partition("=")
        pname, _, annotation = head.partition(":")
        default = inspect.Parameter.empty
        if eq:
            try:
                default = ast.literal_eval(default_text.strip())
            except (ValueError, SyntaxError):
                default = _Default(default_text.strip())
        params.append(inspect.Parameter(pname.strip(), inspect.Parameter.POSITIONAL_OR_KEYWORD, default=default,
                                        annotation=clean_type(annotation.strip()) if annotation else inspect.Parameter.empty))
    return inspect.Signature(params, return_annotation=clean_type(m.group(2).strip()))


def signed(fn):
    """fn (a pybind11 function) wrapped in a Python function with its signature and docstring."""
    sig = pybind_signature(fn.__name__, fn.__doc__)

    @functools.wraps(fn)
    def call(*args, **kwargs):
        return fn(*args, **kwargs)

    call.__doc__ = "\n".join(fn.__doc__.strip().splitlines()[1:]).strip() if sig else fn.__doc__
    if sig is not None:
        call.__signature__ = sig
    call.__module__ = "deepcontact"
    return call
