#!/usr/bin/env python3
"""Blender 3.4's Ocean modifier and libwave's FFT ocean on the same grids, in one run
(shared machines are noisy: only ratios taken minutes apart mean something).
    python3 bench/peers/ocean_side_by_side.py build/release/bench/libwave_bench
Prints one line per grid: Blender ms/frame, libwave surface frame and `wave run` frame
(ms), the FFTW floor, and the ratios."""
import json
import os
import re
import subprocess
import sys

bench = sys.argv[1] if len(sys.argv) > 1 else "build/release/bench/libwave_bench"
here = os.path.dirname(os.path.abspath(__file__))
blender = subprocess.run(["blender", "-b", "--factory-startup", "--python", os.path.join(here, "blender_ocean.py")],
                         capture_output=True, text=True, timeout=1800)
found = list(re.finditer(r"BLENDER-OCEAN grid=(\d+) vertices=\d+ ms_per_frame=([\d.]+) rounds=([\d./]+)", blender.stdout))
peer = {int(m.group(1)): float(m.group(2)) for m in found}
rounds = {int(m.group(1)): m.group(3) for m in found}
if not peer:
    sys.exit("blender produced no measurement:\n" + blender.stdout[-2000:] + blender.stderr[-2000:])
# Medians of five repetitions (Blender's: of three rounds): a single one swings by tens
# of per cent on a shared machine.
ours = subprocess.run([bench, "--benchmark_filter=BM_fftw_floor|BM_fftw_packed_floor|BM_ocean_surface_frame|BM_ocean_stream_frames",
                       "--benchmark_repetitions=5", "--benchmark_report_aggregates_only=true",
                       "--benchmark_format=json"], capture_output=True, text=True, timeout=1800, check=True)
times = {b["run_name"].replace("/real_time", ""): b["real_time"] for b in json.loads(ours.stdout)["benchmarks"]
         if b.get("aggregate_name") == "median"}
for grid in sorted(peer):
    floor = times[f"BM_fftw_floor/{grid}/1"]  # the eight real transforms, patient plans (bench/fftw_floor_wisdom.inc)
    packed = times[f"BM_fftw_packed_floor/{grid}/1"]  # the four complex transforms a frame computes now
    estimate = times[f"BM_fftw_floor/{grid}/0"]
    surface = times[f"BM_ocean_surface_frame/{grid}"]
    line = (f"grid {grid}²: Blender {peer[grid]:.1f} ms/frame (rounds {rounds[grid]}); libwave surface frame {surface:.2f} ms "
            f"({peer[grid] / surface:.1f}x faster), FFTW floor {floor:.2f} ms ({surface / floor:.2f}x the floor; "
            f"FFTW_ESTIMATE's plan {estimate:.2f} ms; the four packed transforms {packed:.2f} ms)")
    # `wave run`'s steady cost per frame (its streamed path, arrays reused from chunk to
    # chunk): a run of F frames minus a run of 1, over F − 1.
    runs = {int(k.split("/")[2]): v for k, v in times.items() if k.startswith(f"BM_ocean_stream_frames/{grid}/")}
    if len(runs) == 2:
        many = max(runs)
        steady = (runs[many] - runs[1]) / (many - 1)
        line += (f"; wave run {steady:.2f} ms/frame with the per-frame arrays and faded foam "
                 f"({peer[grid] / steady:.1f}x faster; its first frame {runs[1]:.0f} ms)")
    print(line)
