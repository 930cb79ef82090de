#!/usr/bin/python3
"""scripts/ptlib: every image format round-trips exactly (EXR: the 32-bit
floats written), paired runs alternate their order and pair their ratios by
round, a generated block is replaced and a missing one refused, bench_trace's
rates are read alike from Google Benchmark JSON and from converted cells, and
the summary that bench.sh trace leads with names Embree's best method.
"""
import json
import os
import sys
import tempfile
import unittest

import numpy as np

SCRIPTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts")
sys.path.insert(0, SCRIPTS)
import bench_tables  # noqa: E402
from ptlib import blocks, images, paired, results  # noqa: E402


class Images(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.rng = np.random.default_rng(7)

    def tearDown(self):
        self.dir.cleanup()

    def path(self, name):
        return os.path.join(self.dir.name, name)

    def test_pfm_rgb_and_grey_round_trip_bit_for_bit_top_row_first(self):
        rgb = self.rng.random((5, 7, 3), dtype=np.float32) * 10
        images.write_pfm(self.path("a.pfm"), rgb)
        np.testing.assert_array_equal(images.read_pfm(self.path("a.pfm")), rgb)
        with open(self.path("a.pfm"), "rb") as f:  # on disk the bottom row comes first
            f.readline(), f.readline(), f.readline()
            np.testing.assert_array_equal(np.frombuffer(f.read(7 * 12), dtype="<f4").reshape(7, 3), rgb[-1])
        grey = self.rng.random((4, 3), dtype=np.float32)
        images.write_image(self.path("g.pfm"), grey)
        np.testing.assert_array_equal(images.read_image(self.path("g.pfm"))[:, :, 0], grey)

    def test_a_truncated_pfm_is_refused(self):
        images.write_pfm(self.path("t.pfm"), np.zeros((4, 4, 3), np.float32))
        with open(self.path("t.pfm"), "r+b") as f:
            f.truncate(30)
        with self.assertRaisesRegex(ValueError, "t.pfm"):
            images.read_pfm(self.path("t.pfm"))

    def test_png_round_trips_and_floats_are_rounded(self):
        rgb = self.rng.integers(0, 256, (6, 5, 3), dtype=np.uint8)
        images.write_image(self.path("a.png"), rgb)
        np.testing.assert_array_equal(images.read_image(self.path("a.png")), rgb)
        images.write_png(self.path("f.png"), np.array([[[0.0, 0.5, 2.0]]]))
        np.testing.assert_array_equal(images.read_png(self.path("f.png")), [[[0, 128, 255]]])

    def test_exr_round_trips_32_bit_floats(self):
        rgb = (self.rng.random((6, 4, 3), dtype=np.float32) * 100).astype(np.float32)
        images.write_image(self.path("a.exr"), rgb)
        np.testing.assert_array_equal(images.read_image(self.path("a.exr"))[:, :, :3], rgb)

    def test_an_unknown_extension_is_refused(self):
        with self.assertRaisesRegex(ValueError, "x.tga"):
            images.read_image(self.path("x.tga"))


class Paired(unittest.TestCase):
    def test_rounds_alternate_the_order_and_ratios_pair_by_round(self):
        self.assertEqual(paired.round_order("ABC", 0), ["A", "B", "C"])
        self.assertEqual(paired.round_order("ABC", 1), ["C", "B", "A"])
        calls = []
        runs = paired.run_rounds(3, ["a", "b"], lambda v, r: calls.append((r, v)) or (10 + r if v == "a" else 20 + r))
        self.assertEqual(calls, [(0, "a"), (0, "b"), (1, "b"), (1, "a"), (2, "a"), (2, "b")])
        s = paired.ratio_summary(runs["b"], runs["a"])
        self.assertEqual((s.low, s.median, s.high), (22 / 12, 21 / 11, 2.0))


class Blocks(unittest.TestCase):
    def test_a_block_is_replaced_and_a_missing_one_refused(self):
        with tempfile.TemporaryDirectory() as d:
            page = os.path.join(d, "p.md")
            with open(page, "w") as f:
                f.write("head\n<!-- t:begin results/x.json -->\nold\n<!-- t:end -->\ntail\n")
            self.assertEqual(blocks.argument(page, "t"), "results/x.json")
            self.assertTrue(blocks.replace(page, "t", "new"))
            with open(page) as f:
                self.assertEqual(f.read(), "head\n<!-- t:begin results/x.json -->\nnew\n<!-- t:end -->\ntail\n")
            self.assertFalse(blocks.replace(page, "t", "new"))
            with self.assertRaises(blocks.MissingBlock):
                blocks.replace(page, "u", "x")


def bench_entry(name, rate, aggregate="median"):
    return {"name": name + "_" + aggregate, "run_name": name, "aggregate_name": aggregate, "rays_per_s": rate * 1e6}


class Results(unittest.TestCase):
    GOOGLE = {"context": {}, "benchmarks": [
        bench_entry("trace/teapot/shadow/bvh4_queue/threads:1", 30.0),
        bench_entry("trace/teapot/shadow/bvh4_queue/threads:1", 99.0, "mean"),
        bench_entry("trace/teapot/shadow/embree_default_stream/threads:1", 20.0),
        bench_entry("trace/teapot/shadow/embree_high_arrays/threads:1", 25.0),
        bench_entry("trace/teapot/shadow/bvh4_watertight/threads:1", 90.0),
        {"name": "trace/teapot/diffuse/bvh4_queue/threads:1", "error_occurred": True, "error_message": "no"}]}

    def test_rates_read_alike_from_google_benchmark_json_a_wrapped_run_and_cells(self):
        cells = {"cells": [{"scene": "teapot", "rays": "shadow", "threads": 1, "method": m, "mrays_per_s": v}
                           for m, v in (("bvh4_queue", 30.0), ("embree_default_stream", 20.0),
                                        ("embree_high_arrays", 25.0), ("bvh4_watertight", 90.0))]}
        for data in (self.GOOGLE, {"benchmark": self.GOOGLE}, cells):
            trace, _, _ = results.trace_rates(data)
            (ours, mine), (theirs, name) = results.ours_and_embree(trace[("teapot", "shadow", 1)])
            self.assertEqual((ours, mine, theirs, name), (30.0, "bvh4_queue", 25.0, "embree_high_arrays"))
        self.assertEqual(results.trace_rates(self.GOOGLE)[2], ["trace/teapot/diffuse/bvh4_queue/threads:1: no"])

    def test_the_summary_names_embrees_best_method_and_the_ratio(self):
        trace, builds, _ = results.trace_rates(self.GOOGLE)
        row = [line for line in bench_tables.summary_text(trace, ["teapot"]) if line.startswith("teapot")]
        self.assertEqual(len(row), 1)
        self.assertEqual(row[0].split()[2:], ["|", "30.0", "25.0", "high_arrays", "1.20x"])

    def test_a_new_record_carries_the_host_date_commit_and_command(self):
        rec = results.new("bench_trace", "t", "cmd", "avx2", benchmark=self.GOOGLE)
        for key in ("host", "date", "commit", "command", "isa"):
            self.assertIn(key, rec)
        self.assertIn("cpu", rec["host"])
        rec["tile_sets"] = {16: "a", 32: "b"}
        rec["cells"] = [{"scene": "s", "mrays_per_s": 1.5}]
        self.assertEqual(json.loads(results.dumps(rec)), json.loads(json.dumps(rec)))  # int keys as strings


if __name__ == "__main__":
    unittest.main()
