#!/usr/bin/env python3
"""CI check: every relative Markdown link in README.md, DEVELOPERS.md, docs/**/*.md and
examples/**/*.md points to a file that exists and, when it names an anchor (`page.md#anchor`),
to a heading of that page (GitHub's anchor rule: lower case, punctuation but `-` and `_`
dropped, spaces to `-`) or an explicit `<a id="…">`.

    scripts/check-doc-links.py        (exit 1 with one line per dead link)

External links (http:, https:, mailto:) are not checked. Standard library only; < 1 s.
"""
import os
import re
import sys

LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)|!\[[^\]]*\]\(([^)\s]+)\)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^\s*(```|~~~)")


def slug(title):
    """GitHub's heading anchor."""
    t = re.sub(r"<[^>]+>", "", title).strip().lower()
    t = re.sub(r"[^\w\- ]", "", t, flags=re.UNICODE)
    return t.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        found, counts, fenced = set(), {}, False
        for line in open(path, encoding="utf-8"):
            if FENCE.match(line):
                fenced = not fenced
                continue
            if fenced:
                continue
            m = HEADING.match(line)
            if m:
                s = slug(m.group(2))
                n = counts.get(s, 0)
                counts[s] = n + 1
                found.add(s if n == 0 else f"{s}-{n}")
            found.update(re.findall(r"<a (?:id|name)=\"([^\"]+)\"", line))
        cache[path] = found
    return cache[path]


def md_files(root):
    out = [os.path.join(root, f) for f in ("README.md", "DEVELOPERS.md") if os.path.exists(os.path.join(root, f))]
    for top in ("docs", "examples", "tests/data", "models", "scenes"):
        for d, _, files in os.walk(os.path.join(root, top)):
            out += [os.path.join(d, f) for f in sorted(files) if f.endswith(".md")]
    return out


def check(path, root):
    problems, fenced = [], False
    for n, line in enumerate(open(path, encoding="utf-8"), 1):
        if FENCE.match(line):
            fenced = not fenced
        if fenced:
            continue
        for m in LINK.finditer(re.sub(r"`[^`]*`", "", line)):
            target = m.group(1) or m.group(2)
            if re.match(r"^[a-z]+:", target):
                continue
            file_part, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
            where = f"{os.path.relpath(path, root)}:{n}"
            if not os.path.exists(dest):
                problems.append(f"{where}: {target}: no file {os.path.relpath(dest, root)}")
            elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
                problems.append(f"{where}: {target}: no heading #{anchor} in {os.path.relpath(dest, root)}")
    return problems


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    files = md_files(root)
    problems = [p for f in files for p in check(f, root)]
    for p in problems:
        print(f"doc-links: {p}")
    print(f"doc-links: {len(files)} files, {len(problems)} dead links")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
