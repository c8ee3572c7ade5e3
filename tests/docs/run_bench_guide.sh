#!/usr/bin/env bash
# Runs every command of docs/bench-guide.md, in order, as a newcomer would:
# from a scratch folder that holds the repository's samples, with `softbench`
# on the PATH. Also checks that the guide's YAML excerpt is the sample plan's
# own lines, that every picture it shows exists, and that each step wrote
# what the guide says it writes.
# Usage: run_bench_guide.sh SOURCE_DIR SOFTBENCH_BINARY
set -euo pipefail
source_dir=$(realpath "${1:?usage: run_bench_guide.sh SOURCE_DIR SOFTBENCH}")
softbench=$(realpath "${2:?usage: run_bench_guide.sh SOURCE_DIR SOFTBENCH}")
guide="$source_dir/docs/bench-guide.md"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir "$scratch/bin" "$scratch/work"
ln -s "$softbench" "$scratch/bin/softbench"
ln -s "$source_dir/samples" "$scratch/work/samples"

# The lines of every ```sh block, in order.
commands=$(awk '/^```sh$/ {inside = 1; next} /^```$/ {inside = 0}
                inside' "$guide")
[[ -n "$commands" ]] || { echo "no commands in $guide"; exit 1; }
while IFS= read -r command; do
  echo "+ $command"
  if ! (cd "$scratch/work" && PATH="$scratch/bin:$PATH" \
        bash -euo pipefail -c "$command" >"$scratch/out.log" 2>&1); then
    echo "the guide's command failed: $command"
    tail -20 "$scratch/out.log"
    exit 1
  fi
done <<<"$commands"

# What the steps say they write.
for file in targets/tag.pdf targets/checkerboard.svg targets/dots.pdf \
    camera.yaml camera.html tune/tune.html report/report.html \
    report/results.csv report-log/summary.json; do
  [[ -s "$scratch/work/$file" ]] || { echo "the guide's $file is missing"; exit 1; }
done

# The plan excerpt: every line is the sample plan's own.
while IFS= read -r line; do
  [[ -z "$line" ]] && continue
  grep -qxF -- "$line" "$source_dir/samples/delta/plan.yaml" ||
    { echo "the guide's plan line is not in the sample: $line"; exit 1; }
done < <(awk '/^```yaml$/ {inside = 1; next} /^```$/ {inside = 0} inside' \
  "$guide")

# The pictures.
for image in $(grep -o '(images/[^)]*)' "$guide" | tr -d '()'); do
  [[ -s "$source_dir/docs/$image" ]] || { echo "missing picture $image"; exit 1; }
done
echo "bench guide: every command ran"
