#!/usr/bin/env python3
"""Every `FACTS §N` that code, docs or the `sensors` listing cites names a section of docs/FACTS.md,
and nothing cites the project's outside notes (METHOD.md, FIELD-NOTES), which a clone of the
repository alone does not have (issue 13 item 21).   Usage: check_fact_refs.py SOURCE_DIR [GYROFLIP]
"""
import json
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(sys.argv[1])
facts = (root / "docs" / "FACTS.md").read_text(encoding="utf-8")
sections = set(re.findall(r"^#+ §([0-9.]+)", facts, re.M))
problems = []
texts = {}
for pattern in ("src/**/*.[ch]pp", "include/**/*.hpp", "apps/**/*.[ch]pp", "docs/*.md", "README.md",
                "tests/**/*.cpp"):
    for p in root.glob(pattern):
        texts[str(p.relative_to(root))] = p.read_text(encoding="utf-8", errors="replace")
if len(sys.argv) > 2:  # what `gyroflip sensors --json` prints cites sources too
    texts["gyroflip sensors --json"] = subprocess.run([sys.argv[2], "sensors", "--json"], check=True,
                                                      capture_output=True, text=True).stdout
    json.loads(texts["gyroflip sensors --json"])
for name, text in texts.items():
    for m in re.finditer(r"FACTS(?:\.md)? §([0-9]+(?:\.[0-9]+)?)", text):
        if m.group(1) not in sections:
            problems.append(f"{name}: cites FACTS §{m.group(1)}, which docs/FACTS.md does not have")
    for m in re.finditer(r"METHOD\.md|FIELD-NOTES", text):
        if name != "docs/FACTS.md" and "shared/docs" not in text[max(0, m.start() - 20):m.start()]:
            problems.append(f"{name}: cites {m.group(0)}, which is not in the repository (use docs/FACTS.md)")
for p in problems:
    print(p)
print(f"{len(texts)} files checked, {len(sections)} sections in docs/FACTS.md, {len(problems)} problems")
sys.exit(1 if problems else 0)
