#!/usr/bin/env python3
"""Which command-line test methods the ASan/UBSan suite needs, by line coverage.

    scripts/asan-selection.py [--build build/coverage] [--jobs 2]

The CLI and hostile-input suites (tests/test_cli.py, tests/test_hostile.py) run `wave`
end to end; under the sanitizers a run costs ~4 × the release build's. A sanitizer finds
a memory or UB error on the code a test reaches, so the sanitizer suite needs each line
of our code that the whole suite reaches once, not every test that reaches it.

This script builds the `coverage` preset (clang's source-based coverage, -O1), runs the
GoogleTest suite and then every test method on its own, each with its own profile, and
takes the lines of libwave/ and bindings-cli/ each one reaches. The unit tests always
run under the sanitizers; then, greedily, the method that adds the most lines not yet
reached per second of its run is kept, until the kept methods reach every line the
suite reaches. The others are written to tests/data/asan-selection.json with the lines
they reach and their cost; under ASan (ASAN_OPTIONS set) the suites skip them.

Run it again when a test or a code path is added (docs/hardening.md, "The sanitizer
suite"). The runs set ASAN_OPTIONS, as ctest's asan preset does, so that methods
which already skip or shrink themselves under ASan are measured as they run there.
"""
import argparse
import concurrent.futures
import datetime
import hashlib
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
SUITES = {"cli": "test_cli.py", "hostile": "test_hostile.py"}
OURS = re.compile(r"^" + re.escape(str(ROOT)) + r"/(libwave|bindings-cli)/")
LLVM = pathlib.Path("/usr/lib/llvm-14/bin")


def methods():
    """cli.Class.test_method for every test method of the two suites, in file order."""
    out = []
    for prefix, name in SUITES.items():
        cls = None
        for line in (ROOT / "tests" / name).read_text().splitlines():
            m = re.match(r"^class ([A-Za-z0-9_]+)\(unittest\.TestCase\)", line)
            if m:
                cls = m.group(1)
                continue
            m = re.match(r"^    def (test_[A-Za-z0-9_]+)\(self", line)
            if m and cls:
                out.append(f"{prefix}.{cls}.{m.group(1)}")
    return out


def lines_reached(profraws, binary, workdir):
    """{(file, line)} of our sources with a count > 0 in the merged profiles."""
    if not profraws:
        return set()
    data = workdir / "merged.profdata"
    subprocess.run([LLVM / "llvm-profdata", "merge", "-sparse", "-o", data, *profraws], check=True)
    lcov = subprocess.run([LLVM / "llvm-cov", "export", binary, "-instr-profile", data, "-format=lcov",
                           "-skip-functions"], check=True, capture_output=True, text=True).stdout
    reached, source = set(), None
    for row in lcov.splitlines():
        if row.startswith("SF:"):
            source = row[3:] if OURS.match(row[3:]) else None
        elif source and row.startswith("DA:"):
            line, count = row[3:].split(",")[:2]
            if int(count) > 0:
                reached.add((source[len(str(ROOT)) + 1:], int(line)))
    return reached


def run_method(test, build, profiles):
    prefix, cls, method = test.split(".")
    folder = profiles / test
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    env = dict(os.environ, WAVE_EXE=str(build / "bindings-cli" / "wave"), LIBWAVE_DATA_DIR=str(ROOT / "data"),
               GLTF_VALIDATOR=str(ROOT / "scripts" / "gltf-validator" / "validate.mjs"),
               LLVM_PROFILE_FILE=str(folder / "%p.profraw"),
               ASAN_OPTIONS="detect_leaks=1:abort_on_error=1",  # the suites' UNDER_ASAN
               LIBWAVE_ASAN_SELECTION="off")  # but every method runs
    start = time.monotonic()
    r = subprocess.run([sys.executable, str(ROOT / "tests" / SUITES[prefix]), f"{cls}.{method}"],
                       env=env, capture_output=True, text=True)
    seconds = time.monotonic() - start
    reached = lines_reached(sorted(folder.glob("*.profraw")), build / "bindings-cli" / "wave", folder)
    shutil.rmtree(folder, ignore_errors=True)
    return test, r.returncode, seconds, reached, r.stderr[-2000:]


def choose(units, results):
    """(every line reached, [(kept method, the lines it added when chosen)], {skipped
    method: (seconds, lines)}): a greedy cover, by new lines per second, of every line the
    suites reach beyond the unit tests; then the kept methods the others cover go, the
    costliest first."""
    covered = set(units)
    everything = set().union(units, *(r for _, r in results.values()))
    kept = []
    left = dict(results)
    while covered != everything:
        test = max(left, key=lambda t: (len(left[t][1] - covered) / max(left[t][0], 0.1), t))
        added = left[test][1] - covered
        covered |= left.pop(test)[1]
        kept.append((test, added))
    for test, _ in sorted(kept, key=lambda e: -results[e[0]][0]):
        others = set(units).union(*(results[t][1] for t, _ in kept if t != test))
        if results[test][1] <= others:
            kept = [e for e in kept if e[0] != test]
            left[test] = results[test]
    return everything, kept, left


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build" / "coverage"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--skip-build", action="store_true", help="use the coverage tree as it is")
    ap.add_argument("--reuse", action="store_true",
                    help="take the last measurement's lines (of the same code), and measure only the methods it lacks")
    args = ap.parse_args()
    build = pathlib.Path(args.build)
    if not args.skip_build:
        subprocess.run(["cmake", "--preset", "coverage"], cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
        subprocess.run(["cmake", "--build", "--preset", "coverage", "--target", "wave", "libwave_tests"], cwd=ROOT, check=True)
    profiles = build / "asan-selection"
    # What was measured holds for this code and these tests only: a hash of the files of
    # libwave/, bindings-cli/ and tests/ (not tests/data, which this script writes) keys
    # the profiles kept for --reuse.
    files = subprocess.run(["git", "ls-files", "libwave", "bindings-cli", "tests", ":!tests/data"], cwd=ROOT,
                           check=True, capture_output=True, text=True).stdout.split()
    key = hashlib.sha256(b"".join(f.encode() + (ROOT / f).read_bytes() for f in files if (ROOT / f).is_file())).hexdigest()
    key_file = profiles / "code.key"
    same_code = key_file.exists() and key_file.read_text() == key
    if not same_code:
        shutil.rmtree(profiles, ignore_errors=True)
    profiles.mkdir(parents=True, exist_ok=True)
    key_file.write_text(key)
    start = time.monotonic()
    if not (same_code and list((profiles / "units").glob("*.profraw"))):  # the units' profile of this code
        shutil.rmtree(profiles / "units", ignore_errors=True)
        (profiles / "units").mkdir(parents=True)
        subprocess.run([build / "tests" / "libwave_tests", "--gtest_brief=1"], check=True, stdout=subprocess.DEVNULL,
                       env=dict(os.environ, LLVM_PROFILE_FILE=str(profiles / "units" / "%p.profraw")))
    units = lines_reached(sorted((profiles / "units").glob("*.profraw")), build / "tests" / "libwave_tests", profiles / "units")
    print(f"unit tests: {len(units)} lines in {time.monotonic() - start:.0f} s", flush=True)

    results = {}
    cache = profiles / "methods.json"  # {test: [seconds, [[file, line], ...]]}: --reuse reads it
    if args.reuse and cache.exists():
        results = {t: (v[0], {tuple(x) for x in v[1]}) for t, v in json.loads(cache.read_text()).items()}
    tests = methods()
    results = {t: results[t] for t in tests if t in results}  # methods since removed drop out
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for test, rc, seconds, reached, err in pool.map(lambda t: run_method(t, build, profiles),
                                                        [t for t in tests if t not in results]):
            if rc != 0:
                sys.exit(f"{test} failed (exit {rc}) in the coverage build:\n{err}")
            results[test] = (seconds, reached)
            print(f"{seconds:7.1f} s {len(reached):6d} lines  {test}", flush=True)
    cache.write_text(json.dumps({t: [s, sorted(r)] for t, (s, r) in results.items()}))

    everything, kept, left = choose(units, results)
    skipped = {test: {"seconds": round(seconds, 1), "lines": len(reached)}
               for test, (seconds, reached) in sorted(left.items())}
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True).stdout.strip()
    out = {
        "about": "Test methods the ASan/UBSan suite skips: every line of libwave/ and bindings-cli/ they reach "
                 "is reached under the sanitizers by the unit tests and the kept methods "
                 "(scripts/asan-selection.py; seconds are the coverage build's).",
        "measured": f"{datetime.date.today().isoformat()} at {commit}",
        "lines": {"suite": len(everything), "unit tests": len(units)},
        "kept_seconds": round(sum(results[t][0] for t, _ in kept), 1),
        # each kept method, in the order chosen, with the lines only it added then (a few shown)
        "kept": {t: {"seconds": round(results[t][0], 1), "lines": len(results[t][1]), "new_lines": len(added),
                     "for": sorted(f"{f}:{n}" for f, n in added)[:3]} for t, added in kept},
        "skipped_seconds": round(sum(v["seconds"] for v in skipped.values()), 1),
        "skipped": skipped,
    }
    path = ROOT / "tests" / "data" / "asan-selection.json"
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"{len(everything)} lines ({len(units)} by the unit tests); kept {len(kept)} methods "
          f"({out['kept_seconds']} s), skipped {len(skipped)} ({out['skipped_seconds']} s): {path}")


if __name__ == "__main__":
    main()
