#!/usr/bin/env python3
"""The style checks (.ci/lint.py) pass on a copy of part of this tree and
catch a formatting diff, a clang-tidy warning and an ESLint finding each
broken into the copy, as check_layers_test.py does for the layers.

Usage: lint_test.py REPOSITORY_ROOT
"""
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
    for failure in failures:
        print(failure)
    print(f"{len(breaks) - len(failures)} of {len(breaks)} broken styles "
          "caught")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
