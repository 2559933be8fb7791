#!/usr/bin/env bash
# The GPU checklist of ../shared/device/README.md as two steps, so that a session lent a GPU machine
# (Ubuntu, the NVIDIA driver, no Debian packages, minutes of device time) spends them measuring:
#
#   ./run device-stage        here: build, then pack into .device/stage.tar.xz the binaries, the
#                             libraries they link, the validation layer, the shared meshes and the
#                             large fetched ones, and download the Vulkan loader's packages into .gl
#   ./run device-check [OUT]  there (the device tool, carrying .device and .gl): unpack, install the
#                             loader, and run every benchmark and the GPU tests, each under a time
#                             limit and all under DEVICE_CHECK_SECONDS (default 480), writing
#                             summary.txt and device-check.tar.gz (the logs and --json files) into
#                             OUT (default $OUT, else build/device-check)
#
# `./run device-check` also runs here on lavapipe (it then leaves the installed loader alone), which
# is how the script itself is tested; DEVICE_CHECK_SECONDS bounds it there too.
set -uo pipefail
cd "$(dirname "$0")/../.."

stage() {
  local stage=.device/stage
  rm -rf "$stage" && mkdir -p "$stage/bin" "$stage/lib" "$stage/meshes" "$stage/large/derived"
  cp build/gimg build/tests/engine/gimg_engine_gpu_tests build/tests/passes/gimg_passes_tests "$stage/bin/"
  for b in "$stage"/bin/*; do ../shared/device/collect-libs.sh "$b" "$stage/lib" >/dev/null; done
  # The Khronos validation layer, which the GPU tests require: its manifest names the library
  # relative to itself.
  mkdir -p "$stage/layers"
  cp /usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so "$stage/layers/"
  sed 's|"library_path": "[^"]*"|"library_path": "./libVkLayer_khronos_validation.so"|' \
    /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json > "$stage/layers/VkLayer_khronos_validation.json"
  # The shared meshes but the two largest scans and the retrieval archive (no benchmark reads them).
  find ../shared/meshes -maxdepth 1 -type f \( -name '*.off' -o -name '*.obj' -o -name '*.ply' \) \
    ! -name 'snowden*' -exec cp {} "$stage/meshes/" \;
  local large=${GIMG_LARGE_MESH_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/gimg-large-meshes}
  if [ ! -s "$large/dragon.ply" ]; then
    sh ../shared/meshes/fetch_large.sh "$large" >/dev/null || echo "device-stage: the large meshes could not be fetched; the checklist runs without them"
  fi
  for m in dragon.ply derived/bunny_loop1.off derived/armadillo_loop1.off; do
    [ -s "$large/$m" ] && cp "$large/$m" "$stage/large/$m"
  done
  tar -C "$stage" -cf - . | xz -T0 -6 > .device/stage.tar.xz
  rm -rf "$stage"
  # The Vulkan loader, for a machine without it.
  if ! ls .gl/libvulkan1_*.deb >/dev/null 2>&1; then
    mkdir -p .gl /tmp/amd64/partial
    local o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64)
    apt-get "${o[@]}" update -qq && (cd .gl && apt-get "${o[@]}" download libvulkan1 libegl1 libglvnd0 libopengl0 \
      libgl1 libglx0 libgles2 >/dev/null)
  fi
  du -ch .device/stage.tar.xz .gl | tail -n 1 | sed 's/total/to carry (.device and .gl; the device tool takes 64 MiB)/'
}

check() {
  local out=${1:-${OUT:-build/device-check}}
  [ -s .device/stage.tar.xz ] || { echo "device-check: no .device/stage.tar.xz (run ./run device-stage first)" >&2; exit 2; }
  mkdir -p "$out"
  local dest work
  dest=$(cd "$out" && pwd)
  work=$(mktemp -d)
  # Everything is written to one folder and packed at the end: the device tool brings back only a
  # few files from OUT.
  out="$work/out"
  mkdir -p "$out"
  tar -C "$work" -xJf .device/stage.tar.xz
  if ! ldconfig -p 2>/dev/null | grep -q 'libvulkan.so.1 '; then
    for f in .gl/*.deb; do dpkg -x "$f" /; done
    ldconfig
  fi
  export LD_LIBRARY_PATH="$work/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" VK_LAYER_PATH="$work/layers"
  if [ -z "${VK_DRIVER_FILES:-}" ]; then
    for icd in /usr/share/vulkan/icd.d/nvidia_icd.json /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json \
               /etc/vulkan/icd.d/nvidia_icd.json; do
      [ -f "$icd" ] && export VK_DRIVER_FILES=$icd VK_ICD_FILENAMES=$icd && break
    done
  fi
  export GIMG_MESH_DIR="$work/meshes" GIMG_LARGE_MESH_DIR="$work/large"
  local gimg="$work/bin/gimg" m="$work/meshes" started=$SECONDS budget=${DEVICE_CHECK_SECONDS:-480}
  : > "$out/summary.txt"
  # step NAME LIMIT COMMAND...: skipped once the budget is spent; its log and exit status recorded.
  step() {
    local name=$1 limit=$2 left=$((budget - (SECONDS - started)))
    shift 2
    if [ "$left" -le 5 ]; then echo "$name: skipped (budget spent)" | tee -a "$out/summary.txt"; return; fi
    [ "$limit" -gt "$left" ] && limit=$left
    local t0=$SECONDS
    timeout "$limit" "$@" > "$out/$name.log" 2>&1
    echo "$name: exit $?, $((SECONDS - t0)) s (limit $limit s)" | tee -a "$out/summary.txt"
  }
  step devices 30 "$gimg" devices
  # What a round trip costs there: it bounds every iterative GPU path that reads back between
  # submissions. execute_sleeping_wait_us against execute_polling_wait_us says whether polling the
  # timeline before sleeping (ContextOptions::wait_spin_us, 1000 us on a GPU) pays there.
  step engine 30 "$gimg" bench engine --runs 200 --json "$out/bench-engine.json"
  # The open issues' real-GPU goals first: dragon at 1024 x 1024 hierarchical (2 ms), quad-region
  # corner edits (4 ms).
  [ -s "$work/large/dragon.ply" ] && step hierarchical-dragon 90 "$gimg" bench hierarchical --mesh "$work/large/dragon.ply" \
    --size 1024 --samples 100000 --runs 2 --json "$out/bench-hierarchical-dragon.json"
  step quadmap 90 "$gimg" bench quadmap --runs 3 --json "$out/bench-quadmap.json"
  step cylinder 90 "$gimg" bench cylinder --runs 5 --json "$out/bench-cylinder.json"
  step reconstruct 30 "$gimg" bench reconstruct --json "$out/bench-reconstruct.json"
  # The GPU map against the linear method (Kanai's and Gu's are CPU methods, measured elsewhere).
  step sphere 90 "$gimg" bench sphere --runs 1 --method harmonic --method linear --json "$out/bench-sphere.json"
  step hierarchical 60 "$gimg" bench hierarchical --samples 100000 --json "$out/bench-hierarchical.json"
  step maps 90 "$gimg" bench maps --mesh "$m/bunny_small.obj" --mesh "$m/eight.off" --wavelet-mesh "$m/armadillo.off" \
    --samples 100000 --json "$out/bench-maps.json"
  # Its rows' submissions and device_wait_seconds say whether a reweighting iteration's time (70-90 ms
  # on the H200 against ~45 ms on lavapipe) is round trips, the device's work or the host's.
  step gim 90 "$gimg" bench gim --mesh "$m/mannequin_devil.off" --size 0 --samples 100000 --no-cpu \
    --json "$out/bench-gim.json"
  # A closed mesh cut open: the cut's nine Floater maps and the curvature map, each many small solves.
  step gim-cut 45 "$gimg" gim "$m/camel.off" --cut --samples 100000 --out "$work/gim-cut" --json "$out/gim-cut-camel.json"
  step retrieval 60 "$gimg" bench retrieval --models 2000 --json "$out/bench-retrieval.json"
  step polycube-gpu 45 "$gimg" polycube "$m/elk.off" --axis z --out "$work/polycube-gpu" --json "$out/polycube-elk-gpu.json"
  step polycube-cpu 45 "$gimg" polycube "$m/elk.off" --axis z --cpu --out "$work/polycube-cpu" --json "$out/polycube-elk-cpu.json"
  step engine-tests 60 "$work/bin/gimg_engine_gpu_tests" --gtest_brief=1
  step passes-tests 200 "$work/bin/gimg_passes_tests" --gtest_brief=1
  echo "device-check: $((SECONDS - started)) s" | tee -a "$out/summary.txt"
  cp "$out/summary.txt" "$dest/summary.txt"
  tar -C "$out" -czf "$dest/device-check.tar.gz" .
  echo "device-check: summary.txt and device-check.tar.gz (logs and --json files) in $dest"
  rm -rf "$work"
}

case "${1:-}" in
  stage) stage ;;
  check) shift; check "$@" ;;
  *) echo "usage: tests/device/checklist.sh stage|check [OUT]" >&2; exit 2 ;;
esac
