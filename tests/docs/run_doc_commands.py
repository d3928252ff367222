"""Runs the shell blocks of the given Markdown pages as a reader would: each page's ```sh blocks
in order, in one bash (set -e, so a page's later block may use what an earlier one exported),
from a scratch folder that mirrors the repository's root (its entries linked there, so the
blocks' relative paths work and what they write lands in the scratch folder), with HOME in the
scratch folder and the README's PATH. A block preceded by the line
    <!-- not run by the docs check: REASON -->
is left out and listed with its reason. A sample of output, a plain ``` block whose first line
is "$ COMMAND" and whose rest is what the command prints, preceded by the line
    <!-- output checked by the docs check -->
is checked too: the command is run after the page's blocks and must print that text, up to the
figures that differ from run to run (times, rates and shares; counts must match). Exits non-zero
if any block fails or any output differs, naming the page and the block's first line.

usage: run_doc_commands.py REPOSITORY PAGE.md [PAGE.md ...]
"""

import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

SKIP = re.compile(r"<!-- not run by the docs check: (.+?) -->")
CHECK_OUTPUT = "<!-- output checked by the docs check -->"
# What differs from run to run in a command's output: times, rates, shares, peak memory.
VARYING = [(re.compile(r"\b\d+(\.\d+)? ?[kMG]?rays/s"), "RATE"),
           (re.compile(r"\b\d+(\.\d+)? s\b"), "TIME s"),
           (re.compile(r"\b\d+(\.\d+)?%"), "SHARE%"),
           (re.compile(r"\b\d+(\.\d+)? MB\b"), "MEMORY MB"),
           (re.compile(r"\b\d+(\.\d+)? bytes per sphere\b"), "MEMORY bytes per sphere")]


def blocks(page):
    """(first line number, text, reason to skip or None) of each ```sh block of page."""
    lines = page.read_text().splitlines()
    found, i = [], 0
    while i < len(lines):
        if lines[i].strip() == "```sh":
            start = i
            i += 1
            body = []
            while i < len(lines) and lines[i].strip() != "```":
                body.append(lines[i])
                i += 1
            skip = SKIP.search(lines[start - 1]) if start > 0 else None
            found.append((start + 2, "\n".join(body), skip.group(1) if skip else None))
        i += 1
    return found


def output_samples(page):
    """(line number, command, expected output) of each checked sample of page."""
    lines = page.read_text().splitlines()
    found = []
    for i, line in enumerate(lines):
        if line.strip() == CHECK_OUTPUT and i + 2 < len(lines) and lines[i + 1].strip() == "```":
            command = lines[i + 2]
            if not command.startswith("$ "):
                raise SystemExit(f"{page}:{i + 3}: a checked sample starts with '$ COMMAND'")
            end = lines.index("```", i + 3)
            found.append((i + 3, command[2:], "\n".join(lines[i + 3:end])))
    return found


def normalised(text):
    for pattern, replacement in VARYING:
        text = pattern.sub(replacement, text)
    return text.strip()


def scratch_root(repo, where):
    """A folder whose entries are links to the repository's: the blocks run from there. Its
    build folder is its own, holding only a link to build/release: what the blocks build
    beside it (build/embed, build/rust) starts afresh in every run, never from a cache that a
    run from another folder left."""
    root = Path(where) / "repo"
    root.mkdir()
    for entry in repo.iterdir():
        if entry.name not in (".git", "build"):
            (root / entry.name).symlink_to(entry)
    (root / "build").mkdir()
    (root / "build" / "release").symlink_to(repo / "build" / "release")
    return root


def run_page(repo, page, where):
    root = scratch_root(repo, where)
    home = Path(where) / "home"
    home.mkdir()
    # Physical paths (set -P): a `cd build/release` through the mirror's link lands in the real
    # build tree, so that CMake, which takes the logical working directory, never writes the
    # mirror's paths into it.
    script = ["set -eo pipefail -P"]
    ran, skipped = 0, []
    for line, text, reason in blocks(page):
        first = text.strip().splitlines()[0] if text.strip() else ""
        if reason:
            skipped.append(f"{page.name}:{line}: {first}  ({reason})")
            continue
        script.append(f"echo '--- {page.name}:{line}: '{sh_quote(first)}")
        script.append(text)
        ran += 1
    env = {
        "HOME": str(home),
        "PATH": f"{root}/build/release/render:{root}/build/release/mpi:/usr/sbin:/usr/bin:/sbin:/bin",
        "LANG": "C.UTF-8",
        "TMPDIR": str(where),
    }
    result = subprocess.run(["bash", "-c", "\n".join(script)], cwd=root, env=env)
    code = result.returncode
    for line, command, expected in output_samples(page):
        print(f"--- {page.name}:{line}: $ {command}  (its output checked)", flush=True)
        got = subprocess.run(["bash", "-P", "-c", command], cwd=root, env=env, text=True,
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT).stdout
        ran += 1
        if normalised(got) != normalised(expected):
            print(f"{page.name}:{line}: the output differs from the page's\n page: {expected}\n"
                  f"  got: {got.strip()}")
            code = code or 1
    return code, ran, skipped


def sh_quote(text):
    return "'" + text.replace("'", "'\\''") + "'"


def main(argv):
    repo = Path(argv[1]).resolve()
    failed, total_ran, all_skipped = [], 0, []
    for name in argv[2:]:
        page = repo / name
        with tempfile.TemporaryDirectory(prefix="sphray-docs-") as where:
            code, ran, skipped = run_page(repo, page, where)
        total_ran += ran
        all_skipped += skipped
        if code != 0:
            failed.append(f"{name}: exit {code} (the block or output after the last '---' above)")
    for line in all_skipped:
        print(f"not run: {line}")
    for line in failed:
        print(f"FAILED: {line}")
    print(f"docs: {total_ran} blocks run, {len(all_skipped)} not run, {len(failed)} pages failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
