#!/usr/bin/env bash
# The other side of bad_input.sh (issue 42): a render that goes ahead still prints the warnings
# of loading, before the device line and the render; --verbose prints them at once, even before
# an error. Renders are tiny (16x16, 1 spp).
#   warnings_and_paths.sh PMCR SOURCE_DIR
set -u
pmcr="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
fail() { echo "FAIL: $*"; cat "$tmp/stderr"; failures=$((failures + 1)); }
tiny=(--width 16 --height 16 --spp 1 --no-png)

# A shipped scene with 8 bytes after its GLB container: a warning, and a render.
cat "$src/scenes/furnace.glb" >"$tmp/trailing.glb"
printf 'trailing' >>"$tmp/trailing.glb"
"$pmcr" render "$tmp/trailing.glb" "${tiny[@]}" -o "$tmp/trailing.exr" 2>"$tmp/stderr"
rc=$?
warning=$(grep -n '^warning: .*trailing\.glb: ignoring 8 bytes after the GLB$' "$tmp/stderr" | cut -d: -f1)
device=$(grep -n '^device: ' "$tmp/stderr" | cut -d: -f1)
if [ $rc -ne 0 ] || [ ! -s "$tmp/trailing.exr" ]; then
    fail "the render with a warning exited with $rc or wrote no image"
elif [ -z "$warning" ] || [ -z "$device" ] || [ "$warning" -gt "$device" ]; then
    fail "the warning (line ${warning:-none}) must be printed before the device line (${device:-none})"
else
    echo "ok   (a render prints its warnings first)"
fi

# The same file and a bad --camera: the error alone, or, with --verbose, the warning first.
"$pmcr" render "$tmp/trailing.glb" "${tiny[@]}" --camera 5 -o "$tmp/x.exr" 2>"$tmp/stderr"
rc=$?
if [ $rc -ne 1 ] || [ "$(wc -l <"$tmp/stderr")" -ne 1 ] || ! grep -q '^pmcr: error: .*--camera 5' "$tmp/stderr"; then
    fail "a bad --camera must be the one line printed (exit $rc)"
else
    echo "ok   (an error is the one line)"
fi
"$pmcr" render "$tmp/trailing.glb" "${tiny[@]}" --camera 5 --verbose -o "$tmp/x.exr" 2>"$tmp/stderr"
rc=$?
if [ $rc -ne 1 ] || [ "$(wc -l <"$tmp/stderr")" -ne 2 ] ||
    ! head -1 "$tmp/stderr" | grep -q '^warning: .*ignoring 8 bytes' ||
    ! tail -1 "$tmp/stderr" | grep -q '^pmcr: error: .*--camera 5'; then
    fail "--verbose must print the warning, then the error (exit $rc)"
else
    echo "ok   (--verbose prints the warning before the error)"
fi
[ -e "$tmp/x.exr" ] && fail "a failed render left x.exr"

"$pmcr" render --help >"$tmp/help"
for option in --verbose; do
    grep -q -- "^  $option " "$tmp/help" || fail "render --help lacks $option"
done

[ $failures -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo ok
