#!/usr/bin/env python3
"""The `wave` command line as a user meets it: exit codes (0 ok, 2 bad input or usage,
1 runtime failure), `error: …` on stderr naming the file/value, and no partial output."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

WAVE = os.environ["WAVE_EXE"]
DATA = os.environ["LIBWAVE_DATA_DIR"]


def wave(*args, cwd=None):
    return subprocess.run([WAVE, *args], capture_output=True, text=True, cwd=cwd, timeout=120)


class Basics(unittest.TestCase):
    def test_version_and_help(self):
        r = wave("--version")
        self.assertEqual(r.returncode, 0)
        self.assertRegex(r.stdout, r"^wave \d+\.\d+\.\d+")
        r = wave("--help")
        self.assertEqual(r.returncode, 0)
        for sub in ("run", "dispersion", "seafloor"):
            self.assertIn(sub, r.stdout)
        r = wave("dispersion", "--help")
        self.assertEqual(r.returncode, 0)
        self.assertIn("--period", r.stdout)

    def test_dispersion_json(self):
        r = wave("dispersion", "--period", "10", "--depth", "5", "--json", "--deep-height", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        d = json.loads(r.stdout)
        # L/L0 at d/L0 = 5/156.13 = 0.032: SPM Table C-1 gives 0.4335 (interpolated).
        self.assertAlmostEqual(d["wavelength_m"] / d["deep_wavelength_m"], 0.4335, delta=2e-3)
        self.assertAlmostEqual(d["celerity_m_per_s"], d["wavelength_m"] / 10.0, places=12)
        self.assertFalse(d["breaking"])

    def test_dispersion_dry(self):
        r = wave("dispersion", "--period", "10", "--depth", "-1", "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(json.loads(r.stdout)["dry"])

    def test_seafloor_info_on_real_data(self):
        r = wave("seafloor", "info", os.path.join(DATA, "bathymetry/haringvliet_swan_f31hari_250m.bot"),
                 "--swan-grid", "88,117", "--swan-spacing", "250", "--nodata", "-99", "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        d = json.loads(r.stdout)
        self.assertEqual(d["nodes"], [88, 117])
        self.assertGreater(d["nodata_count"], 0)
        r = wave("seafloor", "info", "berkhoff-shoal", "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertAlmostEqual(json.loads(r.stdout)["depth_range_m"][1], 0.45, places=9)


class BadInput(unittest.TestCase):
    def expect_error(self, args, code, *parts):
        r = wave(*args)
        self.assertEqual(r.returncode, code, f"{args}: stdout={r.stdout} stderr={r.stderr}")
        self.assertTrue(r.stderr.startswith("error: "), r.stderr)
        for p in parts:
            self.assertIn(p, r.stderr)

    def test_usage_errors_exit_2(self):
        self.expect_error(["frobnicate"], 2)
        self.expect_error([], 2)
        self.expect_error(["dispersion", "--period", "abc", "--depth", "3"], 2, "abc")
        self.expect_error(["dispersion", "--period", "-4", "--depth", "3"], 2, "-4")
        self.expect_error(["dispersion", "--depth", "3"], 2, "--period")

    def test_bad_files_exit_2(self):
        with tempfile.TemporaryDirectory() as d:
            missing = os.path.join(d, "missing.asc")
            self.expect_error(["seafloor", "info", missing], 2, missing, "not found")
            bot = os.path.join(d, "x.bot")
            with open(bot, "w") as f:
                f.write("1 2 3\n")
            self.expect_error(["seafloor", "info", bot], 2, bot, "--swan-grid")
            self.expect_error(["seafloor", "info", bot, "--swan-grid", "2,2", "--swan-spacing", "1"], 2,
                              "truncated")
            cj = os.path.join(d, "c.json")
            with open(cj, "w") as f:
                f.write('{"contours": [{"depth": "two", "points": [[0,0],[1,1]]}]}')
            self.expect_error(["seafloor", "info", cj], 2, cj, "/contours/0/depth")
            self.expect_error(["seafloor", "info", "atlantis"], 2, "atlantis")


class Contours(unittest.TestCase):
    def test_json_round_trip_and_obj(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "bay.json")
            r = wave("contours", "gonzato-bay", "--levels", "1,2.5", "-o", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(out) as f:
                doc = json.load(f)
            self.assertEqual(sorted(c["depth"] for c in doc["contours"]), [0.0, 1.0, 2.5])
            # The written file is a valid seafloor input again.
            r = wave("seafloor", "info", out, "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(json.loads(r.stdout)["contour_lines"], 3)
            obj = os.path.join(d, "bay.obj")
            self.assertEqual(wave("contours", "gonzato-bay", "--level-spacing", "1", "-o", obj).returncode, 0)
            text = open(obj).read()
            self.assertEqual(text.count("\nl "), 5)
            self.assertNotIn(" -0\n", text)

    def test_bad_levels_exit_2_without_output(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "x.json")
            r = wave("contours", "gonzato-bay", "--levels", "9", "-o", out)
            self.assertEqual(r.returncode, 2)
            self.assertIn("level 9", r.stderr)
            self.assertIn("-2 .. 5", r.stderr)
            r = wave("contours", "gonzato-bay", "--levels", "1", "-o", os.path.join(d, "x.txt"))
            self.assertEqual(r.returncode, 2)
            self.assertIn(".json", r.stderr)
            self.assertEqual(os.listdir(d), [])


class MainJob(unittest.TestCase):
    def test_run_writes_report(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            r = wave("run", "-o", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("break", r.stdout)
            with open(os.path.join(out, "surf-zone.json")) as f:
                report = json.load(f)
            lines = report["cross_shore_lines"]
            self.assertEqual(len(lines), 21)
            for line in lines:  # every line of the bay reaches the beach and breaks
                self.assertGreaterEqual(line["break_height_m"], 0.78 * line["break_depth_m"] - 1e-12)
            self.assertEqual(sorted(os.listdir(out)), ["surf-zone.json"])  # no temporary left

    def test_unwritable_output_is_a_runtime_failure_without_partial_files(self):
        with tempfile.TemporaryDirectory() as d:
            blocker = os.path.join(d, "file")
            with open(blocker, "w") as f:
                f.write("x")
            r = wave("run", "-o", os.path.join(blocker, "sub"))
            self.assertEqual(r.returncode, 1, r.stderr)
            self.assertTrue(r.stderr.startswith("error: "))
            self.assertEqual(os.listdir(d), ["file"])

    def test_existing_output_is_replaced_atomically(self):
        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(wave("run", "-o", d).returncode, 0)
            first = open(os.path.join(d, "surf-zone.json")).read()
            self.assertEqual(wave("run", "-o", d).returncode, 0)
            self.assertEqual(open(os.path.join(d, "surf-zone.json")).read(), first)  # deterministic
            self.assertEqual(os.listdir(d), ["surf-zone.json"])


if __name__ == "__main__":
    unittest.main(verbosity=2)
