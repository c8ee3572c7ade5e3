#!/usr/bin/env python3
"""The style checks (.ci/lint.py) pass on a copy of part of this tree and
catch a formatting diff, a clang-tidy warning and an ESLint finding each
broken into the copy, as check_layers_test.py does for the layers; and
tidy, given no files, picks the sources changed since .ci/tidy_base and
those including a changed header, or every source when the base or its
configuration is not this tree's.

Usage: lint_test.py REPOSITORY_ROOT
"""
import importlib.util
import json
import pathlib
import shutil
import subprocess
import sys
import tempfile

# A small library's sources stand for the tree: tidying all of it is the
# lint preset's job, not this test's.
TIDY_FILE = "util/text_file.cc"
FORMAT_FILE = "util/statistics.h"
JS_FILE = "report/tune_core.js"


def copy_tree(root, tree):
    shutil.copytree(root / "util", tree / "util")
    for name in (".clang-format", ".clang-tidy"):
        shutil.copy(root / name, tree / name)
    (tree / "report").mkdir()
    for path in (root / "report").glob("*.js"):
        shutil.copy(path, tree / "report" / path.name)
    (tree / "report" / "node_modules").symlink_to(
        root / "report" / "node_modules")
    # The compile database of the copy's one tidied file.
    (tree / "build").mkdir()
    (tree / "build" / "compile_commands.json").write_text(json.dumps([{
        "directory": str(tree),
        "file": str(tree / TIDY_FILE),
        "command": f"c++ -std=c++20 -I{tree} -c {tree / TIDY_FILE}",
    }]))


def lint(root, tree, stage, path):
    return subprocess.run(
        [sys.executable, str(root / ".ci" / "lint.py"), str(tree), "--build",
         str(tree / "build"), "--only", stage, str(tree / path)],
        capture_output=True, text=True)


def load_lint(root):
    spec = importlib.util.spec_from_file_location("lint",
                                                  root / ".ci" / "lint.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def git(tree, *args):
    subprocess.run(["git", "-C", str(tree), "-c", "user.name=lint_test",
                    "-c", "user.email=lint_test@localhost", *args],
                   check=True, capture_output=True)


def check_tidy_selection(root, tree):
    """Failures of tidy's choice of sources in `tree` (a copy of util/)."""
    lint = load_lint(root)
    build = tree / "build"
    every = lint.sources(tree, ["util"], {".cc"})

    def chosen():
        files, _ = lint.tidy_sources(tree, build, every)
        return sorted(f.relative_to(tree).as_posix() for f in files)

    failures = []

    def expect(what, got, wanted):
        if got != wanted:
            failures.append(f"tidy's choice {what}: {got}, expected {wanted}")

    everything = sorted(f.relative_to(tree).as_posix() for f in every)
    expect("without a base", chosen(), everything)
    git(tree, "init", "-q")
    git(tree, "add", "-A")
    git(tree, "commit", "-q", "-m", "base")
    head = subprocess.run(["git", "-C", str(tree), "rev-parse", "HEAD"],
                          capture_output=True, text=True).stdout.strip()
    (tree / ".ci").mkdir(exist_ok=True)
    (tree / lint.TIDY_BASE).write_text(
        f"{head} {lint.configuration_digest(tree, build)}\n")
    expect("with nothing changed", chosen(), [])
    # util/input_file.h is included by text_file.cc, directly and through
    # no other util/ header, and not by parallel_tasks.cc.
    header = tree / "util" / "input_file.h"
    original = header.read_text()
    header.write_text(original + "// changed\n")
    picked = chosen()
    if "util/text_file.cc" not in picked or \
            "util/parallel_tasks.cc" in picked:
        failures.append("tidy's choice after util/input_file.h changed: "
                        f"{picked}, expected text_file.cc and not "
                        "parallel_tasks.cc")
    header.write_text(original)
    (tree / "util" / "new_source.cc").write_text("int x;\n")
    every.append(tree / "util" / "new_source.cc")
    expect("with a new source", chosen(), ["util/new_source.cc"])
    with open(tree / ".clang-tidy", "a") as config:
        config.write("# changed\n")
    expect("with .clang-tidy changed", chosen(), sorted(
        f.relative_to(tree).as_posix() for f in every))
    return failures


def main():
    root = pathlib.Path(sys.argv[1]).resolve()
    failures = []
    breaks = [
        ("format", FORMAT_FILE, "int  badly_spaced =1;\n",
         "not clang-formatted"),
        ("tidy", TIDY_FILE,
         "namespace softbench {\nint not_camel_case() { return 0; }\n}\n",
         "invalid case style for function 'not_camel_case'"),
        ("js", JS_FILE, "const unusedValue = 1;\n",
         "'unusedValue' is assigned a value but never used"),
    ]
    with tempfile.TemporaryDirectory() as scratch:
        tree = pathlib.Path(scratch) / "tree"
        copy_tree(root, tree)
        for stage, path, text, expected in breaks:
            clean = lint(root, tree, stage, path)
            if clean.returncode != 0:
                failures.append(f"{stage}: the unbroken copy fails:\n"
                                + clean.stdout + clean.stderr)
                continue
            original = (tree / path).read_text()
            (tree / path).write_text(original + text)
            broken = lint(root, tree, stage, path)
            (tree / path).write_text(original)
            if broken.returncode == 0 or expected not in broken.stdout:
                failures.append(f"{stage}: {path} broken with {text!r}: "
                                f"expected a failure naming {expected!r}, "
                                f"got:\n{broken.stdout}{broken.stderr}")
        failures += check_tidy_selection(root, tree)
    for failure in failures:
        print(failure)
    print(f"{len(failures)} failure(s): {len(breaks)} broken styles and "
          "tidy's choice of sources checked")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
