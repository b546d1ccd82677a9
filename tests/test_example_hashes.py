#!/usr/bin/env python3
"""Every example's output, byte for byte, against SHA-256 hashes recorded before a change.

Restructuring the wiring (issue 21) must not change a single output byte: this runs the
built-in default scene and each examples/*.json for the first two frames of its loop
(the default form and container of the scene) and compares every file it writes, except
report.json (it holds timings), with tests/data/example-hashes.json.

    WAVE_EXE=build/release/bindings-cli/wave python3 tests/test_example_hashes.py
    ... --record   # rewrite the table (after a change that is meant to alter outputs)

Registered for the release build only: the sanitised build is another compiler setting,
and the hashes record the release binary's floating-point results.
"""
import hashlib
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parent.parent
WAVE = os.environ.get("WAVE_EXE", str(ROOT / "build/release/bindings-cli/wave"))
TABLE = ROOT / "tests/data/example-hashes.json"
FRAMES = "0:2"


def scenes():
    yield "default", []
    # The other forms and encodings of the default scene (the files form's index and
    # frames carry the run key, which names libwave's version: re-record on a bump).
    yield "default-morph-float", ["--no-quantize"]
    yield "default-nodes-quantized", ["--form", "nodes", "--quantize"]
    yield "default-files-gltf", ["--form", "files", "--container", "gltf"]
    yield "default-morph-draco", ["--draco"]
    yield "default-files-meshopt", ["--form", "files", "--codec", "meshopt"]
    yield "default-morph-meshopt", ["--codec", "meshopt"]
    for path in sorted((ROOT / "examples").glob("*.json")):
        yield path.stem, [str(path)]


def run_hashes(name, args):
    with tempfile.TemporaryDirectory() as out:
        r = subprocess.run([WAVE, "run", *args, "-o", out, "--frames", FRAMES, "-q"],
                           capture_output=True, text=True, timeout=900)
        if r.returncode != 0:
            raise AssertionError(f"{name}: wave run exited {r.returncode}: {r.stderr}")
        files = {}
        for p in sorted(pathlib.Path(out).rglob("*")):
            if p.is_file() and p.name != "report.json":
                # Reports name a seafloor file by its path: hashed with the checkout's root
                # replaced, so a clone anywhere gives the same table.
                data = p.read_bytes().replace(str(ROOT).encode(), b"<root>")
                files[str(p.relative_to(out))] = hashlib.sha256(data).hexdigest()
        return files


class ExampleHashes(unittest.TestCase):
    def test_every_example_byte_identical(self):
        table = json.loads(TABLE.read_text())
        self.assertEqual(sorted(table), sorted(name for name, _ in scenes()), "an example without recorded hashes")
        for name, args in scenes():
            with self.subTest(example=name):
                self.assertEqual(run_hashes(name, args), table[name])


if __name__ == "__main__":
    if "--record" in sys.argv:
        TABLE.write_text(json.dumps({name: run_hashes(name, args) for name, args in scenes()}, indent=1) + "\n")
        print(f"recorded {TABLE}")
    else:
        unittest.main()
