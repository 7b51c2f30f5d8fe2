#!/usr/bin/env bash
# Measures two promises of the output contract (README) with the release binary:
#  1. 8 concurrent `analyze` runs of one 3-minute file give byte-identical outputs;
#  2. a `generate` killed with SIGKILL at 6 points of its run leaves either the old output
#     or the complete new one (never a torn, empty or missing file, nor a temporary file).
# Usage: scripts/check_output_contract.sh [BINARY]   (default: target/release/violin-skeleton)
set -euo pipefail
BIN=${1:-${CARGO_TARGET_DIR:-target}/release/violin-skeleton}
[ -x "$BIN" ] || { echo "build it first: cargo build --release -p violin-skeleton-cli" >&2; exit 2; }
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cd "$WORK"

# A 3-minute recording: the demo clip (24.6 s) eight times over.
"$BIN" demo --quiet --out demo >/dev/null
python3 - <<'PY'
import wave
with wave.open("demo/demo.wav") as w:
    params, frames = w.getparams(), w.readframes(w.getnframes())
with wave.open("take.wav", "wb") as out:
    out.setparams(params)
    for _ in range(8):
        out.writeframes(frames)
PY
echo "input: take.wav, $(python3 -c 'import wave; w=wave.open("take.wav"); print(round(w.getnframes()/w.getframerate(),1))') s"

# 1. Eight concurrent analyses.
start=$(date +%s.%N)
for k in 1 2 3 4 5 6 7 8; do "$BIN" --quiet analyze take.wav -o "a$k.json" & done
wait
end=$(date +%s.%N)
distinct=$(sha256sum a?.json | awk '{print $1}' | sort -u | wc -l)
echo "8 concurrent analyze runs in $(python3 -c "print(round($end-$start,1))") s: $distinct distinct output(s) ($(stat -c %s a1.json) bytes)"
[ "$distinct" = 1 ] || { echo "FAIL: outputs differ" >&2; exit 1; }

# 2. SIGKILL during generate over an existing output.
"$BIN" --quiet generate take.wav -o new.json
echo '{"old": true}' > old.json
t0=$(date +%s.%N); "$BIN" --quiet generate take.wav -o timing.json; t1=$(date +%s.%N)
run_s=$(python3 -c "print($t1-$t0)")
echo "generate alone: $(python3 -c "print(round($run_s,2))") s"
for frac in 0.05 0.2 0.4 0.6 0.8 0.95; do
    cp old.json out.json
    "$BIN" --quiet generate take.wav -o out.json & pid=$!
    sleep "$(python3 -c "print($run_s*$frac)")"
    kill -9 "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
    if cmp -s out.json old.json; then state=old
    elif cmp -s out.json new.json; then state=new
    else echo "FAIL: killed at ${frac} of the run, out.json is torn ($(stat -c %s out.json) bytes)" >&2; exit 1
    fi
    leftovers=$(find . -maxdepth 1 -name '.violin-skeleton-*' | wc -l)
    find . -maxdepth 1 -name '.violin-skeleton-*' -delete
    echo "SIGKILL at $(python3 -c "print(round($run_s*$frac,2))") s: output is the $state one; $leftovers temporary file(s) left"
done
echo "ok"
