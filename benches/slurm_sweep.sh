#!/usr/bin/env bash
# Benchmark (issue 13, item 6): the 10,000-cell bench grid of benches/sweep.rs swept on this
# machine unsharded, then as Slurm array jobs of 4 and 16 shards plus their merge job on a
# one-node cluster (.ci/slurm/slurm-up.sh; root), and the scheduler's turnaround for an empty
# job. Every figure is wall time measured in this run; the merged outputs are compared with
# the unsharded one byte for byte. Run from the repository root after
# `cargo build --release`:   bash benches/slurm_sweep.sh
set -euo pipefail
root=$PWD
bin=$root/target/release/safereach
[[ -x $bin ]] || { echo "build first: cargo build --release" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bash "$root/.ci/slurm/slurm-up.sh" >/dev/null

cp "$root/problems/seed.toml" "$work/"
speeds=$(python3 -c 'print(", ".join(repr(round(0.005 + 0.003*i, 10)) for i in range(100)))')
radii=$(python3 -c 'print(", ".join(repr(round(0.5 + 0.015*i, 10)) for i in range(100)))')
cat > "$work/bench-grid.toml" <<GRID
base = "seed.toml"
[axes]
"environment.obstacle_speed" = [$speeds]
"controller.reaction_radius" = [$radii]
GRID

now() { date +%s.%N; }
wait_jobs() {  # wait until none of the given jobs is queued or running
  while [[ -n $(squeue -h -o %i -j "$1") ]]; do sleep 0.05; done
}
secs() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }

cores=$(nproc)
t0=$(now)
"$bin" sweep "$work/bench-grid.toml" --out "$work/whole" >/dev/null
t1=$(now)
whole=$(secs "$t0" "$t1")
echo "machine: $cores cores; grid: 10,000 cells (seed problem, W x rho)"
echo "unsharded sweep, $cores threads:        ${whole} s"

for shards in 4 16; do
  out=$work/s$shards
  t0=$(now)
  said=$("$bin" sweep "$work/bench-grid.toml" --out "$out" --slurm --shards "$shards" \
           --sbatch-arg=--cpus-per-task=1)
  array=$(sed -n 's/.*array job \([0-9]*\).*/\1/p' <<<"$said" | head -1)
  merge=$(sed -n 's/.*merge job \([0-9]*\).*/\1/p' <<<"$said" | head -1)
  wait_jobs "$array,$merge"
  t1=$(now)
  cmp -s "$out/bench-grid.jsonl" "$work/whole/bench-grid.jsonl" \
    || { echo "$shards shards: merged output differs from the unsharded sweep" >&2; exit 1; }
  total=$(secs "$t0" "$t1")
  ratio=$(awk -v a="$total" -v b="$whole" 'BEGIN { printf "%.2f", a / b }')
  echo "slurm, $shards shards + merge (1 CPU each): ${total} s submit-to-merged (${ratio}x unsharded), output identical"
done

t0=$(now)
job=$(sbatch --parsable --output=/dev/null --wrap=true)
wait_jobs "$job"
t1=$(now)
echo "scheduler turnaround, empty job:        $(secs "$t0" "$t1") s"
t0=$(now)
a=$(sbatch --parsable --output=/dev/null --wrap=true)
b=$(sbatch --parsable --output=/dev/null --dependency=afterok:"$a" --wrap=true)
wait_jobs "$a,$b"
t1=$(now)
echo "scheduler turnaround, job + dependent:  $(secs "$t0" "$t1") s"
bash "$root/.ci/slurm/slurm-down.sh" >/dev/null
