#!/bin/bash
# The volume, the sweep's Indexed Job, then the merge Job, each waited for with a timeout
# (FAZE4_TIMEOUT_S, default 6 h) that gives up as soon as the Job has failed.
set -euo pipefail
here=$(dirname "$0")
timeout_s=${FAZE4_TIMEOUT_S:-21600}

# waits for Job $1: 0 when Complete, 1 as soon as it is Failed or when the timeout passes
wait_for() {
    local job=$1 deadline=$((SECONDS + timeout_s)) state
    while ((SECONDS < deadline)); do
        state=$(kubectl get job "$job" -o jsonpath='{range .status.conditions[?(@.status=="True")]}{.type} {end}')
        case " $state " in
            *" Complete "*) echo "$job: complete"; return 0 ;;
            *" Failed "*)
                echo "$job: failed (kubectl describe job $job; failed parts: $(kubectl get job "$job" -o jsonpath='{.status.failedIndexes}'))" >&2
                return 1 ;;
        esac
        sleep 10
    done
    echo "$job: not complete after ${timeout_s} s" >&2
    return 1
}

kubectl apply -f "$here/parts-pvc.yaml"
kubectl apply -f "$here/sweep-job.yaml"
wait_for faze4-sweep
kubectl apply -f "$here/merge-job.yaml"
wait_for faze4-merge
