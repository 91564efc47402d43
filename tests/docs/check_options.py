#!/usr/bin/env python3
"""The README's command table and docs/cli.md list every option each subcommand takes (issue 13,
"A user's first hour"): the options are read from `gyroflip CMD --help`, so a new flag without docs
fails this test.   Usage: check_options.py SOURCE_DIR GYROFLIP
"""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(sys.argv[1])
exe = sys.argv[2]
readme = (root / "README.md").read_text(encoding="utf-8")
cli_md = (root / "docs" / "cli.md").read_text(encoding="utf-8")
main_help = subprocess.run([exe, "--help"], capture_output=True, text=True, check=True).stdout
commands = re.findall(r"^  ([a-z][a-z0-9-]*)\s", main_help.split("Subcommands:")[-1], re.M)
problems = []


def options_of(cmd):
    text = subprocess.run([exe, cmd, "--help"], capture_output=True, text=True, check=True).stdout
    # Option names start a line of the Options: list (`  -o,--output TEXT ...`, `  --json`).
    names = set()
    for line in text.splitlines():
        m = re.match(r"^\s+((?:-[a-zA-Z],)?--[a-z][a-z0-9-]*)", line)
        if m:
            names.update(n for n in m.group(1).split(",") if n.startswith("--"))
    names.discard("--help")
    return names


for cmd in commands:
    row = re.search(rf"^\| `gyroflip {re.escape(cmd)}[ `].*$", readme, re.M)
    section = re.search(rf"^### `gyroflip {re.escape(cmd)}[ `].*?(?=^### |\Z)", cli_md, re.M | re.S)
    if not row:
        problems.append(f"README.md: no row for `gyroflip {cmd}` in the command table")
    if not section:
        problems.append(f"docs/cli.md: no section `### gyroflip {cmd}`")
    for opt in sorted(options_of(cmd)):
        pat = re.compile(re.escape(opt) + r"(?![a-z0-9-])")
        if row and not pat.search(row.group(0)):
            problems.append(f"README.md: `gyroflip {cmd}` row does not list {opt}")
        if section and not pat.search(section.group(0)):
            problems.append(f"docs/cli.md: section `gyroflip {cmd}` does not list {opt}")
for p in problems:
    print(p)
print(f"{len(commands)} commands checked, {len(problems)} problems")
sys.exit(1 if problems else 0)
