#!/usr/bin/env python3
"""List C++ functions longer than --max lines; exit 1 when there is one.

    scripts/check-function-length.py --max 100 apps
    scripts/check-function-length.py --max 60 --top 10 research/src engine/src/world/world.cpp
    scripts/check-function-length.py --self-test

Why: a command of the `deepcontact` executable is option parsing, one call into a library and
printing (apps/deepcontact/CMakeLists.txt: "thin commands over the libraries"); a function that
grows past a screenful there is almost always domain logic that belongs in a library, where it
can be tested without the CLI. This check keeps apps/ to that.

What counts as a function: every brace-delimited body at namespace or class scope that
follows a parameter list, i.e. free and member functions, constructors (with or without an
initialiser list), operators, GoogleTest bodies (`TEST(A, B) { ... }`), lambdas assigned at
namespace or class scope (`auto f = [&](int x) { ... };`) and function-try-blocks (their
handlers included). A lambda, local class or block inside a function is part of that
function. Its length runs from the first line of its declaration (the `template <...>` line
when there is one; comments and access labels such as `public:` before it do not count) to
the line of its closing brace, both included: a one-line function has length 1.

How: a lexer first blanks comments, string literals (raw strings included), character
literals and preprocessor directives (with their line continuations), keeping every newline,
so that braces in them are never seen; digit separators (1'000) are not taken for character
literals. A scan then matches braces. At namespace and class scope, the text since the last
`;`, `{` or `}` of that scope (the "head") decides what a `{` opens:
  * `namespace`, `extern "C"`: a scope, scanned for functions;
  * `class`, `struct`, `union`, `enum` (after an optional `template <...>`): a scope;
  * a head ending in `)` plus qualifiers (const, noexcept, override, final, mutable, &, &&,
    a trailing return type, a requires clause), a constructor's initialiser list
    (`) : a_(x), b_{y}`) or a lambda introducer after `=` (`= [&]`): a function body;
  * anything else (`std::vector<int> v{1, 2};`, `= {…}`, braces inside parentheses): an
    initialiser, skipped, and the head goes on to the next `;`.
Both branches of an `#if` are scanned as if they were one text; a file whose braces do not
balance that way is reported (exit 2) instead of guessed at.

Output: one line per function over --max, longest first, as `path:line: name: N lines`, then
a summary with the longest function seen. Exit status: 0 none over, 1 some over, 2 usage or
unbalanced braces.
"""
from __future__ import annotations

import argparse
import os
import re
import sys
from dataclasses import dataclass

EXTENSIONS = (".cpp", ".cc", ".cxx", ".hpp", ".hh", ".hxx", ".h", ".ipp", ".inl")


@dataclass
class Function:
    path: str
    line: int    # first line of the declaration (1-based)
    end: int     # line of the closing brace
    name: str

    @property
    def length(self) -> int:
        return self.end - self.line + 1


class UnbalancedBraces(Exception):
    pass


# ---- lexing ----------------------------------------------------------------------------

def _is_ident(ch: str) -> bool:
    return ch.isalnum() or ch == "_"


def _raw_string_prefix(src: str, quote: int) -> bool:
    """Whether the `"` at `quote` opens a raw string: R, u8R, uR, UR or LR as a whole token."""
    if quote == 0 or src[quote - 1] != "R":
        return False
    start = quote - 1
    while start > 0 and _is_ident(src[start - 1]):
        start -= 1
    return src[start:quote] in ("R", "u8R", "uR", "UR", "LR")


def _digit_separator(src: str, quote: int) -> bool:
    """Whether the `'` at `quote` separates digits of a number (1'000'000, 0xFF'FF)."""
    start = quote
    while start > 0 and (_is_ident(src[start - 1]) or src[start - 1] in ".'"):
        start -= 1
    token = src[start:quote]
    return bool(token) and (token[0].isdigit() or (token[0] == "." and len(token) > 1 and token[1].isdigit()))


def blank_non_code(src: str) -> str:
    """`src` with comments, literals and preprocessor directives replaced by spaces.

    Newlines are kept (so offsets and line numbers are unchanged) and the quotes of a string
    literal stay (so `extern "C"` is still recognisable)."""
    out = list(src)
    n = len(src)
    i = 0
    at_line_start = True   # only whitespace since the last newline (a `#` there is a directive)
    in_directive = False

    def blank(a: int, b: int) -> None:
        for k in range(a, min(b, n)):
            if out[k] != "\n":
                out[k] = " "

    while i < n:
        c = src[i]
        nxt = src[i + 1] if i + 1 < n else ""
        if c == "\n":
            # A directive ends at a newline that no backslash continues.
            if in_directive and not (i > 0 and src[i - 1] == "\\"):
                in_directive = False
            at_line_start = True
            i += 1
            continue
        if c == "/" and nxt == "/":           # line comment (continued by a trailing backslash)
            j = i
            while j < n:
                if src[j] == "\n" and src[j - 1] != "\\":
                    break
                j += 1
            blank(i, j)
            i = j
            continue
        if c == "/" and nxt == "*":           # block comment
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
            blank(i, j)
            i = j
            continue
        if c == '"' and _raw_string_prefix(src, i):
            open_paren = src.find("(", i + 1)
            delim = src[i + 1:open_paren] if open_paren >= 0 else ""
            close = src.find(")" + delim + '"', open_paren + 1) if open_paren >= 0 else -1
            j = n if close < 0 else close + len(delim) + 2
            blank(i + 1, j - 1)
            i = j
            continue
        if c == '"' or (c == "'" and not _digit_separator(src, i)):
            j = i + 1
            while j < n and src[j] != c and src[j] != "\n":
                j += 2 if src[j] == "\\" else 1
            j = min(j + 1, n)
            blank(i + 1, j - 1)
            if in_directive:
                blank(i, j)
            i = j
            at_line_start = False
            continue
        if at_line_start and c == "#":
            in_directive = True
        if not c.isspace():
            at_line_start = False
        if in_directive:
            out[i] = " "
        i += 1
    return "".join(out)


# ---- classifying a head ----------------------------------------------------------------

_ACCESS = re.compile(r"\s*(?:public|private|protected)\s*:(?!:)")
_QUALIFIER = re.compile(
    r"(?:\s+|\b)(?:const|volatile|noexcept|override|final|mutable|constexpr|consteval|try|&&|&)\s*$")


def _skip_access_labels(head: str) -> int:
    """Offset of the head's declaration after any leading `public:`-style labels."""
    pos = 0
    while True:
        m = _ACCESS.match(head, pos)
        if not m:
            return pos
        pos = m.end()


def _strip_template(head: str) -> str:
    """The head without a leading `template <...>` (balanced angle brackets)."""
    m = re.match(r"\s*template\s*<", head)
    if not m:
        return head
    depth, i = 1, m.end()
    while i < len(head) and depth > 0:
        if head[i] == "<":
            depth += 1
        elif head[i] == ">" and head[i - 1] != "-":
            depth -= 1
        i += 1
    return _strip_template(head[i:])


def _top_level(head: str):
    """Yields (index, char, paren depth before the char) over `head`."""
    depth = 0
    for i, ch in enumerate(head):
        if ch == ")":
            depth -= 1
        yield i, ch, depth
        if ch == "(":
            depth += 1


def _ends_like_parameter_list(head: str) -> bool:
    """`head` ends in `)` once qualifiers, a trailing return type and a requires clause are cut."""
    text = head.rstrip()
    # A requires clause or trailing return type after the parameter list: cut at the last
    # top-level `requires` / `->` whose left side then ends in `)`.
    cuts = [i for i, ch, d in _top_level(text) if d == 0 and ch == "-" and text[i + 1:i + 2] == ">"]
    cuts += [m.start() for m in re.finditer(r"\brequires\b", text)]
    for cut in sorted(cuts, reverse=True):
        if _ends_like_parameter_list(text[:cut]) and text[:cut].rstrip().endswith(")"):
            return True
    while True:
        m = _QUALIFIER.search(text)
        if not m:
            break
        text = text[:m.start()].rstrip()
    return text.endswith(")")


def _has_initialiser_list(head: str) -> bool:
    """`Name(args) [noexcept] : member(x), other{y}` — a constructor about to open its body."""
    text = head.rstrip()
    if not (text.endswith(")") or text.endswith("}")):
        return False
    for i, ch, d in _top_level(text):
        if d == 0 and ch == ":" and text[i - 1:i] != ":" and text[i + 1:i + 2] != ":":
            before = text[:i]
            return _ends_like_parameter_list(before)
    return False


def classify(head: str) -> str:
    """'scope', 'function' or 'initialiser' for the `{` that follows `head`."""
    depth = 0
    for ch in head:
        depth += ch == "("
        depth -= ch == ")"
    if depth > 0:
        return "initialiser"  # a brace inside an argument list
    body = _strip_template(head[_skip_access_labels(head):]).strip()
    if re.match(r"(?:inline\s+)?namespace\b", body) or re.fullmatch(r'extern\s*"[^"]*"', body):
        return "scope"
    function_like = _ends_like_parameter_list(body) or _has_initialiser_list(body)
    if re.match(r"(?:(?:typedef|friend)\s+)?(?:class|struct|union|enum)\b", body) and not function_like:
        return "scope"
    if function_like:
        return "function"
    if re.search(r"=\s*\[[^\]]*\]\s*(?:mutable\s*)?$", body):
        return "function"  # `auto f = [&] { ... };`
    return "initialiser"


_NOT_A_NAME = {"decltype", "sizeof", "alignof", "alignas", "noexcept", "requires", "__attribute__",
               "if", "for", "while", "switch", "return"}


def function_name(head: str) -> str:
    """A readable name for the function `head` declares (display only)."""
    body = " ".join(_strip_template(head[_skip_access_labels(head):]).split())
    lam = re.match(r"(?:[\w:<>,*&\s]*?\s)?(\w+)\s*=\s*\[", body)
    if lam and "(" not in body[:lam.end()]:
        return lam.group(1) + " (lambda)"
    angle = 0
    for m in re.finditer(r"[<>]|(operator\s*(?:\(\)|\[\]|[^\s\w(]+|\s+[\w:]+)|~?[A-Za-z_]\w*(?:\s*::\s*~?[A-Za-z_]\w*)*)\s*\(",
                         body):
        tok = m.group(0)
        if tok == "<":
            angle += 1
            continue
        if tok == ">":
            angle = max(0, angle - 1)
            continue
        name = m.group(1)
        if angle or name in _NOT_A_NAME:
            continue
        name = re.sub(r"\s+", "", name) if not name.startswith("operator ") else name
        if re.fullmatch(r"(?:TYPED_)?TEST(?:_[A-Z]+)?", name):  # TEST(Suite, Name), TEST_F(...): keep the arguments
            close = body.find(")", m.end())
            return name + "(" + body[m.end():close].strip() + ")"
        return name
    return body[:60]


# ---- scanning --------------------------------------------------------------------------

def _match_braces(code: str) -> dict[int, int]:
    match, stack = {}, []
    for i, ch in enumerate(code):
        if ch == "{":
            stack.append(i)
        elif ch == "}":
            if not stack:
                raise UnbalancedBraces(f"line {code.count(chr(10), 0, i) + 1}: '}}' without '{{'")
            match[stack.pop()] = i
    if stack:
        raise UnbalancedBraces(f"line {code.count(chr(10), 0, stack[-1]) + 1}: '{{' never closed")
    return match


def functions_in(path: str, text: str) -> list[Function]:
    code = blank_non_code(text)
    match = _match_braces(code)
    def line(offset: int) -> int:
        return code.count("\n", 0, offset) + 1

    found: list[Function] = []

    def scan(start: int, end: int) -> None:
        head_start = start
        i = start
        while i < end:
            ch = code[i]
            if ch == ";":
                head_start = i + 1
            elif ch == "{":
                close = match[i]
                head = code[head_start:i]
                kind = classify(head)
                if kind == "scope":
                    scan(i + 1, close)
                    head_start = close + 1
                elif kind == "function" and re.match(r"\s*catch\b", head) and found and found[-1].end == line(head_start):
                    found[-1].end = line(close)  # a handler of a function-try-block: the function goes on
                    head_start = close + 1
                elif kind == "function":
                    skip = _skip_access_labels(head)
                    first = head_start + skip + (len(head) - skip - len(head[skip:].lstrip()))
                    found.append(Function(path, line(first), line(close), function_name(head)))
                    head_start = close + 1
                # an initialiser: skipped, the head runs on to its `;`
                i = close + 1
                continue
            i += 1

    scan(0, len(code))
    return found


def source_files(paths: list[str]) -> list[str]:
    files = []
    for p in paths:
        if os.path.isfile(p):
            files.append(p)
        elif os.path.isdir(p):
            for root, dirs, names in os.walk(p):
                dirs.sort()
                files += [os.path.join(root, n) for n in sorted(names) if n.endswith(EXTENSIONS)]
        else:
            raise FileNotFoundError(p)
    return files


# ---- self test -------------------------------------------------------------------------

_SELF_TEST = r'''
#include <string>   // {
#define OPEN {
namespace a::b {
namespace {
constexpr long kBig = 1'000'000;   // not a char literal
extern "C" {
int c_api(void) { return 0; }
}
extern "C" int LLVMFuzzerTestOneInput(const char* d) { return 0; }
const char* kBrace = "}{";
const char kOpen = '{';
const char* kRaw = R"x(} ")" {)x";
std::vector<int> kList{1, 2, 3};
struct S : Base<int> {
  int x{0};
 public:
  S() : x_{1}, y_(2) {
    run([] { return 1; });
  }
  [[nodiscard]] bool ok() const noexcept { return true; }
  auto tail(int a) -> std::vector<int> {
    return {a};
  }
  template <typename T>
  T twice(T t) requires std::integral<T> {
    /* } */ return t + t;
  }
};
enum class E : int { A, B };
}  // namespace
int free_function(int a,
                  int b) {
  if (a) {
    return b;
  }
  return a;
}
const auto on_epoch = [&](int e) {
  return e;
};
TEST(Suite, Case) {
  EXPECT_EQ(1, 1);
}
void guarded() try {
  run();
} catch (const std::exception&) {
  recover();
}
}  // namespace a::b
'''

_SELF_TEST_EXPECTED = [("c_api", 8, 1), ("LLVMFuzzerTestOneInput", 10, 1), ("S", 18, 3), ("ok", 21, 1),
                       ("tail", 22, 3), ("twice", 25, 4), ("free_function", 32, 7), ("on_epoch (lambda)", 39, 3),
                       ("TEST(Suite, Case)", 42, 3), ("guarded", 45, 5)]


def self_test() -> int:
    got = [(f.name, f.line, f.length) for f in functions_in("<self-test>", _SELF_TEST)]
    if got != _SELF_TEST_EXPECTED:
        print("self-test failed:\n  got      " + repr(got) + "\n  expected " + repr(_SELF_TEST_EXPECTED))
        return 1
    print(f"self-test passed ({len(got)} functions)")
    return 0


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("paths", nargs="*", help="folders (searched recursively) or files")
    parser.add_argument("--max", type=int, default=100, help="longest allowed function in lines (default 100)")
    parser.add_argument("--top", type=int, default=0, help="also list the K longest functions, over --max or not")
    parser.add_argument("--self-test", action="store_true", help="check the scanner on built-in C++ and exit")
    args = parser.parse_args(argv)
    if args.self_test:
        return self_test()
    if not args.paths:
        parser.error("give at least one folder or file")
    try:
        files = source_files(args.paths)
    except FileNotFoundError as e:
        print(f"check-function-length: {e}: no such file or folder", file=sys.stderr)
        return 2
    everything: list[Function] = []
    status = 0
    for path in files:
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
        try:
            everything += functions_in(path, text)
        except UnbalancedBraces as e:
            print(f"{path}: {e} (braces do not balance across #if branches?)", file=sys.stderr)
            status = 2
    everything.sort(key=lambda f: (-f.length, f.path, f.line))
    over = [f for f in everything if f.length > args.max]
    for f in over:
        print(f"{f.path}:{f.line}: {f.name}: {f.length} lines")
    if args.top > 0:
        print(f"the {min(args.top, len(everything))} longest:")
        for f in everything[:args.top]:
            print(f"  {f.path}:{f.line}: {f.name}: {f.length} lines")
    longest = f"; longest {everything[0].path}:{everything[0].line} {everything[0].name} " \
              f"({everything[0].length} lines)" if everything else ""
    print(f"{len(over)} of {len(everything)} functions in {len(files)} files over {args.max} lines{longest}")
    if status:
        return status
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
