#!/usr/bin/env bash
# Installs lixel's Python client from the build (client/python/pyproject.toml) into a fresh
# virtual environment that sees Debian's packages, as the README says, then drives a moving
# scene through a Session with it (client/python/session_example.py) against a fresh
# lixel_server on a loopback port, and checks what it printed.
set -euo pipefail
server=$1
package=$2
example=$3
work=$(mktemp -d)
log=$work/server.log
out=$work/server.out
"$server" --address=127.0.0.1:0 --instance=python-session --workers=1 > "$out" 2> "$log" &
pid=$!
trap 'kill $pid 2>/dev/null || true; rm -rf "$work"' EXIT
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
"$work/venv/bin/pip" install --quiet --no-build-isolation --no-index "$package"
for _ in $(seq 100); do [[ -s $out ]] && break; sleep 0.1; done
port=$(head -1 "$out")
# Run from elsewhere, so only the installed package can be imported.
result=$(cd "$work" && "$work/venv/bin/python" "$example" --target "127.0.0.1:$port" --frames 12)
echo "$result"
grep -q "^scene sha256:.*uploaded once" <<< "$result"
grep -q "^frame 12: [1-9][0-9]* maps, [1-9][0-9]* bytes" <<< "$result"
grep -q "^session: [1-9][0-9]* frames served" <<< "$result"
# The same moving scene as masks: each frame's view mask, evaluated.
masks=$(cd "$work" && "$work/venv/bin/python" "$example" --target "127.0.0.1:$port" --frames 6 \
        --masks)
echo "$masks"
grep -q "^frame 6: mask 256 x 256, [1-9][0-9]* bytes, [1-9][0-9]* of [1-9][0-9]* surface" <<< "$masks"
grep -q "^session: [1-9][0-9]* frames served" <<< "$masks"
