"""The figures of docs/python.md: the call overhead and the throughput of lists against `gimg batch`.

    PYTHONPATH=build/python GIMG_BIN=build/gimg python3 tests/python/bench_python.py [MESHES]

MESHES defaults to ../shared/meshes. Prints one line per figure.
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import gimg

MESHES = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "../../../shared/meshes")
GIMG = os.environ.get("GIMG_BIN", "build/gimg")
device = gimg.Device()
print("device:", device.name)

# Call overhead: one cylinder() call from Python against the same body timed inside C++ (frame,
# Z-buffer, upload, projection), alternated call by call so both see the same machine.
positions, faces = gimg.load_mesh(os.path.join(MESHES, "chinese_dragon_10k.off"))
for _ in range(20):
    gimg.cylinder(device, positions, faces, width=256, height=128)
ratios = []
for rnd in range(5):
    from_python, in_cpp = [], []
    for _ in range(300):
        t = time.perf_counter()
        gimg.cylinder(device, positions, faces, width=256, height=128)
        from_python.append((time.perf_counter() - t) * 1e3)
        in_cpp.append(gimg._cylinder_ms_in_cpp(device, positions, faces, 256, 128, 1))
    a, b = statistics.median(from_python), statistics.median(in_cpp)
    ratios.append(a / b)
    print(f"overhead round {rnd}: Python {a:.3f} ms, C++ {b:.3f} ms, {100 * (a / b - 1):+.1f} %")
print(f"overhead: median of the rounds {100 * (statistics.median(ratios) - 1):+.1f} %")

# Lists: 256 perturbed copies of five closed genus-0 shared meshes, from Python and through `gimg batch`.
rng = np.random.default_rng(7)
sources = ["bunny_small.obj", "blobby.off", "hand.off", "cow.off", "homer.off"]  # genus 0, for sphere
meshes = []
for k in range(256):
    p, f = gimg.load_mesh(os.path.join(MESHES, sources[k % len(sources)]))
    scale = np.linalg.norm(p.max(0) - p.min(0))
    meshes.append((p + rng.normal(0.0, 1e-3 * scale, p.shape), f))
with tempfile.TemporaryDirectory() as folder:
    for k, (p, f) in enumerate(meshes):
        gimg.save_mesh(os.path.join(folder, f"m{k:03d}.ply"), p, f)

    def rate(run, repeats):
        seconds = []
        for _ in range(repeats):
            t = time.perf_counter()
            run()
            seconds.append(time.perf_counter() - t)
        return len(meshes) / statistics.median(seconds)

    for name, options, cli, repeats in [
        ("info", {}, [], 5),
        ("cylinder", {"device": device, "width": 144, "height": 144}, ["--size", "144x144"], 5),
        ("sphere", {"device": device}, [], 1),
    ]:
        function = getattr(gimg, name)
        listed = rate(lambda: gimg.batch(function, meshes, **options), repeats)
        one_by_one = rate(lambda: [function(positions=p, faces=f, **options) for p, f in meshes], repeats)
        out = os.path.join(folder, "out-" + name)

        def command():
            subprocess.run([GIMG, "batch", name, "--inputs", folder, "--out", out, "--", *cli], check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            subprocess.run(["rm", "-rf", out], check=True)

        batch = rate(command, 1 if name == "sphere" else 3)
        print(f"{name}: gimg.batch {listed:.0f} models/s, a call per mesh {one_by_one:.0f}/s, "
              f"gimg batch {batch:.0f}/s ({listed / batch:.1f}x)")
