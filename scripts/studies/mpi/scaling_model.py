#!/usr/bin/python3
"""Predicted parallel efficiency of `mpirun -np N pathtracer` for a 1920x1080
4096-spp CBbunny render, by a discrete-event simulation of the tile protocol
(distributed/mpi_render.cpp) fed with figures measured by measure_tiles.sh.

  scaling_model.py [MEASUREMENTS.json]   the tables (default out/mpi/measurements.json)
  scaling_model.py measure ...           what measure_tiles.sh calls to write MEASUREMENTS.json

The model (docs/scaling_out.md):
- Every rank is one core (-t 1), as fast as the measuring machine's core;
  a variant has a quarter of the ranks at half speed.
- A tile's time at 4096 spp = (measured - per-tile overhead) * 4096 / SPP +
  per-tile overhead; the overhead comes from fitting the total time of each
  tile size against its tile count (fewer, larger tiles cost less to set up).
- Rank 0 renders tiles too and answers requests in a second thread, one at a
  time: a request costs it LATENCY + bytes / BANDWIDTH of its time; a reply
  reaches the rank one LATENCY later. A result is 20 B per pixel + 72 B.
  Requests queue when rank 0's thread is busy: that is when rank 0 becomes
  the bottleneck, and its utilisation is reported.
- Start: mpirun's launch (measured for 2 ranks, plus LAUNCH_PER_DOUBLING per
  doubling of the rank count, for a tree launch), then every rank loads the
  scene and builds its BVH (measured) at the same time.
- Efficiency(N) = T(1) / (N * T(N)), with T(1) one process rendering every
  tile without MPI.
"""
import argparse
import heapq
import json
import math
import os
import shlex
import statistics
import struct
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))  # scripts/: ptlib
from ptlib import results  # noqa: E402
from ptlib.paired import run_rounds  # noqa: E402

LATENCY = 50e-6           # s, one way, per message (cluster Ethernet; plus the 0.2 ms polling of rank 0)
POLL = 100e-6             # s, mean wait of rank 0's polling thread (it sleeps 0.2 ms between polls)
BANDWIDTH = 1.25e9        # B/s (10 Gb Ethernet)
LAUNCH_PER_DOUBLING = 0.05  # s
TARGET_SPP = 4096


def read_tile_set(path):
    """Tile numbers, pixel counts and seconds of a tile set (io/tile_set.cpp)."""
    data = open(path, "rb").read()
    assert data[:8] == b"PTTILES1", path
    at = 8
    (fp_len,) = struct.unpack_from("<I", data, at)
    at += 4 + fp_len
    width, height, max_samples, tile_size = struct.unpack_from("<iiIi", data, at)
    at += 16 + 16 + 2 + 6 * 8 + 8
    (count,) = struct.unpack_from("<I", data, at)
    at += 4
    tiles = []
    for _ in range(count):
        t, seconds, n = struct.unpack_from("<IdI", data, at)
        at += 16 + n * 20
        tiles.append((t, n, seconds))
    tiles.sort()
    return {"width": width, "height": height, "tile": tile_size, "tiles": tiles}


def simulate(costs, pixels, ranks, speeds, startup):
    """Makespan of the tile protocol and rank 0's server utilisation."""
    queue = list(range(len(costs)))
    queue.reverse()
    events = []  # (time, kind, rank)
    server_free = startup
    server_busy = 0.0
    end = startup
    # rank 0 renders: it takes tiles directly.
    heapq.heappush(events, (startup, 0, 0))
    for r in range(1, ranks):
        heapq.heappush(events, (startup + LATENCY, 1, r, 0))  # request without a result
    holding = {}
    while events:
        ev = heapq.heappop(events)
        time, kind, rank = ev[0], ev[1], ev[2]
        if kind == 0:  # rank 0 free to render
            if queue:
                t = queue.pop()
                done = time + costs[t] / speeds[0]
                end = max(end, done)
                heapq.heappush(events, (done, 0, 0))
            continue
        # a request (with the previous tile's result of `nbytes`) reaches rank 0's thread
        nbytes = ev[3]
        start = max(time + POLL, server_free)
        service = LATENCY + nbytes / BANDWIDTH
        server_free = start + service
        server_busy += service
        end = max(end, server_free)
        if queue:
            t = queue.pop()
            arrive = server_free + LATENCY
            done = arrive + costs[t] / speeds[rank]
            heapq.heappush(events, (done + LATENCY + (20 * pixels[t] + 72) / BANDWIDTH, 1, rank, 20 * pixels[t] + 72))
    return end, server_busy / max(end - startup, 1e-9)


MPIRUN = "mpirun --oversubscribe --mca pml ob1 --mca btl self,vader"  # one machine: shared memory only


def seconds(command):
    start = time.perf_counter()
    subprocess.run(shlex.split(command), check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def measure_main(argv):
    """measure SPP PATHTRACER SCENE OUT --command CMD: the start-ups (5 alternating pairs of a process's and
    of mpirun's) and the tile sets measure_tiles.sh wrote, as a results record with the host."""
    p = argparse.ArgumentParser(prog="scaling_model.py measure")
    p.add_argument("spp", type=int)
    p.add_argument("pathtracer")
    p.add_argument("scene")
    p.add_argument("out")
    p.add_argument("--command", required=True)
    a = p.parse_args(argv)
    commands = {"process": f"{a.pathtracer} {a.scene} -r 1 1 -s 1 -t 1 -q -f out/mpi/startup.png",
                "mpirun": f"{MPIRUN} -np 2 {a.pathtracer} --list-isa"}
    runs = run_rounds(5, list(commands), lambda what, r: seconds(commands[what]))
    rec = results.new("mpi-tiles", "Tile times and start-ups for the scaling model", a.command, "",
                      spp=a.spp, process_startup_s=statistics.median(runs["process"]),
                      mpirun_startup_2_ranks_s=statistics.median(runs["mpirun"]),
                      tile_sets={t: f"out/mpi/tiles_{t}.tiles" for t in (16, 32, 64, 128)})
    results.save(a.out, rec)


def main():
    if len(sys.argv) > 1 and sys.argv[1] in ("-h", "--help"):
        sys.exit(__doc__)
    if len(sys.argv) > 1 and sys.argv[1] == "measure":
        return measure_main(sys.argv[2:])
    meas = json.load(open(sys.argv[1] if len(sys.argv) > 1 else "out/mpi/measurements.json"))
    spp = meas["spp"]
    sets = {int(k): read_tile_set(v) for k, v in meas["tile_sets"].items()}
    # Per-tile overhead: total(size) = work + tiles(size) * overhead, least squares.
    xs = [len(s["tiles"]) for s in sets.values()]
    ys = [sum(t[2] for t in s["tiles"]) for s in sets.values()]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    overhead = max(0.0, sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs))
    startup = meas["process_startup_s"]
    host = meas["host"]
    print(f"Measured on {host['cpu']} ({host['cores']} cores), commit {meas['commit']}: CBbunny 1920x1080 at {spp} spp, one thread; process start-up (load + BVH) "
          f"{startup:.3f} s, mpirun start-up with 2 ranks {meas['mpirun_startup_2_ranks_s']:.3f} s, "
          f"per-tile overhead {overhead * 1e3:.2f} ms")
    print()
    print("| tile | tiles | bytes per tile | 4096-spp tile time median (max) | one process T(1) |")
    print("|---|---|---|---|---|")
    scaled = {}
    for size, s in sorted(sets.items()):
        costs = [(sec - overhead) * TARGET_SPP / spp + overhead for _, _, sec in s["tiles"]]
        pixels = [n for _, n, _ in s["tiles"]]
        scaled[size] = (costs, pixels)
        med = sorted(costs)[len(costs) // 2]
        t1 = startup + sum(costs)
        print(f"| {size} | {len(costs)} | {20 * size * size + 72} | {med:.2f} s ({max(costs):.2f} s) | {t1 / 3600:.2f} h |")
    print()
    for label, slow in (("every rank as fast", False), ("a quarter of the ranks at half speed", True)):
        print(f"Predicted parallel efficiency ({label}); rank 0's request thread utilisation in brackets:")
        print()
        print("| tile | " + " | ".join(f"{n} ranks" for n in (8, 64, 512)) + " |")
        print("|---|---|---|---|")
        for size, (costs, pixels) in sorted(scaled.items()):
            t1 = startup + sum(costs)
            cells = []
            for n in (8, 64, 512):
                speeds = [0.5 if slow and r % 4 == 3 else 1.0 for r in range(n)]
                launch = meas["mpirun_startup_2_ranks_s"] + LAUNCH_PER_DOUBLING * math.log2(n / 2)
                tn, util = simulate(costs, pixels, n, speeds, launch + startup)
                capacity = sum(speeds)
                cells.append(f"{t1 / (capacity * tn):.1%} ({util:.2%})")
            print(f"| {size} | " + " | ".join(cells) + " |")
        print()


if __name__ == "__main__":
    main()
