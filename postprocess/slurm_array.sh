#!/bin/bash
# A Slurm job array over a sweep table (docs/batch.md "Batch runs"): task N runs row N of TABLE.
# Ahead of the time limit Slurm sends SIGUSR1 to this batch shell (--signal=B:USR1@120), which
# passes it on to ffrf: a mechanism run ends after its current step, writes its final and
# restart state and exits 5 (docs/faults.md "Faults", exit codes). Exit 5 is turned into a requeue
# of this task (scontrol requeue; sbatch of the same task when requeue is refused), and the
# requeued task continues the run with --restart, bit for bit the uninterrupted run.
#
#SBATCH --job-name=ffrf-sweep
#SBATCH --array=1-24
#SBATCH --cpus-per-task=2
#SBATCH --time=00:30:00
#SBATCH --signal=B:USR1@120
#SBATCH --requeue
#SBATCH --open-mode=append
#
# Settings (environment, defaults in brackets): FFRF [ffrf], CASE [engine_rc1.nml],
# TABLE [table.csv], OUTPUT [sweep/{case}_{task}.h5, relative to OUTPUT_DIR], OUTPUT_DIR [.],
# MESH_DIR [the case's folder], FFRF_OPTIONS [--quiet]. Submit: sbatch slurm_array.sh
# (sweep/ must exist). Exit status: ffrf's (0 done, 2 input, 3 file, 4 numerical), 0 when the
# task was requeued.
set -u
FFRF=${FFRF:-ffrf}
CASE=${CASE:-engine_rc1.nml}
TABLE=${TABLE:-table.csv}
OUTPUT=${OUTPUT:-sweep/\{case\}_\{task\}.h5}
OUTPUT_DIR=${OUTPUT_DIR:-.}
FFRF_OPTIONS=${FFRF_OPTIONS---quiet}
EXIT_INTERRUPTED=5   # ffrf: interrupted by a signal, restart state written

task=${SLURM_ARRAY_TASK_ID:?not a Slurm array task (SLURM_ARRAY_TASK_ID unset)}
case_name=$(basename "${CASE%.*}")
output=${OUTPUT//\{case\}/$case_name}
output=${output//\{task\}/$task}
results="$OUTPUT_DIR/$output"
requeued_mark="$results.requeued"

# A requeued task (our mark, or Slurm's restart count after a node failure) continues from
# the newest restart state: the checkpoint of a killed run, else the interrupted results file.
arguments=("$CASE" --sweep "$TABLE" --task "$task" --output "$output" --output-dir "$OUTPUT_DIR"
           --threads "${SLURM_CPUS_PER_TASK:-1}")
if [ -n "${MESH_DIR:-}" ]; then arguments+=(--mesh-dir "$MESH_DIR"); fi
if [ -e "$requeued_mark" ] || [ "${SLURM_RESTART_COUNT:-0}" -gt 0 ]; then
  if [ -e "$results.checkpoint" ]; then
    arguments+=(--restart "$results.checkpoint")
  elif [ -e "$results" ]; then
    arguments+=(--restart "$results")
  fi
fi
rm -f "$requeued_mark"

# ffrf runs as a child so that this shell can pass Slurm's signal on and see the exit code
# shellcheck disable=SC2086
"$FFRF" "${arguments[@]}" $FFRF_OPTIONS &
child=$!
trap 'kill -USR1 "$child" 2>/dev/null' USR1
trap 'kill -TERM "$child" 2>/dev/null' TERM
# a trapped signal interrupts wait (status > 128): wait again until ffrf has ended
while :; do
  wait "$child"
  status=$?
  if kill -0 "$child" 2>/dev/null; then continue; fi
  # the signal came as ffrf ended: its status is the next wait's
  if [ "$status" -gt 128 ]; then wait "$child" 2>/dev/null; status=$?; fi
  break
done

if [ "$status" -eq "$EXIT_INTERRUPTED" ]; then
  touch "$requeued_mark"
  job="${SLURM_ARRAY_JOB_ID:-${SLURM_JOB_ID:-}}_$task"
  [ -n "${SLURM_ARRAY_JOB_ID:-}" ] || job=${SLURM_JOB_ID:-}
  echo "slurm_array.sh: task $task interrupted (exit $status); requeueing $job to continue" \
       "with --restart" >&2
  if scontrol requeue "$job"; then
    exit 0
  fi
  # requeue refused (e.g. JobRequeue=0): submit this task again
  if sbatch --array="$task" --export=ALL "$0"; then
    exit 0
  fi
  echo "slurm_array.sh: neither scontrol requeue nor sbatch worked; resubmit task $task" \
       "by hand: it continues from $results" >&2
fi
exit "$status"
