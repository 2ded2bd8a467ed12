#!/usr/bin/env python3
"""Checks that what docs/*.md cite exists in the repository, so the documents do not rot when
files move:

  - every `path/with/slash` or `file.ext` in backticks: a path from the repository root or from
    the document's folder (globs allowed), or, for a bare file name, a file of that name
    somewhere in the tree;
  - every markdown link target [text](target) that is not a URL: relative to the document;
  - every `Class::member` in backticks: both names occur in src/; every other identifier in
    backticks that has an underscore or an inner capital (`add_psd_correction`, `LocalViews`):
    it occurs in src/, a CMakeLists.txt or a scene file;
  - every commit id in backticks (7 to 40 hex digits, with a digit and a letter): a commit of
    this repository (skipped outside a git checkout).

Prints each missing reference with its document and line; exit status 1 if there is one.
Usage: check_doc_paths.py [document.md ...]   (default: docs/design.md and docs/README.md)
"""
import glob
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXTENSIONS = (".hpp", ".cpp", ".cu", ".cuh", ".h", ".md", ".json", ".opts", ".py", ".sh",
              ".txt", ".in", ".slurm", ".csv", ".msh", ".obj", ".stl")


def in_git_checkout():
    try:
        return subprocess.run(["git", "rev-parse", "--git-dir"], cwd=ROOT, capture_output=True).returncode == 0
    except FileNotFoundError:
        return False


def repository_files(git):
    """Files of the source tree: git's list (tracked and not ignored), or a walk without git."""
    if git:
        out = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                             capture_output=True, text=True, check=True).stdout
        return [line for line in out.splitlines() if line]
    found = []
    for folder, dirs, names in os.walk(ROOT):
        dirs[:] = [d for d in dirs if not d.startswith(".") and not d.startswith("build")]
        found += [os.path.relpath(os.path.join(folder, n), ROOT) for n in names]
    return found


def source_text():
    parts = []
    for path in glob.glob(os.path.join(ROOT, "src", "**", "*"), recursive=True):
        if os.path.isfile(path) and path.endswith((".hpp", ".cpp", ".cu", ".cuh", ".h", ".in")):
            with open(path, encoding="utf-8", errors="replace") as f:
                parts.append(f.read())
    return "\n".join(parts)


def build_text():
    parts = []
    for pattern in ("CMakeLists.txt", "src/**/CMakeLists.txt", "scenes/**/*.json", "scenes/**/*.opts"):
        for path in glob.glob(os.path.join(ROOT, pattern), recursive=True):
            with open(path, encoding="utf-8", errors="replace") as f:
                parts.append(f.read())
    return "\n".join(parts)


_known_commits = {}


def is_commit(token):
    if token not in _known_commits:
        _known_commits[token] = subprocess.run(["git", "cat-file", "-e", token + "^{commit}"], cwd=ROOT,
                                               capture_output=True).returncode == 0
    return _known_commits[token]


ENGINEER_DOCUMENTS = ("design.md", "README.md")


def main(argv):
    # The engineers' documents cite code by path and name; the user references (scenes.md,
    # output.md, ...) name output files and keys that exist only at run time, so they are not
    # checked by default.
    documents = argv[1:] or [os.path.join(ROOT, "docs", d) for d in ENGINEER_DOCUMENTS]
    git = in_git_checkout()
    files = repository_files(git)
    basenames = {os.path.basename(f) for f in files}
    src = source_text()
    src_and_build = src + "\n" + build_text()
    problems = []
    checked = 0
    for doc in documents:
        doc_dir = os.path.dirname(os.path.abspath(doc))
        with open(doc, encoding="utf-8") as f:
            lines = f.read().splitlines()
        for number, line in enumerate(lines, 1):
            where = f"{os.path.relpath(doc, ROOT)}:{number}"
            for target in re.findall(r"\]\(([^)\s]+)\)", line):
                if re.match(r"[a-z]+://", target) or target.startswith("#"):
                    continue
                checked += 1
                if not os.path.exists(os.path.normpath(os.path.join(doc_dir, target.split("#")[0]))):
                    problems.append(f"{where}: link target {target} does not exist")
            for token in re.findall(r"`([^`\s]+)`", line):
                token = token.rstrip(".,;:")
                if re.fullmatch(r"[0-9a-f]{7,40}", token) and re.search(r"[0-9]", token) and \
                        re.search(r"[a-f]", token):
                    if not git:
                        continue  # a source tree without its history: commits cannot be checked
                    checked += 1
                    if not is_commit(token):
                        problems.append(f"{where}: commit {token} is not in this repository")
                    continue
                member = re.fullmatch(r"(?:\w+::)*(\w+)::(\w+)", token)
                if member:
                    checked += 1
                    for name in member.groups():
                        if not re.search(r"\b" + re.escape(name) + r"\b", src):
                            problems.append(f"{where}: {name} (of {token}) does not occur in src/")
                    continue
                if re.fullmatch(r"[A-Za-z_]\w*", token) and ("_" in token or re.search(r"[a-z][A-Z]", token)):
                    checked += 1
                    if not re.search(r"\b" + re.escape(token) + r"\b", src_and_build):
                        problems.append(f"{where}: {token} does not occur in src/, CMake files or scenes/")
                    continue
                if any(c in token for c in "<>()=$") or token.startswith("-"):
                    continue
                looks_like_path = "/" in token and re.fullmatch(r"[\w.*\-/]+", token) and not token.startswith("/")
                looks_like_file = re.fullmatch(r"[\w.\-]+", token) and token.endswith(EXTENSIONS)
                if not (looks_like_path or looks_like_file):
                    continue
                checked += 1
                if "/" in token:
                    path = token.rstrip("/")
                    if not glob.glob(os.path.join(ROOT, path)) and not glob.glob(os.path.join(doc_dir, path)):
                        problems.append(f"{where}: path {token} does not exist")
                elif token not in basenames and not glob.glob(os.path.join(doc_dir, token)):
                    problems.append(f"{where}: no file named {token} in the repository")
    for p in problems:
        print(p)
    print(f"{checked} references checked in {len(documents)} document(s), {len(problems)} missing")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
