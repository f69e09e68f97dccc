#!/usr/bin/env python3
"""CI check: the generated results and every quote of them agree with docs/results/results.json.

    scripts/results/check_markers.py

Fails (exit 1, one line per problem) when
  - a `<!-- results:NAME -->` … `<!-- /results -->` block in README.md, DEVELOPERS.md or docs/*.md
    differs from what the JSON renders for NAME (someone edited a figure by hand, or the JSON
    changed without `make results` rewriting the quotes: run scripts/results/results.py --fill-only),
  - NAME is not a block of the JSON,
  - docs/results/<part>.md differs from what the JSON renders for that part.
Checks agreement only, never the timings themselves. Runs nothing; standard library only.
"""
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import render  # noqa: E402


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    path = os.path.join(root, render.JSON_PATH)
    if not os.path.exists(path):
        print(f"results-markers: {render.JSON_PATH} missing (run `make results`)")
        return 1
    data = json.load(open(path))
    named = render.blocks_by_name(data)
    problems, quotes = [], 0
    for doc in render.doc_files(root):
        rel = os.path.relpath(doc, root)
        text = open(doc).read()
        opened = len(re.findall(r"<!-- results:[a-z0-9-]+ -->", text))
        if opened != len(render.MARKER.findall(text)):
            problems.append(f"{rel}: a `<!-- results:NAME -->` marker without its own line or its `<!-- /results -->`")
        for m in render.MARKER.finditer(text):
            quotes += 1
            line = text[:m.start()].count("\n") + 1
            if m.group(1) not in named:
                problems.append(f"{rel}:{line}: results:{m.group(1)} is not a block of {render.JSON_PATH}")
                continue
            record, block = named[m.group(1)]
            if m.group(2) != render.quote(record, block, rel):
                problems.append(f"{rel}:{line}: results:{m.group(1)} differs from {render.JSON_PATH} "
                                "(scripts/results/results.py --fill-only rewrites it)")
    for name, record in data["parts"].items():
        md = os.path.join(root, render.RESULTS_DIR, name + ".md")
        if not os.path.exists(md) or open(md).read() != render.part_markdown(record):
            problems.append(f"{os.path.relpath(md, root)}: differs from {render.JSON_PATH}")
    index = os.path.join(root, render.RESULTS_DIR, "README.md")
    if not os.path.exists(index) or open(index).read() != render.index_markdown(data):
        problems.append(f"{os.path.relpath(index, root)}: differs from {render.JSON_PATH}")
    for p in problems:
        print(f"results-markers: {p}")
    print(f"results-markers: {quotes} quotes, {len(data['parts'])} parts, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
