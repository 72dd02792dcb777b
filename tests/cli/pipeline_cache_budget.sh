#!/usr/bin/env bash
# The on-disk pipeline cache (vk/pipeline_cache.h) and the stats that account for a render's
# time (issue 38): a cache file that is corrupt, truncated, not pmcr's or made for another
# device is ignored with exactly one warning and replaced; the pre-passes run on the render
# clock, inside --time, and the stats' times nest as they should. No timing bound is asserted.
#   pipeline_cache_budget.sh PMCR SOURCE_DIR
set -u
pmcr="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# Mesa's own shader cache stays where it was (it would follow XDG_CACHE_HOME and compile every
# kernel cold, three times slower on lavapipe): this test is about pmcr's cache file only.
export MESA_SHADER_CACHE_DIR="${MESA_SHADER_CACHE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}}"
export XDG_CACHE_HOME="$tmp/cache"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

render() {  # render [extra args]: a tiny pt render; stderr to $tmp/stderr
    "$pmcr" render "$src/scenes/cornell-classic.glb" --width 16 --height 16 --spp 1 -q \
        -o "$tmp/out.exr" --no-png "$@" 2>"$tmp/stderr" >/dev/null
}

render || fail "first render exited with $?: $(cat "$tmp/stderr")"
[ -s "$tmp/stderr" ] && fail "first render printed: $(cat "$tmp/stderr")"
cache=$(ls "$XDG_CACHE_HOME"/pmcr/*.bin 2>/dev/null | head -1)
[ -n "$cache" ] || fail "no cache file under $XDG_CACHE_HOME/pmcr"
cp "$cache" "$tmp/good.bin"
render || fail "second render exited with $?"
[ -s "$tmp/stderr" ] && fail "second render (valid cache) printed: $(cat "$tmp/stderr")"

# expect_ignored DESCRIPTION REASON: the render succeeds with one warning naming the cache file
# and REASON, writes its image, and leaves a valid cache for the next run.
expect_ignored() {
    rm -f "$tmp/out.exr"
    render
    local rc=$?
    if [ $rc -ne 0 ]; then fail "$1: exit status $rc: $(cat "$tmp/stderr")"; return; fi
    [ -f "$tmp/out.exr" ] || fail "$1: no image written"
    if [ "$(wc -l <"$tmp/stderr")" -ne 1 ] || ! grep -q "^warning: $cache: ignoring the pipeline cache: $2" "$tmp/stderr"; then
        fail "$1: expected one warning '... $2', got: $(cat "$tmp/stderr")"; return
    fi
    render
    [ -s "$tmp/stderr" ] && fail "$1: the cache was not replaced; next run printed: $(cat "$tmp/stderr")"
    echo "ok   ($1)"
}

# A flipped byte in the driver's data.
python3 - "$tmp/good.bin" "$cache" <<'PY'
import sys
b = bytearray(open(sys.argv[1], 'rb').read()); b[-1] ^= 0xff; open(sys.argv[2], 'wb').write(b)
PY
expect_ignored "corrupt" "corrupt"
head -c 30 "$tmp/good.bin" >"$cache"
expect_ignored "truncated" "truncated"
printf 'garbage, not a cache' >"$cache"
expect_ignored "not pmcr's" "not a pmcr pipeline cache"
: >"$cache"
expect_ignored "empty" "not a pmcr pipeline cache"
# A whole container around another device's data (vendor ID changed, checksum redone).
python3 - "$tmp/good.bin" "$cache" <<'PY'
import struct, sys
f = open(sys.argv[1], 'rb').read(); blob = bytearray(f[24:])
blob[8:12] = struct.pack('<I', (struct.unpack('<I', bytes(blob[8:12]))[0] + 1) & 0xffffffff)
h = 0xcbf29ce484222325
for c in blob: h = ((h ^ c) * 0x100000001b3) & 0xffffffffffffffff
open(sys.argv[2], 'wb').write(f[:8] + struct.pack('<QQ', len(blob), h) + bytes(blob))
PY
expect_ignored "another device" "made for another device or driver"
# A cache directory that cannot be written costs a warning at most, never the render.
rm -rf "$XDG_CACHE_HOME"; : >"$XDG_CACHE_HOME"
render || fail "render with an unwritable cache directory exited with $?: $(cat "$tmp/stderr")"
rm -f "$XDG_CACHE_HOME"

# The stats account for the time: pre-passes on the clock (inside --time), the pipelines off it.
for method in erpt pmc-er mlt pssmlt pt; do
    "$pmcr" render "$src/scenes/cornell-classic.glb" --method "$method" --width 16 --height 16 \
        --time 0.5 -q -o "$tmp/$method.exr" --no-png 2>"$tmp/stderr" >/dev/null ||
        { fail "$method: exit status $?: $(cat "$tmp/stderr")"; continue; }
    python3 - "$tmp/$method.json" "$method" <<'PY' || fail "$method: stats do not add up"
import json, sys
s = json.load(open(sys.argv[1])); method = sys.argv[2]
def check(ok, what):
    if not ok: print(f"  {method}: {what}: {json.dumps({k: s.get(k) for k in ['render_seconds', 'sampling_seconds', 'pipeline_seconds', 'prepass_seconds', 'written_seconds', 'wall_seconds', 'device_busy', 'device_idle_seconds', 'rays_per_kernel_second']})}"); sys.exit(1)
for k in ['pipeline_seconds', 'prepass_seconds', 'device_busy', 'device_idle_seconds', 'rays_per_kernel_second', 'written_seconds', 'wall_seconds']:
    check(k in s, f"no {k}")
check((s['prepass_seconds'] > 0) == (method != 'pt'), "a pre-pass where there is none, or none where there is one")
check(s['prepass_seconds'] <= s['sampling_seconds'], "pre-pass outside the render clock")
check(s['pipeline_seconds'] + s['sampling_seconds'] <= s['render_seconds'] + 1e-3, "pipelines and clock exceed the render")
check(s['sampling_seconds'] <= s['written_seconds'] <= s['wall_seconds'], "written before sampled, or after the process")
check(0.0 <= s['device_idle_seconds'] <= s['sampling_seconds'], "idle time outside the clock")
check(s['rays_per_kernel_second'] > 0, "no rays per kernel second")
PY
done

# A budget shorter than the pre-pass: the first pass still runs (a render always has an image),
# and pssmlt's bootstrap and passes shrink to the budget (pssmlt_integrator.h: 4 bootstrap
# samples per pixel and 4 steps a pass at 128x128 with 4096 chains, 16384 on a GPU).
for method in erpt pmc-er mlt pssmlt pssmlt-over-pt; do
    args=(--method "$method")
    [ "$method" = pssmlt-over-pt ] && args=(--method pssmlt --over pt)
    "$pmcr" render "$src/scenes/cornell-classic.glb" "${args[@]}" --width 128 --height 128 --time 0.001 -q \
        -o "$tmp/short.exr" --no-png 2>"$tmp/stderr" >/dev/null ||
        { fail "$method --time 0.001: exit status $?: $(cat "$tmp/stderr")"; continue; }
    python3 - "$tmp/short.json" "$method" <<'PY' || fail "$method --time 0.001: no pass, or a pre-pass past the budget"
import json, sys
s = json.load(open(sys.argv[1])); method = sys.argv[2]; m = s['method_stats']
ok = s['spp'] > 0 and m.get('passes', 1) >= 1
if method.startswith('pssmlt'):
    ok = ok and m['bootstrap_samples'] < 4 * 128 * 128 and m['steps_per_pass'] == 1
if not ok: print(f"  {method}: spp {s['spp']}, {json.dumps(m)}"); sys.exit(1)
PY
done

[ $failures -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo "pipeline cache and time accounting: all checks passed"
