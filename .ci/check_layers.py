#!/usr/bin/env python3
"""The house rules of softbench's libraries (README, "Layout"), checked from
the #include lines and the CMake link lists. Prints every broken rule as
`file:line: rule` and exits 1; exits 0 when the house is in order.

Usage: check_layers.py [REPOSITORY_ROOT]   (default: this script's parent)
"""
import pathlib
import re
import sys

# Each library, the folder it lives in, and the libraries it may use. A
# library may use what its allowed libraries may use (the flow is one way:
# util -> model -> calibration | vision -> formats -> ... -> commands).
LIBRARIES = {
    "util": ("util", set()),
    "model": ("model", set()),
    "calibration": ("calibration", {"model", "util"}),
    "vision": ("vision", {"model", "util"}),
    "formats": ("pipelines/formats", {"model", "util"}),
    "measurement": ("pipelines/measurement",
                    {"formats", "vision", "calibration"}),
    "validation": ("pipelines/validation", {"measurement"}),
    "characterisation": ("pipelines/characterisation",
                         {"formats", "calibration"}),
    "synthetic": ("pipelines/synthetic",
                  {"formats", "vision", "calibration", "characterisation"}),
    "targets": ("pipelines/targets", {"vision", "calibration"}),
    "reports": ("pipelines/reports", {"validation", "characterisation"}),
    "commands": ("pipelines/commands",
                 {"reports", "synthetic", "validation", "characterisation",
                  "measurement", "formats", "vision", "calibration",
                  "targets"}),
}
# Pairs that must never meet, whatever else changes (the rules).
FORBIDDEN = [
    ("validation", "characterisation",
     "validation/ and characterisation/ do not know each other"),
    ("characterisation", "validation",
     "validation/ and characterisation/ do not know each other"),
    ("synthetic", "measurement",
     "synthetic/ never depends on measurement/"),
    ("synthetic", "validation", "synthetic/ never depends on validation/"),
]
# Headers only one library may include.
EXCLUSIVE_HEADERS = [
    (re.compile(r"#include\s*<CLI/"), "commands",
     "only commands/ uses CLI11"),
    (re.compile(r"#include\s*<spdlog/"), "commands",
     "only commands/ uses spdlog"),
    (re.compile(r"#include\s*<lib(av|sw)[a-z]*/"), "vision",
     "FFmpeg headers only in vision/"),
    (re.compile(r"#include\s*<opencv2/"), None,
     "model/ depends on Eigen only (no OpenCV)"),
]
STDOUT = re.compile(r"std::cout|\bprintf\s*\(|\bputs\s*\(|\bstdout\b")
# Libraries never print: stderr is the command line's (progress, errors).
STDERR = re.compile(r"std::cerr|std::clog|\bstderr\b|STDERR_FILENO")
# Header-only helpers every library may include.
FOR_EVERY_LIBRARY = {"util/check.h", "util/join_names.h"}
EXCLUSIVE_LINKS = [
    (re.compile(r"CLI11::"), "commands", "only commands/ links CLI11"),
    (re.compile(r"spdlog::"), "commands", "only commands/ links spdlog"),
    (re.compile(r"PkgConfig::(FFMPEG|AV)"), "vision",
     "only vision/ links FFmpeg"),
]


def closure(name):
    """Every library `name` may use, directly or through another."""
    seen, todo = set(), [name]
    while todo:
        for dep in LIBRARIES[todo.pop()][1]:
            if dep not in seen:
                seen.add(dep)
                todo.append(dep)
    return seen


def library_of_include(path):
    for name, (folder, _) in LIBRARIES.items():
        if path.startswith(folder + "/"):
            return name
    return None


def target_links(text):
    """{target: [(library, line)]} of softbench libraries and link tokens."""
    links = {}
    for m in re.finditer(r"target_link_libraries\(\s*(\S+)([^)]*)\)", text):
        line = text.count("\n", 0, m.start()) + 1
        tokens = [(tok, line + m.group(0).count("\n", 0, m.group(0).find(tok)))
                  for tok in m.group(2).split()]
        links.setdefault(m.group(1), []).extend(tokens)
    return links


def check_sources(root, errors):
    for name, (folder, _) in LIBRARIES.items():
        allowed = closure(name) | {name}
        for source in sorted((root / folder).glob("*.*")):
            if source.suffix not in (".h", ".cc", ".in"):
                continue
            rel = source.relative_to(root)
            for number, line in enumerate(source.read_text().splitlines(), 1):
                where = f"{rel}:{number}"
                m = re.match(r'\s*#include\s*"([^"]+)"', line)
                if m and m.group(1) not in FOR_EVERY_LIBRARY:
                    used = library_of_include(m.group(1))
                    if used and used not in allowed:
                        errors.append(f"{where}: {name}/ may not use {used}/ "
                                      f"({m.group(1)})")
                    for a, b, rule in FORBIDDEN:
                        if name == a and used == b:
                            errors.append(f"{where}: {rule}")
                for pattern, owner, rule in EXCLUSIVE_HEADERS:
                    if pattern.search(line) and (
                            (owner is None and name == "model") or
                            (owner is not None and name != owner)):
                        errors.append(f"{where}: {rule}")
                code = line.split("//")[0]
                if name != "commands" and STDOUT.search(code):
                    errors.append(f"{where}: only commands/ writes to stdout")
                if (name != "commands" and STDERR.search(code) and
                        rel.as_posix() != "util/check.h"):
                    errors.append(f"{where}: libraries never print; only "
                                  "commands/ writes to stderr")


def check_links(root, errors):
    for name, (folder, _) in LIBRARIES.items():
        cmake = root / folder / "CMakeLists.txt"
        if not cmake.exists():
            errors.append(f"{folder}/CMakeLists.txt: missing")
            continue
        text = cmake.read_text()
        allowed = closure(name) | {name}
        for target, tokens in target_links(text).items():
            for token, line in tokens:
                where = f"{folder}/CMakeLists.txt:{line}"
                if token.startswith("softbench_"):
                    used = token[len("softbench_"):]
                    if used in LIBRARIES and used not in allowed:
                        errors.append(f"{where}: {name}/ may not link {token}")
                for pattern, owner, rule in EXCLUSIVE_LINKS:
                    if pattern.search(token) and name != owner:
                        errors.append(f"{where}: {rule}")


def check_benchmarks(root, errors):
    """Each benchmark links the smallest set of libraries that gives it every
    header it includes: no library another linked one already brings, and
    none it does not use."""
    cmake = root / "bench" / "CMakeLists.txt"
    text = cmake.read_text()
    for m in re.finditer(r"add_executable\(\s*(\S+)\s+(\S+\.cc)", text):
        target, source = m.group(1), m.group(2)
        includes = {library_of_include(i) for i in re.findall(
            r'#include\s*"([^"]+)"', (root / "bench" / source).read_text())}
        needed = {lib for lib in includes if lib}
        smallest = {lib for lib in needed
                    if not any(lib in closure(o) for o in needed if o != lib)}
        links = target_links(text).get(target, [])
        linked = {t[len("softbench_"):] for t, _ in links
                  if t.startswith("softbench_")}
        line = links[0][1] if links else 1
        if linked != smallest:
            errors.append(
                f"bench/CMakeLists.txt:{line}: {target} links "
                f"{sorted(linked)} but needs exactly {sorted(smallest)}")


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else
                        pathlib.Path(__file__).resolve().parent.parent)
    errors = []
    check_sources(root, errors)
    check_links(root, errors)
    check_benchmarks(root, errors)
    for error in errors:
        print(error)
    if errors:
        print(f"check_layers: {len(errors)} broken rule(s); see README, "
              "\"Layout\"")
        return 1
    print("check_layers: every library keeps to its place")
    return 0


if __name__ == "__main__":
    sys.exit(main())
