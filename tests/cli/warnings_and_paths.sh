#!/usr/bin/env bash
# The other side of bad_input.sh (issue 42): a render that goes ahead still prints the warnings
# of loading, before the device line and the render; --verbose prints them at once, even before
# an error; relative paths that leave the scene's folder are read unless --restrict-paths, and
# --restrict-paths takes the files inside it. Renders are tiny (16x16, 1 spp).
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

# A triangle whose buffer lies in the folder above the scene's, lit by a constant sky.
mkdir -p "$tmp/scene"
base64 -d >"$tmp/triangle.bin" <<<'AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA'
cp "$tmp/triangle.bin" "$tmp/scene/triangle.bin"
gltf() {  # gltf FILE BUFFER-URI
    cat >"$1" <<GLTF
{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
 "bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":36,"uri":"$2"}]}
GLTF
}
gltf "$tmp/scene/up.gltf" ../triangle.bin
gltf "$tmp/scene/beside.gltf" triangle.bin
"$pmcr" render "$tmp/scene/up.gltf" --env 1,1,1 "${tiny[@]}" -q -o "$tmp/up.exr" 2>"$tmp/stderr" &&
    [ -s "$tmp/up.exr" ] && echo "ok   (a relative path out of the folder is read by default)" ||
    fail "the buffer in the folder above was not read without --restrict-paths"
"$pmcr" render "$tmp/scene/beside.gltf" --restrict-paths --env 1,1,1 "${tiny[@]}" -q -o "$tmp/beside.exr" 2>"$tmp/stderr" &&
    [ -s "$tmp/beside.exr" ] && echo "ok   (--restrict-paths reads the files in the folder)" ||
    fail "--restrict-paths refused a buffer beside the scene"
# A shipped scene that names its sky (extras.pmcr.environment), beside it.
"$pmcr" render "$src/scenes/sky-spheres.glb" --restrict-paths "${tiny[@]}" -q -o "$tmp/sky.exr" 2>"$tmp/stderr" &&
    [ -s "$tmp/sky.exr" ] && echo "ok   (--restrict-paths reads the sky beside the scene)" ||
    fail "--restrict-paths refused sky-spheres.glb's own sky"

"$pmcr" render --help >"$tmp/help"
for option in --verbose --restrict-paths; do
    grep -q -- "^  $option " "$tmp/help" || fail "render --help lacks $option"
done

[ $failures -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
echo ok
