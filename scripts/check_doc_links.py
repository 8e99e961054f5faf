#!/usr/bin/env python3
"""Every file the documentation names must exist in the repository.

Checks, from the repository root:
  - in README.md and docs/**/*.md: relative Markdown links ([text](path)) and
    repository paths written out (`src/...`, `docs/...`, `tests/...`, ...,
    with {a,b} alternatives and * wildcards);
  - in the sources (src, include, tests, bench, apps, python, scripts,
    examples): every `docs/....md` they cite, and no citation of documents
    that live outside the repository (design.md, solver-notes.md, ../shared/).

Usage: scripts/check_doc_links.py [REPO_ROOT]; exit status 1 with one line
per broken reference. Run by ctest as Docs.LinksExist (tests/CMakeLists.txt).
"""
import glob
import itertools
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
TOP_DIRS = ("docs", "src", "tests", "include", "bench", "scripts", "apps", "python", "examples", "scenes", "viewer", "cmake")
SOURCE_DIRS = ("src", "include", "tests", "bench", "apps", "python", "scripts", "examples")
SOURCE_EXTS = (".hpp", ".cpp", ".h", ".py", ".sh", ".cmake", ".txt", ".js", ".json")

MD_LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
REPO_PATH = re.compile(r"(?<![\w./-])((?:%s)/[\w./*{},<>-]*)" % "|".join(TOP_DIRS))
DOC_CITE = re.compile(r"(?<![\w/.-])((?:\.\./)*docs/[\w/.-]+\.md)")
# Names that stand for any file, in examples (an error message's file name).
EXAMPLE_NAMES = {"scenes/x.json"}
OUTSIDE = re.compile(r"\bdesign\.md\b|solver-notes\.md|\.\./shared/|\bshared/docs/|the solver notes")


def expand_braces(path):
    """src/a.{hpp,cpp} -> [src/a.hpp, src/a.cpp]."""
    parts = re.split(r"(\{[^{}]*\})", path)
    choices = [p[1:-1].split(",") if p.startswith("{") else [p] for p in parts]
    return ["".join(c) for c in itertools.product(*choices)]


def exists(path, base=ROOT):
    for candidate in expand_braces(path):
        full = os.path.normpath(os.path.join(base, candidate))
        if "*" in candidate:
            if not glob.glob(full):
                return False
        elif not os.path.exists(full):
            return False
    return True


def clean(path):
    path = path.split("#")[0]
    while path and path[-1] in ".,:;)'\"`":
        path = path[:-1]
    return path


def check_markdown(md, problems):
    rel = os.path.relpath(md, ROOT)
    in_code = False
    for number, line in enumerate(open(md, encoding="utf-8"), 1):
        if line.lstrip().startswith("```"):
            in_code = not in_code
            continue
        if in_code:
            continue  # shell examples name build outputs that need not exist
        for target in MD_LINK.findall(line):
            if re.match(r"[a-z]+:", target) or target.startswith("#"):
                continue
            target = clean(target)
            if target and not exists(target, os.path.dirname(md)):
                problems.append(f"{rel}:{number}: link to missing {target}")
        for path in REPO_PATH.findall(line):
            path = clean(path)
            if "<" in path or "node_modules" in path or path in EXAMPLE_NAMES:
                continue  # a placeholder (src/solver/joints/<type>.cpp), installed or made-up files
            if not exists(path):
                problems.append(f"{rel}:{number}: names missing {path}")


def check_sources(problems):
    for top in SOURCE_DIRS:
        for directory, _, files in os.walk(os.path.join(ROOT, top)):
            if "node_modules" in directory:
                continue
            for name in files:
                if not name.endswith(SOURCE_EXTS) or name == os.path.basename(__file__):
                    continue
                path = os.path.join(directory, name)
                rel = os.path.relpath(path, ROOT)
                try:
                    lines = open(path, encoding="utf-8").read().splitlines()
                except UnicodeDecodeError:
                    continue
                for number, line in enumerate(lines, 1):
                    if OUTSIDE.search(line):
                        problems.append(f"{rel}:{number}: cites a document outside the repository: {line.strip()}")
                    for cite in DOC_CITE.findall(line):
                        cite = clean(cite)
                        target = cite if not cite.startswith("../") else os.path.relpath(
                            os.path.normpath(os.path.join(os.path.dirname(path), cite)), ROOT)
                        if not exists(target):
                            problems.append(f"{rel}:{number}: cites missing {cite}")


def main():
    problems = []
    markdown = [os.path.join(ROOT, "README.md")] + sorted(glob.glob(os.path.join(ROOT, "docs", "**", "*.md"), recursive=True))
    for md in markdown:
        check_markdown(md, problems)
        for number, line in enumerate(open(md, encoding="utf-8"), 1):
            if OUTSIDE.search(line):
                problems.append(f"{os.path.relpath(md, ROOT)}:{number}: cites a document outside the repository")
    check_sources(problems)
    for p in problems:
        print(p)
    print(f"check_doc_links: {len(markdown)} documents and the sources checked, {len(problems)} broken references")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
