#!/usr/bin/env bash
# Careless and hostile use of the gimg command line, one case per run: ./hostile.sh CASE
# Environment: GIMG (the binary), MAKE (make_hostile_files), WORK (a scratch folder of its own),
# DATA (tests/data/meshes).
# Every case asserts the exit code, the one-line message and which files exist afterwards; ctest
# gives each 10 seconds.
set -uo pipefail
case_name=$1
W="$WORK/$case_name"
rm -rf "$W" && mkdir -p "$W" && cd "$W" || exit 1

failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# run CODE REGEX CMD...: CMD exits CODE; if CODE != 0, stderr is one line matching REGEX.
run() {
  local want=$1 regex=$2
  shift 2
  "$@" >"$W/out" 2>"$W/err"
  local got=$?
  [ "$got" -eq "$want" ] || fail "'$*' exited $got, not $want: $(cat "$W/err")"
  if [ "$want" -ne 0 ]; then
    [ "$(wc -l <"$W/err")" -eq 1 ] || fail "'$*': stderr is not one line: $(cat "$W/err")"
    grep -Eq "^gimg: error: .*$regex" "$W/err" || fail "'$*': stderr '$(cat "$W/err")' does not match '$regex'"
  fi
}
exists() { for f in "$@"; do [ -e "$f" ] || fail "$f is missing"; done; }
absent() { for f in "$@"; do [ ! -e "$f" ] || fail "$f exists but must not"; done; }
no_temps() { local t; t=$(find "$W" -name '*.gimg-*.tmp' | head -1); [ -z "$t" ] || fail "temporary file left: $t"; }

"$MAKE" image good "$W/good" >/dev/null || exit 1
cp "$W/good/distance.exr" "$W/good.exr.bak"

case "$case_name" in
nonregular_outputs)
  "$MAKE" scaled 1 "$W/m.off"
  mkfifo "$W/pipe.json"
  run 2 "not a regular file" "$GIMG" info "$W/m.off" --json "$W/pipe.json"
  run 2 "not a regular file" "$GIMG" cylinder "$W/m.off" --out "$W/c" --json "$W/pipe.json"
  [ -p "$W/pipe.json" ] || fail "the pipe was replaced"
  absent "$W/c/distance.exr"
  echo '{"keep": 1}' >"$W/target.json"
  ln -s "$W/target.json" "$W/link.json"
  run 2 "symbolic link" "$GIMG" info "$W/m.off" --json "$W/link.json"
  [ -L "$W/link.json" ] || fail "the link was replaced"
  grep -q keep "$W/target.json" || fail "the link's target changed"
  run 0 "" "$GIMG" info "$W/m.off" --json -
  grep -q '"vertices"' "$W/out" || fail "--json - wrote no JSON to standard output"
  ;;
output_is_input)
  "$MAKE" scaled 1 "$W/m.off"
  cp "$W/m.off" "$W/m.keep"
  run 2 "must end in .png" "$GIMG" render "$W/m.off" --out "$W/m.off"
  cmp -s "$W/m.off" "$W/m.keep" || fail "the input mesh changed"
  run 2 "must end in .png" "$GIMG" render "$W/m.off" --out "$W/x.jpg"
  absent "$W/x.jpg"
  run 2 "must end in .ply or .obj" "$GIMG" repair "$W/m.off" --out "$W/m.off"
  run 2 "also written as --out" "$GIMG" cylinder "$W/m.off" --out "$W/d" --json "$W/d/frame.json"
  absent "$W/d/distance.exr"
  run 2 "also written as --out" "$GIMG" sphere "$W/m.off" --out "$W/s" --json "$W/s/metrics.json"
  run 2 "is an input" "$GIMG" reconstruct "$W/good/distance.exr" --out "$W/r.ply" --json "$W/good/frame.json"
  cmp -s "$W/good/distance.exr" "$W/good.exr.bak" || fail "the input image changed"
  ;;
signal_leaves_nothing)
  "$MAKE" scaled 1 "$W/m.off"
  # The roundtrip writes its image files (as temporary files) and then measures for seconds.
  "$GIMG" roundtrip "$W/m.off" --out "$W/rt" --size 256x128 --samples 20000000 >/dev/null 2>&1 &
  pid=$!
  for _ in $(seq 100); do
    [ -n "$(find "$W/rt" -name '.distance.exr.gimg-*.tmp' 2>/dev/null | head -1)" ] && break
    sleep 0.05
  done
  [ -n "$(find "$W/rt" -name '.distance.exr.gimg-*.tmp' 2>/dev/null | head -1)" ] || fail "no temporary file seen"
  kill -TERM "$pid"
  wait "$pid"
  code=$?
  [ "$code" -eq 143 ] || fail "the run ended with $code, not by SIGTERM (143)"
  no_temps
  absent "$W/rt/distance.exr" "$W/rt/frame.json" "$W/rt/reconstruction.ply" "$W/rt"
  # A temporary file a killed run left (its process gone) is cleaned by the next write.
  mkdir -p "$W/c"
  touch "$W/c/.frame.json.gimg-999999999-0.tmp"
  run 0 "" "$GIMG" cylinder "$W/m.off" --out "$W/c" --size 32x16
  no_temps
  exists "$W/c/frame.json"
  ;;
mixed_runs)
  "$MAKE" scaled 1 "$W/m.off"
  printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n' >"$W/other.off"
  run 0 "" "$GIMG" cylinder "$W/m.off" --out "$W/a" --size 64x32
  run 0 "" "$GIMG" cylinder "$W/other.off" --out "$W/b" --size 64x32
  cp "$W/b/distance.exr" "$W/a/distance.exr"
  run 2 "not the image" "$GIMG" reconstruct "$W/a/distance.exr" --out "$W/r.ply"
  run 0 "" "$GIMG" cylinder "$W/other.off" --out "$W/c" --size 32x16
  cp "$W/c/distance.exr" "$W/b/distance.exr"
  run 2 "describes a 64x32 image" "$GIMG" reconstruct "$W/b/distance.exr" --out "$W/r.ply"
  absent "$W/r.ply"
  ;;
bounded_work)
  "$MAKE" copies 10000 "$W/c10k.off"
  "$MAKE" copies 100000 "$W/c100k.off"
  run 0 "" "$GIMG" compare "$W/c10k.off" "$W/c10k.off"
  run 0 "" "$GIMG" cylinder "$W/c100k.off" --out "$W/c" --method raycast
  run 0 "" "$GIMG" render "$W/c100k.off" --out "$W/c.png"
  run 2 "--samples takes a whole number" "$GIMG" roundtrip "$W/c10k.off" --out "$W/rt" --samples -1
  run 2 "--samples takes a whole number" "$GIMG" roundtrip "$W/c10k.off" --out "$W/rt" --samples 4294967296
  absent "$W/rt"
  ;;
pictures_at_any_scale)
  for s in 1e-15 1e20 1e38; do
    "$MAKE" scaled "$s" "$W/m$s.off"
    run 0 "" "$GIMG" render "$W/m$s.off" --out "$W/m$s.png"
  done
  "$MAKE" stray "$W/stray.off"
  run 0 "" "$GIMG" render "$W/stray.off" --out "$W/stray.png"
  run 0 "" "$GIMG" cylinder "$W/stray.off" --out "$W/c" --json "$W/c.json"
  grep -Eq '"covered_pixels": [1-9]' "$W/c.json" || fail "the stray-vertex model covers no pixel"
  "$MAKE" flat "$W/flat.off"
  run 2 "shows nothing" "$GIMG" render "$W/flat.off" --out "$W/flat.png"
  run 2 "covers no pixel" "$GIMG" cylinder "$W/flat.off" --out "$W/f"
  absent "$W/flat.png" "$W/f/distance.exr"
  ;;
checks_before_writing)
  "$MAKE" scaled 1 "$W/m.off"
  run 2 "at least 2x2" "$GIMG" roundtrip "$W/m.off" --out "$W/rt" --size 1x1
  absent "$W/rt"
  printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n' >"$W/tetra.off"
  run 0 "" "$GIMG" roundtrip "$W/tetra.off" --out "$W/tiny" --samples 1000
  exists "$W/tiny/reconstruction.ply" "$W/tiny/compare.png"
  ;;
nothing_to_reconstruct)
  for kind in empty checker; do
    "$MAKE" image "$kind" "$W/$kind" >/dev/null
    run 2 "nothing to reconstruct" "$GIMG" reconstruct "$W/$kind/distance.exr" --out "$W/$kind.ply"
    absent "$W/$kind.ply"
  done
  run 2 "nothing to reconstruct: every block" "$GIMG" reconstruct "$W/good/distance.exr" --out "$W/t0.ply" --threshold 0
  absent "$W/t0.ply"
  ;;
bad_image_data)
  run 2 "no channel \"mask\"" sh -c "'$MAKE' image no-mask '$W/nm' && '$GIMG' reconstruct '$W/nm/distance.exr' --out '$W/x.ply'"
  run 2 "mask = nan" sh -c "'$MAKE' image nan-mask '$W/nan' && '$GIMG' reconstruct '$W/nan/distance.exr' --out '$W/x.ply'"
  run 2 "data window" sh -c "'$MAKE' image window '$W/win' && '$GIMG' reconstruct '$W/win/distance.exr' --out '$W/x.ply'"
  run 2 "rotation is not a rotation" sh -c "'$MAKE' image zero-rotation '$W/rot' && '$GIMG' reconstruct '$W/rot/distance.exr' --out '$W/x.ply'"
  absent "$W/x.ply"
  ;;
plain_messages)
  "$MAKE" scaled 1 "$W/m.off"
  run 2 "more than this device projects at once" "$GIMG" cylinder "$W/m.off" --out "$W/big" --size 16384x16384
  absent "$W/big"
  mkdir -p "$W/dirframe" && cp "$W/good/distance.exr" "$W/dirframe/" && mkdir "$W/dirframe/frame.json"
  run 2 "is a folder" "$GIMG" reconstruct "$W/dirframe/distance.exr" --out "$W/x.ply"
  run 1 "no Vulkan driver found" env VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json \
    "$GIMG" cylinder "$W/m.off" --out "$W/nv"
  run 2 "unknown command 'frobnicate'" "$GIMG" frobnicate
  run 2 "not expected: --loud" "$GIMG" info "$W/m.off" --loud
  touch "$W/afile"
  run 2 "is a file; it takes a folder" "$GIMG" sphere "$W/m.off" --out "$W/afile"
  run 2 "is a file; it takes a folder" "$GIMG" cylinder "$W/m.off" --out "$W/afile"
  ;;
cpu_methods_without_vulkan)
  "$MAKE" scaled 1 "$W/m.off"
  for method in kanai linear; do
    VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json \
      "$GIMG" --quiet sphere "$W/m.off" --out "$W/$method" --method "$method" >/dev/null 2>&1 ||
      fail "sphere --method $method without a Vulkan driver failed"
    exists "$W/$method/sphere.ply" "$W/$method/metrics.json"
  done
  for cmd in "cylinder $W/m.off --out $W/ray --method raycast" "cylinder $W/m.off --out $W/scan --method scanline" \
             "reconstruct $W/good/distance.exr --out $W/r.ply --cpu" "compare $W/m.off $W/m.off" "info $W/m.off" \
             "repair $W/m.off --out $W/rep.ply"; do
    # shellcheck disable=SC2086
    VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json "$GIMG" --quiet $cmd >/dev/null 2>&1 ||
      fail "'gimg $cmd' without a Vulkan driver failed"
  done
  ;;
strict_numbers)
  "$MAKE" scaled 1 "$W/m.off"
  run 2 "--max-iterations takes a whole number" "$GIMG" sphere "$W/m.off" --out "$W/s" --max-iterations -1
  run 2 "--seed takes a whole number" "$GIMG" compare "$W/m.off" "$W/m.off" --seed -1
  run 2 "--lod takes a whole number" "$GIMG" reconstruct "$W/good/distance.exr" --out "$W/x.ply" --lod 0x10
  run 2 "--threshold takes a distance" "$GIMG" reconstruct "$W/good/distance.exr" --out "$W/x.ply" --threshold 1e-400
  run 2 "--runs takes a whole number" "$GIMG" bench cylinder --runs 0
  run 1 "cannot write to standard output" sh -c "'$GIMG' info '$W/m.off' >/dev/full"
  absent "$W/s" "$W/x.ply"
  ;;
polycube_refusals)
  printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n' >"$W/tetra.off"
  printf 'OFF\n8 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n5 0 0\n6 0 0\n5 1 0\n5 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n3 4 6 5\n3 4 5 7\n3 5 6 7\n3 4 7 6\n' >"$W/two.off"
  run 2 "the mesh has 2 pieces; a polycube needs one" "$GIMG" polycube "$W/two.off" --out "$W/p"
  run 2 "--da takes a number" "$GIMG" polycube "$W/tetra.off" --out "$W/p" --da 0
  run 2 "--dz takes a number" "$GIMG" polycube "$W/tetra.off" --out "$W/p" --dz -1
  run 2 "--axis" "$GIMG" polycube "$W/tetra.off" --out "$W/p" --axis w
  run 2 "--slice-smoothing takes a whole number from 0 to 1000" "$GIMG" polycube "$W/tetra.off" --out "$W/p" --slice-smoothing 1001
  run 2 "the mesh is flat: closed off, it encloses no volume" "$GIMG" polycube "$DATA/quad_uv.obj" --out "$W/p"
  absent "$W/p/polycube.obj" "$W/p/mapped.ply"
  run 0 "" "$GIMG" polycube "$W/tetra.off" --out "$W/t" --axis y
  exists "$W/t/polycube.obj" "$W/t/mapped.ply" "$W/t/checker.png" "$W/t/polycube.png"
  no_temps
  ;;
batch_shards_cover_once)
  # Twelve models in nested folders, one of them broken: every shard count covers each model once,
  # the broken one recorded with its message, and the shards merge into the single run's results.
  mkdir -p "$W/coll/a" "$W/coll/b"
  for i in 1 2 3 4 5 6; do "$MAKE" scaled "$i" "$W/coll/a/m$i.off"; "$MAKE" scaled "$i" "$W/coll/b/m$i.off"; done
  printf 'OFF\n3 1 0\n0 0 0\n1 0\n' >"$W/coll/b/broken.off"
  run 0 "" "$GIMG" batch info --inputs "$W/coll" --out "$W/one" --quiet
  [ "$(wc -l <"$W/one/results.jsonl")" -eq 13 ] || fail "the single run has $(wc -l <"$W/one/results.jsonl") lines, not 13"
  grep -q '"model":"broken","result":null,"seconds".*"status":"failed"' "$W/one/results.jsonl" ||
    grep -q '"error":"[^"]*broken.off: the OFF header' "$W/one/results.jsonl" || fail "the broken model is not recorded"
  [ "$(grep -c '"status":"ok"' "$W/one/results.jsonl")" -eq 12 ] || fail "not 12 models ok"
  for n in 1 2 3 4 5 6 7; do
    for k in $(seq 0 $((n - 1))); do
      run 0 "" "$GIMG" batch info --inputs "$W/coll" --out "$W/shards$n" --shard "$k/$n" --quiet
    done
    run 0 "" "$GIMG" batch merge "$W/shards$n" --out "$W/merged$n.jsonl" --quiet
    diff <(grep -o '"model":"[^"]*"' "$W/merged$n.jsonl" | sort) <(grep -o '"model":"[^"]*"' "$W/one/results.jsonl" | sort) >/dev/null ||
      fail "$n shards do not cover the collection once"
  done
  # The merged results equal the single run's, timings aside.
  strip() { sed -E 's/"seconds":[^,}]*//g' "$1" | sort; }
  [ "$(strip "$W/merged3.jsonl")" = "$(strip "$W/one/results.jsonl")" ] || fail "3 merged shards differ from one run"
  run 2 "is in both" "$GIMG" batch merge "$W/shards2" "$W/one" --out "$W/bad.jsonl"
  rm "$W/shards2/results-1-of-2.jsonl"
  run 2 "shard 1 of 2 is missing" "$GIMG" batch merge "$W/shards2" --out "$W/bad.jsonl"
  run 2 "--shard takes K/N" "$GIMG" batch info --inputs "$W/coll" --out "$W/x" --shard 3/3
  run 2 "holds an earlier run" "$GIMG" batch info --inputs "$W/coll" --out "$W/one"
  absent "$W/bad.jsonl" "$W/x"
  ;;
batch_index_from_shards)
  # Features per shard, one PCA at the end: the same database as indexing the collection at once.
  mkdir -p "$W/coll"
  cp "$DATA"/*.obj "$DATA"/*.off "$DATA"/*.ply "$W/coll/"
  "$MAKE" scaled 1 "$W/coll/sphere.off"
  "$MAKE" stray "$W/coll/stray.off"
  run 0 "" "$GIMG" index "$W/coll" --out "$W/direct.json" --quiet
  for k in 0 1 2; do run 0 "" "$GIMG" batch features --inputs "$W/coll" --out "$W/f" --shard "$k/3" --quiet; done
  run 0 "" "$GIMG" index "$W/coll" --from-shards "$W/f" --out "$W/shards.json" --quiet
  cmp -s "$W/direct.json" "$W/shards.json" || fail "the index from 3 shards differs from the direct index"
  rm "$W/f/results-1-of-3.jsonl"
  run 2 "shard 1 of 3 is missing" "$GIMG" index "$W/coll" --from-shards "$W/f" --out "$W/bad.json"
  absent "$W/bad.json"
  ;;
batch_resume_after_kill)
  # A batch killed (SIGKILL) mid-run, then resumed: every model once, none redone, nothing partial.
  mkdir -p "$W/coll"
  for i in $(seq 1 24); do "$MAKE" scaled "$i" "$W/coll/m$i.off"; done
  "$GIMG" batch cylinder --inputs "$W/coll" --out "$W/run" --quiet -- --size 512x256 >/dev/null 2>&1 &
  pid=$!
  for _ in $(seq 200); do
    [ -f "$W/run/results.jsonl" ] && [ "$(wc -l <"$W/run/results.jsonl")" -ge 3 ] && break
    sleep 0.02
  done
  kill -KILL "$pid"
  wait "$pid" 2>/dev/null
  before=$(wc -l <"$W/run/results.jsonl")
  [ "$before" -ge 3 ] && [ "$before" -lt 24 ] || fail "the kill came at $before of 24 models, not mid-run"
  first=$(grep -o '"model":"[^"]*"' "$W/run/results.jsonl" | head -1 | cut -d'"' -f4)
  stamp=$(stat -c %Y.%N "$W/run/$first/frame.json" 2>/dev/null)
  run 2 "holds an earlier run" "$GIMG" batch cylinder --inputs "$W/coll" --out "$W/run" -- --size 512x256
  run 0 "" "$GIMG" batch cylinder --inputs "$W/coll" --out "$W/run" --resume --quiet -- --size 512x256
  [ "$(wc -l <"$W/run/results.jsonl")" -eq 24 ] || fail "$(wc -l <"$W/run/results.jsonl") lines after the resume, not 24"
  [ "$(grep -c '"status":"ok"' "$W/run/results.jsonl")" -eq 24 ] || fail "not every model ok after the resume"
  [ "$(grep -o '"model":"[^"]*"' "$W/run/results.jsonl" | sort -u | wc -l)" -eq 24 ] || fail "a model twice"
  [ "$(stat -c %Y.%N "$W/run/$first/frame.json")" = "$stamp" ] || fail "$first was redone"
  for i in $(seq 1 24); do exists "$W/run/m$i/distance.exr" "$W/run/m$i/frame.json" "$W/run/m$i/result.json"; done
  ;;
*)
  echo "unknown case $case_name"
  exit 2 ;;
esac

no_temps
[ "$failures" -eq 0 ] && echo "ok: $case_name" && exit 0
exit 1
