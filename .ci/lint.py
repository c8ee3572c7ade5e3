#!/usr/bin/env python3
"""softbench's style checks, each an error when it finds anything:

  format  clang-format --dry-run --Werror on every C++ source (.clang-format)
  tidy    clang-tidy on every library and program source (.clang-tidy), with
          the build's compile_commands.json; any warning fails
  js      ESLint on report/*.js (report/eslint.config.js), installed with the
          report's assets by scripts/bootstrap.sh

Usage: lint.py ROOT [--build DIR] [--only format,tidy,js] [FILE ...]
Given FILEs, only those are checked. Prints each finding and exits 1 when
there is any; exits 0 when the house is clean.
"""
import argparse
import concurrent.futures
import os
import pathlib
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
        problems += check_tidy(root, build, chosen({".cc"}, TIDY_FOLDERS))
    if "js" in stages:
        problems += check_js(root, [f for f in given if f.suffix == ".js"])
    for problem in problems:
        print(problem)
    print(f"lint ({args.only}): " +
          (f"{len(problems)} finding(s)" if problems else "clean"))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
