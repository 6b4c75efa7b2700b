#!/usr/bin/env bash
# Peer comparison: the same Duffing frequency sweep in ihbm and in published Python
# harmonic-balance packages, timed per curve.
#
#   bash benches/peers/run.sh
#
# Needs only the Rust toolchain and python3 (with venv and pip); the Python packages
# go into a throwaway virtual environment in a temp dir, removed at the end.
# Settings (environment): HARMONICS (5), FROM (0.5), TO (3.0) in rad/s, IHBM_REPEATS
# (20, median), PEER_REPEATS (3, best), PEERS (pip specs, default below), KEEP_VENV=1
# to keep the venv and print its path, RESULTS (output JSON path).
#
# Exit status is non-zero only if ihbm's own part fails; a peer that cannot be
# installed or run is reported and skipped.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
harmonics="${HARMONICS:-5}"
from="${FROM:-0.5}"
to="${TO:-3.0}"
ihbm_repeats="${IHBM_REPEATS:-20}"
peer_repeats="${PEER_REPEATS:-3}"
peers="${PEERS:-harmonicbalance==0.2.0 pyharm-os==1.2.2}"
results="${RESULTS:-$here/results.json}"

say() { printf '\n== %s\n' "$*"; }

tmp="$(mktemp -d "${TMPDIR:-/tmp}/ihbm-peers.XXXXXX")"
cleanup() {
    if [[ "${KEEP_VENV:-0}" == 1 ]]; then
        echo "kept: $tmp (venv in $tmp/venv)"
    else
        rm -rf "$tmp"
    fi
}
trap cleanup EXIT

# --- ihbm (its failure is the only hard failure) -----------------------------------
say "ihbm: cargo run --release --example peer_duffing (N=$harmonics, W $from -> $to, $ihbm_repeats repeats)"
if ! (cd "$root" && cargo run --release --example peer_duffing -- \
        --harmonics "$harmonics" --from "$from" --to "$to" --repeats "$ihbm_repeats") \
        >"$tmp/ihbm.jsonl"; then
    echo "ERROR: ihbm's sweep failed (see the messages above)" >&2
    exit 1
fi
cat "$tmp/ihbm.jsonl"
field() { # field NAME: a number from ihbm's first JSON line
    sed -n "1s/.*\"$1\":\([0-9.e+-]*\).*/\1/p" "$tmp/ihbm.jsonl"
}
points="$(field points)"
samples="$(field samples)"
if [[ -z "$points" || -z "$samples" ]]; then
    echo "ERROR: could not read the point count from ihbm's output" >&2
    exit 1
fi

# --- Python peers ------------------------------------------------------------------
if ! command -v python3 >/dev/null; then
    echo "SKIPPED all peers: python3 not found (ihbm's own results are above)"
    exit 0
fi
outputs=("$tmp/ihbm.jsonl")
skip() { # skip TOOL REASON: record a skipped peer
    printf '{"tool": "%s", "error": "%s"}\n' "$1" "$2" >"$tmp/skip-$1.jsonl"
    outputs+=("$tmp/skip-$1.jsonl")
    echo "SKIPPED $1: $2"
}
venv="$tmp/venv"
say "creating a throwaway venv in $venv"
if ! python3 -m venv "$venv" >"$tmp/venv.log" 2>&1; then
    cat "$tmp/venv.log"
    for spec in $peers; do skip "${spec%%[=<>]*}" "python3 -m venv failed (Debian: apt-get install python3-venv)"; done
else
    py="$venv/bin/python"
    for spec in $peers; do
        tool="${spec%%[=<>]*}"
        say "$tool: pip install $spec"
        if ! "$py" -m pip install --disable-pip-version-check --quiet "$spec" >"$tmp/pip-$tool.log" 2>&1; then
            tail -5 "$tmp/pip-$tool.log"
            skip "$tool" "pip install $spec failed"
            continue
        fi
        say "$tool: the same sweep, $points points to match ihbm, best of $peer_repeats"
        # From inside the temp dir: pyHarm writes a .pyHarm/ state folder into the cwd.
        if (cd "$tmp" && "$py" "$here/peers.py" "$tool" --harmonics "$harmonics" --from "$from" --to "$to" \
                --points "$points" --samples "$samples" --repeats "$peer_repeats") \
                >"$tmp/$tool.jsonl" 2>"$tmp/$tool.err"; then
            cat "$tmp/$tool.jsonl"
            outputs+=("$tmp/$tool.jsonl")
        else
            tail -5 "$tmp/$tool.err"
            reason="$(sed -n 's/.*"error": "\(.*\)"}$/\1/p' "$tmp/$tool.jsonl" | tr -d '"' | head -c 300)"
            skip "$tool" "run failed: ${reason:-see messages above}"
        fi
    done
fi

# --- table -------------------------------------------------------------------------
say "results"
python3 "$here/report.py" "$results" "${outputs[@]}"
