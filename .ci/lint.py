#!/usr/bin/env python3
"""softbench's style checks, each an error when it finds anything:

  format  clang-format --dry-run --Werror on every C++ source (.clang-format)
  tidy    clang-tidy on the library and program sources (.clang-tidy), with
          the build's compile_commands.json; any warning fails. Every source
          with --all; otherwise those changed since .ci/tidy_base (a commit
          whose every source was tidied clean) and those that include a
          changed header; every source when that commit is not in the
          repository or the configuration differs from the one it was tidied
          under (.clang-tidy, clang-tidy's version, the compile commands)
  js      ESLint on report/*.js (report/eslint.config.js), installed with the
          report's assets by scripts/bootstrap.sh

Usage: lint.py ROOT [--build DIR] [--only format,tidy,js] [--all]
                 [--list] [--record-base] [FILE ...]
Given FILEs, only those are checked. --list prints the sources tidy would
check and stops. --record-base, after a clean tidy of every source of a
committed tree (--all), writes HEAD to .ci/tidy_base. Prints each finding
and exits 1 when there is any; exits 0 when the house is clean.
"""
import argparse
import concurrent.futures
import hashlib
import json
import os
import pathlib
import re
import subprocess
import sys

# The folders whose C++ is ours (fuzz/ and bench/ included; the build and
# report/node_modules are not).
SOURCE_FOLDERS = ["util", "model", "calibration", "vision", "pipelines",
                  "tests", "bench", "fuzz"]
# clang-tidy runs on what ships: the libraries, the program and the
# benchmarks (the lint preset configures them all). Tests and the fuzz
# targets (built by clang in their own preset) are formatted but not tidied:
# tidying the tests would double the check's time in CI for code no user
# runs.
TIDY_FOLDERS = ["util", "model", "calibration", "vision", "pipelines",
                "bench"]


# The commit whose every tidied source passed, and the digest of the checks'
# configuration they passed under (lint.py --all --record-base).
TIDY_BASE = ".ci/tidy_base"
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def sources(root, folders, suffixes):
    found = []
    for folder in folders:
        for path in sorted((root / folder).rglob("*")):
            if path.suffix in suffixes and path.is_file():
                found.append(path)
    return found


def check_format(root, files):
    problems = []
    for path in files:
        result = subprocess.run(
            ["clang-format", "--dry-run", "--Werror", str(path)],
            capture_output=True, text=True, cwd=root)
        if result.returncode != 0:
            first = result.stderr.strip().splitlines()
            problems.append(f"{path.relative_to(root)}: not clang-formatted"
                            + (f" ({first[0]})" if first else ""))
    return problems


def tidy_one(root, build, path):
    result = subprocess.run(
        ["clang-tidy", "-p", str(build), "--quiet", str(path)],
        capture_output=True, text=True, cwd=root)
    return [line for line in result.stdout.splitlines()
            if ": warning: " in line or ": error: " in line]


def git_lines(root, *args):
    result = subprocess.run(["git", "-C", str(root), *args],
                            capture_output=True, text=True)
    return result.stdout.splitlines() if result.returncode == 0 else None


def tidy_base(root):
    """(commit, configuration digest) from TIDY_BASE, or (None, None)."""
    path = root / TIDY_BASE
    words = path.read_text().split() if path.is_file() else []
    return (words[0], words[1]) if len(words) >= 2 else (None, None)


def configuration_digest(root, build):
    """What, besides a source and its headers, decides what tidy finds in it:
    .clang-tidy, clang-tidy's version and every distinct compile command of
    the build (its paths made relative, its file names left out)."""
    digest = hashlib.sha256((root / ".clang-tidy").read_bytes())
    version = subprocess.run(["clang-tidy", "--version"],
                             capture_output=True, text=True).stdout
    digest.update(re.sub(r"\s+", " ", version).encode())
    flags = set()
    for entry in json.loads((build / "compile_commands.json").read_text()):
        command = entry.get("command") or " ".join(entry["arguments"])
        command = command.replace(entry["file"], "FILE")
        command = re.sub(r" -o \S+", "", command)
        flags.add(command.replace(str(build), "BUILD").replace(
            str(root), "ROOT"))
    for command in sorted(flags):
        digest.update(command.encode() + b"\n")
    return digest.hexdigest()[:16]


def changed_since(root, base):
    """Paths (relative to root) that differ from commit `base` in the working
    tree, untracked ones included; None when git cannot say."""
    if base is None or git_lines(root, "cat-file", "-e",
                                 base + "^{commit}") is None:
        return None
    changed = git_lines(root, "diff", "--name-only", base, "--")
    untracked = git_lines(root, "ls-files", "--others", "--exclude-standard")
    if changed is None or untracked is None:
        return None
    return set(changed) | set(untracked)


def includes_changed(root, source, changed, memo):
    """Whether `source` (relative to root) or a project header it includes,
    directly or through others, is in `changed`."""
    if source in memo:
        return memo[source]
    memo[source] = source in changed  # a cycle's second visit adds nothing
    path = root / source
    if not memo[source] and path.is_file():
        for header in INCLUDE.findall(path.read_text(errors="replace")):
            if (root / header).is_file() and includes_changed(
                    root, header, changed, memo):
                memo[source] = True
                break
    return memo[source]


def tidy_sources(root, build, all_sources):
    """The sources tidy checks (see the module's doc) and why."""
    if not (build / "compile_commands.json").is_file():
        return all_sources, "every source (no compile_commands.json)"
    base, base_digest = tidy_base(root)
    changed = changed_since(root, base)
    if changed is None:
        return all_sources, (f"every source ({TIDY_BASE} names no commit of "
                             "this repository)")
    if base_digest != configuration_digest(root, build):
        return all_sources, ("every source (.clang-tidy, clang-tidy or the "
                             f"compile commands changed since {base[:12]})")
    memo = {}
    chosen = [f for f in all_sources if includes_changed(
        root, f.relative_to(root).as_posix(), changed, memo)]
    return chosen, (f"{len(chosen)} of {len(all_sources)} sources: those "
                    f"changed since {base[:12]}, where every source was "
                    "clean, or including a changed header (--all: every one)")


def record_base_problems(root, args, given):
    """Why --record-base cannot be honoured, found before tidy's long run."""
    if given or not args.all:
        return ["--record-base needs --all and no FILEs"]
    if git_lines(root, "status", "--porcelain") != []:
        return [f"{TIDY_BASE}: not recorded; commit every change first, so "
                "the commit is what was tidied"]
    return []


def record_base(root, build):
    head = git_lines(root, "rev-parse", "HEAD")[0]
    (root / TIDY_BASE).write_text(
        f"{head} {configuration_digest(root, build)}\n"
        "# The commit whose every source was tidied clean, and the digest of\n"
        "# the configuration it was tidied under (.ci/lint.py --all\n"
        "# --record-base); CI tidies the sources changed since.\n")
    print(f"{TIDY_BASE}: {head}")
    return []


def check_tidy(root, build, files):
    if not (build / "compile_commands.json").is_file():
        return [f"{build}/compile_commands.json: missing; configure a preset "
                "first (cmake --preset release)"]
    problems = []
    workers = max(1, os.cpu_count() or 1)
    with concurrent.futures.ThreadPoolExecutor(workers) as pool:
        for lines in pool.map(lambda p: tidy_one(root, build, p), files):
            problems.extend(lines)
    # A header's warning is reported once per file that includes it.
    return sorted(set(problems))


def check_js(root, files):
    eslint = root / "report" / "node_modules" / ".bin" / "eslint"
    if not eslint.is_file():
        return [f"{eslint}: missing; run scripts/bootstrap.sh (it installs "
                "report/ with npm)"]
    targets = [str(f) for f in files] or ["."]
    result = subprocess.run(
        [str(eslint), "--max-warnings", "0", "--no-warn-ignored"] + targets,
        capture_output=True, text=True, cwd=root / "report")
    if result.returncode == 0:
        return []
    return [line for line in result.stdout.splitlines() if line.strip()] or [
        result.stderr.strip()]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("root", type=pathlib.Path)
    parser.add_argument("--build", type=pathlib.Path)
    parser.add_argument("--only", default="format,tidy,js")
    parser.add_argument("--all", action="store_true")
    parser.add_argument("--list", action="store_true")
    parser.add_argument("--record-base", action="store_true")
    parser.add_argument("files", nargs="*", type=pathlib.Path)
    args = parser.parse_intermixed_args()
    root = args.root.resolve()
    build = (args.build or root / "build" / "lint").resolve()
    given = [f.resolve() for f in args.files]

    def chosen(suffixes, folders):
        if given:
            return [f for f in given if f.suffix in suffixes]
        return sources(root, folders, suffixes)

    problems = []
    stages = args.only.split(",")
    if "format" in stages:
        problems += check_format(root, chosen({".cc", ".h"}, SOURCE_FOLDERS))
    if "tidy" in stages:
        files = chosen({".cc"}, TIDY_FOLDERS)
        if not given and not args.all:
            files, why = tidy_sources(root, build, files)
            print(f"tidy: {why}")
        if args.list:
            for f in files:
                print(f.relative_to(root))
            return 0
        unrecordable = (record_base_problems(root, args, given)
                        if args.record_base else [])
        tidy_problems = unrecordable or check_tidy(root, build, files)
        problems += tidy_problems
        if args.record_base and not tidy_problems:
            problems += record_base(root, build)
    if "js" in stages:
        problems += check_js(root, [f for f in given if f.suffix == ".js"])
    for problem in problems:
        print(problem)
    print(f"lint ({args.only}): " +
          (f"{len(problems)} finding(s)" if problems else "clean"))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
