# Sourced by the benchmark scripts.
#
# run_rounds ROUNDS FILE COMMAND... runs the commands in turn, once each per
# round, so that a change in the shared host's load hits them alike, and
# writes one line per round to FILE: the round's number, then each command's
# wall time [s], CPU time (user + system) [s] and peak memory [kB], from
# /usr/bin/time.
#
# summarise_rounds FILE LABEL... prints, for each command (one LABEL each),
# the median wall and CPU time and peak memory over the rounds, and for each
# command after the first its wall and CPU time over the first's, taken
# within each round: the median and the range.
#
# wall_ratio FILE A B LABEL prints LABEL and command A's wall time over
# command B's (commands counted from 0), taken within each round: the median
# and the range.
run_rounds() {
  local rounds=$1 file=$2
  shift 2
  : > "$file"
  local measure
  measure=$(mktemp)
  for round in $(seq "$rounds"); do
    local line="$round" command
    for command in "$@"; do
      /usr/bin/time -f "%e %U %S %M" -o "$measure" $command >/dev/null 2>&1
      line="$line $(awk '{printf "%s %.2f %s", $1, $2 + $3, $4}' "$measure")"
    done
    echo "$line" | tee -a "$file"
  done
  rm -f "$measure"
}

summarise_rounds() {
  python3 - "$@" <<'PY'
import statistics, sys
file, labels = sys.argv[1], sys.argv[2:]
rounds = [list(map(float, line.split()[1:])) for line in open(file)]
def column(command, field):  # field: 0 wall, 1 CPU, 2 peak memory
    return [r[3 * command + field] for r in rounds]
def spread(values):
    return (f"{statistics.median(values):.3f} "
            f"({min(values):.3f}-{max(values):.3f})")
width = max(len(label) for label in labels)
for k, label in enumerate(labels):
    line = (f"{label:<{width}}  wall {statistics.median(column(k, 0)):7.2f} s"
            f"  CPU {statistics.median(column(k, 1)):7.2f} s"
            f"  peak {statistics.median(column(k, 2)) / 1024:5.0f} MB")
    if k > 0:
        wall = [a / b for a, b in zip(column(k, 0), column(0, 0))]
        cpu = [a / b for a, b in zip(column(k, 1), column(0, 1))]
        line += f"  / {labels[0]}: wall {spread(wall)}, CPU {spread(cpu)}"
    print(line)
print(f"(medians of {len(rounds)} interleaved rounds)")
PY
}

wall_ratio() {
  python3 - "$@" <<'PY'
import statistics, sys
file, a, b, label = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
rounds = [list(map(float, line.split()[1:])) for line in open(file)]
ratios = [r[3 * a] / r[3 * b] for r in rounds]
print(f"{label}: {statistics.median(ratios):.3f} "
      f"({min(ratios):.3f}-{max(ratios):.3f})")
PY
}
