#!/usr/bin/env bash
# Runs one fuzz target until its coverage (libFuzzer's `cov:`) has not grown for MINUTES
# minutes, then stops it and prints the total time, executions and final cov/ft. With
# LONGEST (minutes), it also stops then, plateau or not (the machine is shared: at most 30).
#
#   fuzz/run_until_plateau.sh urdf_model 10
#   fuzz/run_until_plateau.sh dae_mesh 5 30
#
# One job, at nice 10 (the machine is shared). The corpus grows in fuzz/corpus/TARGET
# (gitignored), starting from fuzz/seeds/TARGET and, read-only, the repository's own inputs
# (and the official Faze4 description, assets/faze4_description). Crashes land in fuzz/artifacts/TARGET; the
# run then stops early and says so. The log is fuzz/logs/TARGET-DATE.log.
set -euo pipefail
cd "$(dirname "$0")/.."

target=${1:?usage: $0 TARGET MINUTES}
minutes=${2:?usage: $0 TARGET MINUTES [LONGEST]}
longest=${3:-}
corpus=fuzz/corpus/$target
mkdir -p "$corpus" fuzz/logs
log=fuzz/logs/$target-$(date +%Y%m%d-%H%M%S).log

extra=(fuzz/seeds/"$target")
# RSS_LIMIT_MB: libFuzzer's memory limit for the whole fuzzer process (2048 by default); its
# ASan allocator keeps what it freed, so a campaign over ~45 minutes can need more
flags=(-timeout=10 -rss_limit_mb="${RSS_LIMIT_MB:-2048}" -print_final_stats=1)
case $target in
urdf_model)
    extra+=(urdf tests/urdf)
    # the official description, as the tests find it: the repository's copy, or $FAZE4_DESCRIPTION
    extra+=("${FAZE4_DESCRIPTION:-assets/faze4_description}/urdf")
    flags+=(-dict=fuzz/urdf.dict)
    ;;
npy_samples)
    cp -n tests/fixtures/*.npy "$corpus"/
    ;;
dae_mesh)
    flags+=(-dict=fuzz/dae.dict)
    ;;
motors_file)
    extra+=(tests/motors)
    flags+=(-dict=fuzz/motors.dict)
    ;;
esac

export RUSTC_BOOTSTRAP=1 # cargo fuzz needs nightly-only flags; see the README
nice -n 10 cargo fuzz build "$target" >/dev/null 2>&1 || nice -n 10 cargo fuzz build "$target"

start=$(date +%s)
# its own process group, so that the whole run (cargo and the fuzzer) can be stopped at once
setsid nice -n 10 cargo fuzz run "$target" "$corpus" "${extra[@]}" -- "${flags[@]}" >"$log" 2>&1 &
pid=$!
trap 'kill -INT -- -$pid 2>/dev/null || true' EXIT INT TERM

last_cov=-1
last_growth=$start
reason="the fuzzer ended on its own (a crash, or stopped from outside)"
while kill -0 "$pid" 2>/dev/null; do
    sleep 10
    cov=$(grep -aoE 'cov: [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+' || echo 0)
    if ((cov > last_cov)); then
        last_cov=$cov
        last_growth=$(date +%s)
    elif (($(date +%s) - last_growth >= minutes * 60)); then
        reason="the plateau: no new cov for $minutes min"
        kill -INT -- -"$pid" 2>/dev/null || true
        break
    fi
    if [[ -n $longest ]] && (($(date +%s) - start >= longest * 60)); then
        reason="the time limit of $longest min, coverage still growing: no plateau"
        kill -INT -- -"$pid" 2>/dev/null || true
        break
    fi
done
wait "$pid" 2>/dev/null || true
trap - EXIT INT TERM
end=$(date +%s)

status=$(grep -aE '^#[0-9]+' "$log" | tail -1)
execs=$(grep -aoE 'stat::number_of_executed_units: [0-9]+' "$log" | grep -oE '[0-9]+$' ||
    echo "$status" | grep -oE '^#[0-9]+' | tr -d '#')
echo "target:     $target"
echo "log:        $log"
echo "time:       $((end - start)) s"
echo "stopped:    $reason"
echo "executions: $execs"
echo "final:      $(echo "$status" | grep -oE 'cov: [0-9]+ ft: [0-9]+')"
echo "corpus:     $(find "$corpus" -type f | wc -l) inputs"
if grep -aqE '^==[0-9]+== ?ERROR|panicked at|deadly signal|Test unit written to' "$log"; then
    echo "CRASH:      $(grep -aE 'Test unit written to' "$log" | tail -1)"
    exit 1
fi
echo "crashes:    none"
