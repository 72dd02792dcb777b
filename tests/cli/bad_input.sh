#!/usr/bin/env bash
# Bad input gets one line naming the file and the problem, exit status 1, and no output file.
#   bad_input.sh PMCR SOURCE_DIR
set -u
pmcr="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0

# expect_error DESCRIPTION PATTERN -- ARGS...: pmcr must fail with exit status 1 and exactly one
# stderr line, the error, matching PATTERN (no warning, no device line before it: README "Bad
# input"), and leave no file in $tmp/out.
expect_error() {
    local what="$1" pattern="$2"
    shift 3
    rm -rf "$tmp/out"
    mkdir -p "$tmp/out"
    "$pmcr" "$@" >"$tmp/stdout" 2>"$tmp/stderr"
    local rc=$?
    local lines
    lines=$(wc -l <"$tmp/stderr")
    if [ $rc -ne 1 ]; then
        echo "FAIL ($what): exit status $rc, expected 1"; cat "$tmp/stderr"
        failures=$((failures + 1)); return
    fi
    if [ "$lines" -ne 1 ] || ! grep -qE -e "^pmcr: error: .*$pattern" "$tmp/stderr"; then
        echo "FAIL ($what): expected one line matching /$pattern/, got:"; cat "$tmp/stderr"
        failures=$((failures + 1)); return
    fi
    if [ -n "$(ls -A "$tmp/out")" ]; then
        echo "FAIL ($what): left files: $(ls -A "$tmp/out")"; failures=$((failures + 1)); return
    fi
    echo "ok   ($what): $(cat "$tmp/stderr")"
}

printf 'not json at all' >"$tmp/garbage.gltf"
printf 'glTF\x02\x00\x00\x00' >"$tmp/truncated.glb"
head -c 1000 "$src/scenes/cornell-glass.glb" >"$tmp/cut.glb"  # a real file cut short
cat >"$tmp/nolight.gltf" <<'GLTF'
{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
 "bufferViews":[{"buffer":0,"byteLength":36}],
 "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]}
GLTF
cat >"$tmp/nanpos.gltf" <<'GLTF'
{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
 "materials":[{"emissiveFactor":[1,1,1]}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],
 "bufferViews":[{"buffer":0,"byteLength":36}],
 "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AADAfwAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]}
GLTF
cat >"$tmp/required.gltf" <<'GLTF'
{"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],
 "extensionsRequired":["KHR_draco_mesh_compression"],"scenes":[{"nodes":[]}]}
GLTF

expect_error "missing scene file" "no-such-scene\.glb" -- render "$tmp/no-such-scene.glb" -o "$tmp/out/x.exr"
expect_error "not JSON" "garbage\.gltf" -- render "$tmp/garbage.gltf" -o "$tmp/out/x.exr"
expect_error "truncated glb" "truncated\.glb" -- render "$tmp/truncated.glb" -o "$tmp/out/x.exr"
expect_error "glb cut short" "cut\.glb.*truncated" -- render "$tmp/cut.glb" -o "$tmp/out/x.exr"
expect_error "no emitters" "nolight\.gltf.*emitter" -- render "$tmp/nolight.gltf" -o "$tmp/out/x.exr"
expect_error "NaN geometry" "nanpos\.gltf" -- render "$tmp/nanpos.gltf" -o "$tmp/out/x.exr"
expect_error "required extension" "KHR_draco_mesh_compression" -- render "$tmp/required.gltf" -o "$tmp/out/x.exr"
expect_error "unknown method" "no-such-method" -- render "$src/scenes/furnace.glb" --method no-such-method -o "$tmp/out/x.exr"
expect_error "unknown option" "--bogus" -- render "$src/scenes/furnace.glb" --bogus 3 -o "$tmp/out/x.exr"
expect_error "unknown flag before -o" "--frobnicate: unknown option" -- render "$src/scenes/furnace.glb" --frobnicate -o "$tmp/out/x.exr"
expect_error "bad number" "--spp" -- render "$src/scenes/furnace.glb" --spp abc -o "$tmp/out/x.exr"
expect_error "zero samples" "--spp" -- render "$src/scenes/furnace.glb" --spp 0 -o "$tmp/out/x.exr"
expect_error "missing value" "--spp: missing value" -- render "$src/scenes/furnace.glb" -o "$tmp/out/x.exr" --spp
expect_error "bad method option value" "--chain-length" -- render "$src/scenes/furnace.glb" --method erpt --chain-length 0 -o "$tmp/out/x.exr"
expect_error "option of another method" "--chain-length.*pt" -- render "$src/scenes/furnace.glb" --method pt --chain-length 5 -o "$tmp/out/x.exr"
# The papers' baselines (docs/paper-baselines.md): a bad value, or a method that does not take them.
expect_error "bad pixel sampler" "--pixel-sampler.*foo" -- render "$src/scenes/furnace.glb" --pixel-sampler foo -o "$tmp/out/x.exr"
expect_error "bad pixel sampler, pmc-ip" "--pixel-sampler.*foo" -- render "$src/scenes/furnace.glb" --method pmc-ip --pixel-sampler foo -o "$tmp/out/x.exr"
expect_error "bad MIS heuristic" "--mis.*foo" -- render "$src/scenes/furnace.glb" --mis foo -o "$tmp/out/x.exr"
expect_error "bad MIS heuristic, direct" "--mis.*foo" -- render "$src/scenes/furnace.glb" --method direct --mis foo -o "$tmp/out/x.exr"
expect_error "bad MIS heuristic, bdpt" "--mis.*foo" -- render "$src/scenes/furnace.glb" --method bdpt --mis foo -o "$tmp/out/x.exr"
expect_error "bad strategy-images value" "--strategy-images.*maybe" -- render "$src/scenes/furnace.glb" --method bdpt --strategy-images maybe -o "$tmp/out/x.exr"
expect_error "strategy images of another method" "--strategy-images.*pt" -- render "$src/scenes/furnace.glb" --method pt --strategy-images on -o "$tmp/out/x.exr"
expect_error "pixel sampler, erpt" "--pixel-sampler.*erpt" -- render "$src/scenes/furnace.glb" --method erpt --pixel-sampler independent -o "$tmp/out/x.exr"
expect_error "MIS heuristic, pmc-hi" "--mis.*pmc-hi" -- render "$src/scenes/furnace.glb" --method pmc-hi --mis balance -o "$tmp/out/x.exr"
expect_error "mlt large-step zero" "--large-step" -- render "$src/scenes/furnace.glb" --method mlt --large-step 0 -o "$tmp/out/x.exr"
expect_error "mlt mutation" "--mutation" -- render "$src/scenes/furnace.glb" --method mlt --mutation bogus -o "$tmp/out/x.exr"
expect_error "mlt bootstrap" "--bootstrap" -- render "$src/scenes/furnace.glb" --method mlt --bootstrap 0 -o "$tmp/out/x.exr"
expect_error "pssmlt large-step probability" "--large-step" -- render "$src/scenes/furnace.glb" --method pssmlt --large-step 1.5 -o "$tmp/out/x.exr"
expect_error "pssmlt sigma" "--sigma" -- render "$src/scenes/furnace.glb" --method pssmlt --sigma 0 -o "$tmp/out/x.exr"
expect_error "pm radius" "--radius" -- render "$src/scenes/furnace.glb" --method pm --radius -1 -o "$tmp/out/x.exr"
expect_error "pm alpha" "--alpha" -- render "$src/scenes/furnace.glb" --method pm --alpha 1.5 -o "$tmp/out/x.exr"
expect_error "pm gather rays" "--gather-rays" -- render "$src/scenes/furnace.glb" --method pm --gather-rays 99 -o "$tmp/out/x.exr"
expect_error "pm kernel" "--kernel" -- render "$src/scenes/furnace.glb" --method pm --kernel gauss -o "$tmp/out/x.exr"
expect_error "pm photons" "--photons" -- render "$src/scenes/furnace.glb" --method pm --photons -5 -o "$tmp/out/x.exr"
expect_error "pm too many photons for the device" "storage buffer range" -- render "$src/scenes/furnace.glb" --method pm --photons 16000000 -q -o "$tmp/out/x.exr"
expect_error "pm-pmc progressive" "--progressive" -- render "$src/scenes/furnace.glb" --method pm-pmc --progressive maybe -o "$tmp/out/x.exr"
expect_error "pssmlt bootstrap" "--bootstrap" -- render "$src/scenes/furnace.glb" --method pssmlt --bootstrap 0 -o "$tmp/out/x.exr"
expect_error "pssmlt chains" "--chains" -- render "$src/scenes/furnace.glb" --method pssmlt --chains -3 -o "$tmp/out/x.exr"
expect_error "pssmlt depth beyond its storage" "--max-depth.*pssmlt" -- render "$src/scenes/furnace.glb" --method pssmlt --max-depth 101 -o "$tmp/out/x.exr"
expect_error "pssmlt over an unknown estimator" "--over" -- render "$src/scenes/furnace.glb" --method pssmlt --over mlt -o "$tmp/out/x.exr"
expect_error "mmlt takes no --over" "--over.*mmlt" -- render "$src/scenes/furnace.glb" --method mmlt --over pt -o "$tmp/out/x.exr"
expect_error "mmlt bootstrap" "--bootstrap" -- render "$src/scenes/furnace.glb" --method mmlt --bootstrap -1 -o "$tmp/out/x.exr"
expect_error "mmlt depth beyond its storage" "--max-depth: mmlt" -- render "$src/scenes/furnace.glb" --method mmlt --max-depth 101 -o "$tmp/out/x.exr"
expect_error "mmlt large-step probability" "--large-step" -- render "$src/scenes/furnace.glb" --method mmlt --large-step -0.5 -o "$tmp/out/x.exr"
expect_error "mmlt chains" "--chains" -- render "$src/scenes/furnace.glb" --method mmlt --chains -3 -o "$tmp/out/x.exr"
expect_error "bad output extension" "x\.jpg" -- render "$src/scenes/furnace.glb" -o "$tmp/out/x.jpg"
expect_error "missing output directory" "nodir" -- render "$src/scenes/furnace.glb" -o "$tmp/out/nodir/x.exr"
expect_error "unknown device" "no-such-gpu" -- render "$src/scenes/furnace.glb" --device no-such-gpu -o "$tmp/out/x.exr"
expect_error "unknown command" "frobnicate" -- frobnicate
printf 'not an image' >"$tmp/sky.exr"
expect_error "missing environment image" "no-sky\.exr" -- render "$src/scenes/furnace.glb" --env "$tmp/no-sky.exr" -o "$tmp/out/x.exr"
expect_error "corrupt environment image" "sky\.exr" -- render "$src/scenes/furnace.glb" --env "$tmp/sky.exr" -o "$tmp/out/x.exr"
expect_error "environment not an image" "sky\.png.*--env expects" -- render "$src/scenes/furnace.glb" --env "$tmp/sky.png" -o "$tmp/out/x.exr"
expect_error "negative environment" "1,-1,1.*>= 0" -- render "$src/scenes/furnace.glb" --env 1,-1,1 -o "$tmp/out/x.exr"
expect_error "rotation without environment" "--env-rotate.*need --env" -- render "$src/scenes/furnace.glb" --env-rotate 30 -o "$tmp/out/x.exr"

# --- Issue 42: the edges of the promise. Inputs are written here, from the shipped scenes or by
# hand; none is copied from elsewhere.

# One line only: warnings of loading and the device line never precede an error.
glb_length() {  # glb_length FILE N: set a GLB header's total-length field to N (little-endian)
    printf "$(printf '\\x%02x\\x%02x\\x%02x\\x%02x' $(($2 & 255)) $(($2 >> 8 & 255)) \
        $(($2 >> 16 & 255)) $(($2 >> 24 & 255)))" | dd of="$1" bs=1 seek=8 conv=notrunc status=none
}
cp "$src/scenes/furnace.glb" "$tmp/length0.glb"
glb_length "$tmp/length0.glb" 0
cp "$src/scenes/furnace.glb" "$tmp/short.glb"
glb_length "$tmp/short.glb" $(($(wc -c <"$src/scenes/furnace.glb") - 64))
expect_error "GLB length 0, no warning first" "length0\.glb.*truncated GLB" -- render "$tmp/length0.glb" -o "$tmp/out/x.exr"
expect_error "GLB length short, no warning first" "short\.glb.*(truncated|BIN)" -- render "$tmp/short.glb" -o "$tmp/out/x.exr"
# A floor, and an emitter collapsed to a point: dropped with a warning, then no emitters.
cat >"$tmp/collapsed.gltf" <<'GLTF'
{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0},{"mesh":1}],
 "materials":[{"emissiveFactor":[1,1,1]}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]},{"primitives":[{"attributes":{"POSITION":1},"material":0}]}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,0,1]},
              {"bufferView":0,"byteOffset":36,"componentType":5126,"count":3,"type":"VEC3","min":[0,1,0],"max":[0,1,0]}],
 "bufferViews":[{"buffer":0,"byteLength":72}],
 "buffers":[{"byteLength":72,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAAAAAAAAAAAAAIA/AACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8AAAAA"}]}
GLTF
expect_error "emitter of zero area, no warning first" "collapsed\.gltf.*no emitters" -- render "$tmp/collapsed.gltf" -o "$tmp/out/x.exr"
# A textured floor whose image uri is missing, a directory or a device file (tinygltf warns first).
textured() {  # textured NAME URI: a lit floor whose base colour texture is the image at URI
    cat >"$tmp/$1.gltf" <<GLTF
{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
 "images":[{"uri":"$2"}],"textures":[{"source":0}],
 "materials":[{"emissiveFactor":[1,1,1],"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"material":0}]}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
              {"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}],
 "bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":12,"byteLength":24}],
 "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]}
GLTF
}
mkdir -p "$tmp/folder.png"
ln -s /dev/null "$tmp/device.png"
textured missing-image missing.png
textured directory-image folder.png
textured device-image device.png
expect_error "image uri missing" "missing-image\.gltf.*missing\.png" -- render "$tmp/missing-image.gltf" -o "$tmp/out/x.exr"
expect_error "image uri a directory" "directory-image\.gltf.*folder\.png" -- render "$tmp/directory-image.gltf" -o "$tmp/out/x.exr"
expect_error "image uri a device file" "device-image\.gltf.*device\.png" -- render "$tmp/device-image.gltf" -o "$tmp/out/x.exr"
expect_error "camera out of range, no device line" "furnace\.glb.*--camera 5 out of range" -- render "$src/scenes/furnace.glb" --camera 5 -o "$tmp/out/x.exr"

# Lights whose power overflows 32-bit floats, named; scenes whose lights have no power at all.
punctual() {  # punctual NAME TYPE INTENSITY: the unlit triangle of nolight.gltf under one light
    cat >"$tmp/$1.gltf" <<GLTF
{"asset":{"version":"2.0"},"extensionsUsed":["KHR_lights_punctual"],
 "extensions":{"KHR_lights_punctual":{"lights":[{"type":"$2","intensity":$3,"name":"lamp"}]}},
 "scene":0,"scenes":[{"nodes":[0,1]}],
 "nodes":[{"mesh":0},{"translation":[0.2,0.2,1],"extensions":{"KHR_lights_punctual":{"light":0}}}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
 "bufferViews":[{"buffer":0,"byteLength":36}],
 "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]}
GLTF
}
punctual point-1e39 point 1e39
punctual point-3e38 point 3e38
punctual sun-1e39 directional 1e39
punctual sun-3e38 directional 3e38
for light in point-1e39 point-3e38 sun-1e39 sun-3e38; do
    for method in pt erpt; do
        expect_error "$light light, $method" "$light\.gltf: light 0 \('lamp'\): its power overflows" -- render "$tmp/$light.gltf" --method $method -o "$tmp/out/x.exr"
    done
done
# Equirectangular PFM skies, 2 x 1 pixels (little-endian: scale -1): every pixel 3e38, or black.
{ printf 'PF\n2 1\n-1\n'; for i in 1 2 3 4 5 6; do printf '\xe6\xb1\x61\x7f'; done; } >"$tmp/bright.pfm"
{ printf 'PF\n2 1\n-1\n'; head -c 24 /dev/zero; } >"$tmp/black.pfm"
expect_error "environment of 3e38 pixels" "nolight\.gltf: environment '.*bright\.pfm': its power overflows" -- render "$tmp/nolight.gltf" --env "$tmp/bright.pfm" -o "$tmp/out/x.exr"
expect_error "environment overflowing when scaled" "1e30,1,1: .*overflows.*--env-scale" -- render "$tmp/nolight.gltf" --env 1e30,1,1 --env-scale 1e30 -o "$tmp/out/x.exr"
expect_error "black constant environment" "nolight\.gltf: no light" -- render "$tmp/nolight.gltf" --env 0,0,0 -o "$tmp/out/x.exr"
expect_error "environment scaled to zero" "nolight\.gltf: no light" -- render "$tmp/nolight.gltf" --env 1,1,1 --env-scale 0 -o "$tmp/out/x.exr"
expect_error "black environment image" "nolight\.gltf: no light" -- render "$tmp/nolight.gltf" --env "$tmp/black.pfm" -o "$tmp/out/x.exr"
for method in erpt pmc-ip mlt pm; do
    expect_error "black environment, $method" "nolight\.gltf: no light" -- render "$tmp/nolight.gltf" --method $method --env 0,0,0 -o "$tmp/out/x.exr"
done

# Numbers on the command line are decimal: anything else names its option.
expect_error "hexadecimal environment" "0x10,1,1: --env expects R,G,B \(three decimal numbers\)" -- render "$src/scenes/furnace.glb" --env 0x10,1,1 -o "$tmp/out/x.exr"
expect_error "hexadecimal samples" "--spp: .*'0x10'" -- render "$src/scenes/furnace.glb" --spp 0x10 -o "$tmp/out/x.exr"
expect_error "hexadecimal float" "--time: .*'0x1p3'" -- render "$src/scenes/furnace.glb" --time 0x1p3 -o "$tmp/out/x.exr"
expect_error "blank before a number" "--width: .*' 16'" -- render "$src/scenes/furnace.glb" --width " 16" -o "$tmp/out/x.exr"
expect_error "infinite exposure" "--exposure: .*'inf'" -- render "$src/scenes/furnace.glb" --exposure inf -o "$tmp/out/x.exr"
expect_error "not-a-number scale" "--env-scale: .*'nan'" -- render "$src/scenes/furnace.glb" --env 1,1,1 --env-scale nan -o "$tmp/out/x.exr"
expect_error "hexadecimal method option" "--chain-length: .*'0x10'" -- render "$src/scenes/furnace.glb" --method erpt --chain-length 0x10 -o "$tmp/out/x.exr"
expect_error "exponent in an integer" "--seed: .*'1e3'" -- render "$src/scenes/furnace.glb" --seed 1e3 -o "$tmp/out/x.exr"

# --restrict-paths: no buffer, image or environment outside the scene's folder, links followed.
mkdir -p "$tmp/farm"
base64 -d >"$tmp/outside.bin" <<<'AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA'
ln -s ../outside.bin "$tmp/farm/link.bin"
external() {  # external NAME BUFFER-URI: nolight.gltf's triangle read from a buffer file
    sed "s|data:application/octet-stream;base64,[A-Za-z0-9+/=]*|$2|" "$tmp/nolight.gltf" >"$tmp/farm/$1.gltf"
}
external up ../outside.bin
external passwd ../../../../../../../../../../../../etc/passwd
external link link.bin
cp "$tmp/missing-image.gltf" "$tmp/farm/image-up.gltf"
sed -i 's|"missing.png"|"../device.png"|' "$tmp/farm/image-up.gltf"
sed 's|"scene":0|"extras":{"pmcr":{"environment":"../bright.pfm"}},"scene":0|' "$tmp/nolight.gltf" >"$tmp/farm/sky-up.gltf"
expect_error "restricted buffer outside" "up\.gltf: uri '\.\./outside\.bin' leaves the scene's folder" -- render "$tmp/farm/up.gltf" --restrict-paths --env 1,1,1 -o "$tmp/out/x.exr"
expect_error "restricted buffer at /etc/passwd" "passwd\.gltf: uri '(\.\./)+etc/passwd' leaves the scene's folder" -- render "$tmp/farm/passwd.gltf" --restrict-paths --env 1,1,1 -o "$tmp/out/x.exr"
expect_error "restricted buffer through a link" "link\.gltf: uri 'link\.bin' leaves the scene's folder" -- render "$tmp/farm/link.gltf" --restrict-paths --env 1,1,1 -o "$tmp/out/x.exr"
expect_error "restricted image outside" "image-up\.gltf: uri '\.\./device\.png' leaves the scene's folder" -- render "$tmp/farm/image-up.gltf" --restrict-paths -o "$tmp/out/x.exr"
expect_error "restricted environment from the scene" "bright\.pfm: the environment image leaves the scene's folder" -- render "$tmp/farm/sky-up.gltf" --restrict-paths -o "$tmp/out/x.exr"
cp "$tmp/nolight.gltf" "$tmp/farm/inside.gltf"
expect_error "restricted environment from --env" "black\.pfm: the environment image leaves the scene's folder" -- render "$tmp/farm/inside.gltf" --restrict-paths --env "$tmp/black.pfm" -o "$tmp/out/x.exr"
# Without it, /etc/passwd is read as a relative path like any other, and refused as a buffer
# whose size does not match: one line still.
expect_error "unrestricted buffer at /etc/passwd" "passwd\.gltf: invalid glTF" -- render "$tmp/farm/passwd.gltf" --env 1,1,1 -o "$tmp/out/x.exr"

[ $failures -eq 0 ] || { echo "$failures failure(s)"; exit 1; }
