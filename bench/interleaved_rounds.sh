# Sourced by the benchmark scripts: run_rounds ROUNDS FILE COMMAND...
# runs the commands in turn, once each per round, so that a change in the
# shared host's load hits them alike, and appends one line per round to FILE:
# the round's number and each command's wall time [s].
run_rounds() {
  local rounds=$1 file=$2
  shift 2
  : > "$file"
  for round in $(seq "$rounds"); do
    local line="$round" command start
    for command in "$@"; do
      start=$EPOCHREALTIME
      $command >/dev/null 2>&1
      line="$line $(python3 -c "print($EPOCHREALTIME - $start)")"
    done
    echo "$line" | tee -a "$file"
  done
}
