#!/usr/bin/env python3
"""CheckLayers.FailsWhenARuleIsBroken: breaks each of .ci/check_layers.py's
rules in a copy of the tree and expects the check to fail, naming the
offending file and line. Usage: check_layers_test.py REPOSITORY_ROOT"""
import pathlib
import shutil
import subprocess
import sys
import tempfile

FOLDERS = ["util", "model", "calibration", "vision", "pipelines", "bench"]

# (file, text appended, expected in the check's output)
BREAKS = [
    ("pipelines/formats/test_plan.cc", '#include "vision/video_reader.h"\n',
     "formats/ may not use vision/"),
    ("pipelines/formats/mechanism_io.cc",
     '#include "calibration/force_fit.h"\n', "formats/ may not use calibration/"),
    ("pipelines/validation/validation.cc",
     '#include "pipelines/characterisation/fit_analysis.h"\n',
     "validation/ and characterisation/ do not know each other"),
    ("pipelines/characterisation/fit_analysis.cc",
     '#include "pipelines/validation/validation.h"\n',
     "validation/ and characterisation/ do not know each other"),
    ("pipelines/synthetic/scene_renderer.cc",
     '#include "pipelines/measurement/video_measurement.h"\n',
     "synthetic/ never depends on measurement/"),
    ("pipelines/synthetic/render_timeline.cc",
     '#include "pipelines/validation/validation.h"\n',
     "synthetic/ never depends on validation/"),
    ("pipelines/reports/html_report.cc", "#include <libavutil/base64.h>\n",
     "FFmpeg headers only in vision/"),
    ("pipelines/measurement/video_measurement.cc",
     "#include <spdlog/spdlog.h>\n", "only commands/ uses spdlog"),
    ("pipelines/formats/test_plan.h", "#include <CLI/CLI.hpp>\n",
     "only commands/ uses CLI11"),
    ("pipelines/validation/validation.cc", "void F() { std::cout << 1; }\n",
     "only commands/ writes to stdout"),
    ("util/progress.cc", 'void F() { std::fprintf(stderr, "1"); }\n',
     "libraries never print; only commands/ writes to stderr"),
    ("model/mechanism.cc", "#include <opencv2/core.hpp>\n",
     "model/ depends on Eigen only"),
    ("vision/dot_centre.cc", '#include "calibration/force_fit.h"\n',
     "vision/ may not use calibration/"),
    ("util/csv.cc", '#include "model/units.h"\n', "util/ may not use model/"),
    ("pipelines/formats/CMakeLists.txt",
     "target_link_libraries(softbench_formats PRIVATE softbench_vision)\n",
     "formats/ may not link softbench_vision"),
    ("pipelines/reports/CMakeLists.txt",
     "target_link_libraries(softbench_reports PRIVATE spdlog::spdlog)\n",
     "only commands/ links spdlog"),
    ("bench/CMakeLists.txt",
     "target_link_libraries(model_benchmark PRIVATE softbench_commands)\n",
     "model_benchmark links"),
]


def run_check(root, tree):
    return subprocess.run(
        [sys.executable, str(root / ".ci" / "check_layers.py"), str(tree)],
        capture_output=True, text=True)


def main():
    root = pathlib.Path(sys.argv[1]).resolve()
    failures = []
    with tempfile.TemporaryDirectory() as scratch:
        tree = pathlib.Path(scratch)
        for folder in FOLDERS:
            shutil.copytree(root / folder, tree / folder)
        clean = run_check(root, tree)
        if clean.returncode != 0:
            failures.append("the unbroken copy fails:\n" + clean.stdout)
        for path, text, expected in BREAKS:
            target = tree / path
            original = target.read_text()
            target.write_text(original + text)
            line = original.count("\n") + 1
            result = run_check(root, tree)
            target.write_text(original)
            located = f"{path}:{line}:"
            if result.returncode == 0:
                failures.append(f"{path}: '{text.strip()}' passed the check")
            elif expected not in result.stdout or (
                    path.endswith((".cc", ".h")) and
                    located not in result.stdout):
                failures.append(f"{path}: expected '{located} ... {expected}'"
                                f", got:\n{result.stdout}")
    for failure in failures:
        print(failure)
    print(f"{len(BREAKS) - len(failures)} of {len(BREAKS)} broken rules caught")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
