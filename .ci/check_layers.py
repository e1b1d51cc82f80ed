#!/usr/bin/env python3
"""Checks the project's #include lines against the layer table of docs/architecture.md.

    python3 .ci/check_layers.py [REPO_ROOT]

The table between the `<!-- layers: begin -->` and `<!-- layers: end -->` markers lists, per
top-level folder, the folders it may include. Every `#include "folder/..."` in a .h or .cpp
file under a listed folder must name the folder itself or one the table allows. Fails (exit
1) on every include the table forbids, on a folder holding C++ code that the table does not
list, and on a listed folder that does not exist; prints each finding as file:line.
Exit 2 when the document or its table cannot be read.
"""
import pathlib
import re
import sys

BEGIN, END = "<!-- layers: begin -->", "<!-- layers: end -->"
INCLUDE = re.compile(r'^\s*#\s*include\s+"([A-Za-z0-9_.-]+)/')
SKIP_DIRS = {".git", "build", "data", "docs", "cmake", "node_modules"}


def read_table(doc: pathlib.Path) -> dict[str, set[str]]:
    text = doc.read_text(encoding="utf-8")
    if BEGIN not in text or END not in text:
        sys.exit(f"{doc}: the layer table markers {BEGIN} / {END} are missing")
    rules: dict[str, set[str]] = {}
    for n, line in enumerate(text.split(BEGIN, 1)[1].split(END, 1)[0].splitlines(), 1):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 2 or not cells[0].startswith("`"):
            continue  # header, separator, blank
        folder = cells[0].strip("`")
        if folder in rules:
            sys.exit(f"{doc}: layer table: folder `{folder}` is listed twice")
        rules[folder] = set(re.findall(r"`([^`]+)`", cells[1]))
    if not rules:
        sys.exit(f"{doc}: the layer table between the markers has no rows")
    for folder, allowed in rules.items():
        unknown = allowed - rules.keys()
        if unknown:
            sys.exit(f"{doc}: layer table: `{folder}` may include unknown "
                     f"{', '.join(sorted(unknown))}")
    return rules


def code_folders(root: pathlib.Path) -> set[str]:
    found = set()
    for p in root.iterdir():
        if p.is_dir() and p.name not in SKIP_DIRS and not p.name.startswith("."):
            if any(f.suffix in (".h", ".cpp") for f in p.rglob("*")):
                found.add(p.name)
    return found


def main() -> int:
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    rules = read_table(root / "docs" / "architecture.md")
    problems = []
    for folder in sorted(code_folders(root) - rules.keys()):
        problems.append(f"{folder}/: holds C++ code but docs/architecture.md has no row for it")
    for folder in sorted(rules.keys() - code_folders(root)):
        problems.append(f"docs/architecture.md: lists `{folder}`, which holds no C++ code")
    checked = 0
    for folder, allowed in sorted(rules.items()):
        base = root / folder
        if not base.is_dir():
            continue
        for f in sorted(base.rglob("*")):
            if f.suffix not in (".h", ".cpp") or not f.is_file():
                continue
            for n, line in enumerate(f.read_text(encoding="utf-8").splitlines(), 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                checked += 1
                target = m.group(1)
                if target == folder or target in allowed:
                    continue
                # A test beside its code may also use the shared test helpers.
                if target == "tests" and f.name.endswith("_test.cpp"):
                    continue
                if target not in rules:
                    continue  # a third-party header with a folder (e.g. "gtest/...")
                problems.append(f"{f.relative_to(root)}:{n}: {folder}/ may not include "
                                f"{target}/ (docs/architecture.md): {line.strip()}")
    for p in problems:
        print(p)
    print(f"check_layers: {checked} project includes in {len(rules)} folders, "
          f"{len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
