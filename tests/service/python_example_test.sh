#!/usr/bin/env bash
# Runs client/python/example.py (Debian's python3-grpcio, generated stubs) against a fresh
# lixel_server on a loopback port and checks what it printed.
set -euo pipefail
server=$1
stubs=$2
example=$3
log=$(mktemp)
out=$(mktemp)
"$server" --address=127.0.0.1:0 --instance=python-test --workers=1 > "$out" 2> "$log" &
pid=$!
trap 'kill $pid 2>/dev/null || true; rm -f "$log" "$out"' EXIT
for _ in $(seq 100); do [[ -s $out ]] && break; sleep 0.1; done
port=$(head -1 "$out")
result=$(/usr/bin/python3 "$example" --target "127.0.0.1:$port" --stubs "$stubs")
echo "$result"
grep -q "^scene sha256:" <<< "$result"
grep -q "map plane floor" <<< "$result"
grep -q "received [1-9][0-9]* bytes of maps" <<< "$result"
grep -q "coded: [1-9][0-9]* bytes of maps, .* decoded within each image's stated bound" <<< "$result"
grep -q "misclassified" <<< "$result"
