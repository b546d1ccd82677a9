#!/usr/bin/env python3
"""The library's shape, checked from its sources (docs/architecture.md, "Structure checks").

  test_structure.py file_lines   no file of libwave/src over MAX_LINES lines: a file
                                 that grows past it holds more than one job, and is cut
                                 at its seams (one file per job)
  test_structure.py stage_order  each stage (a folder of libwave/src and its header in
                                 libwave/include/libwave) includes only the stages
                                 before it in the README's order, their public headers
                                 or their internals: never a later one
  test_structure.py surface_kind `SurfaceKind::` only in the enum (libwave/scene.h), the
                                 models (libwave/src/scene/models/) and their
                                 registry: the rest of the library, the CLI and the
                                 bindings ask the model (its traits), never the kind
  test_structure.py strip_motion the strips' motions' own scene keys (/breakers: Scene::
                                 breakers, /motion: Scene::profile) read only by their
                                 entries of the motion table (scene/models/*_strips.cpp),
                                 the scene reader, and `wave inspect --scene` (which
                                 checks a file against the lips Jeschke's breakers draw)

Each prints what it found wrong and exits 1, or exits 0.
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
SRC = ROOT / "libwave" / "src"
MAX_LINES = 900
SOURCE_SUFFIXES = {".cpp", ".h", ".inc", ".in"}


def sources():
    return sorted(p for p in SRC.rglob("*") if p.is_file() and p.suffix in SOURCE_SUFFIXES)


def file_lines():
    problems = []
    for path in sources():
        with open(path, encoding="utf-8") as f:
            lines = sum(1 for _ in f)
        if lines > MAX_LINES:
            problems.append(f"{path.relative_to(ROOT)}: {lines} lines, more than {MAX_LINES}: cut it at its seams")
    return problems


# Public headers of no stage folder of their own.
CORE_HEADERS = {"errors", "io", "version", "beta_spline"}
# After the README's chain: inspect reads what export wrote; scene wires every stage.
AFTER_EXPORT = ["inspect", "scene"]


def readme_order():
    """The stages in the order of the README's "Pipeline" section: core and physics
    (used by every stage), then the arrow chain, then AFTER_EXPORT."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text.split("\n## Pipeline", 1)[1].split("\n## ", 1)[0]
    chain = next(line for line in section.splitlines() if "→" in line)
    stages = [s.strip() for s in chain.split("→")]
    for required in AFTER_EXPORT:
        if required not in section:
            raise SystemExit(f"README.md, Pipeline: no word of the stage {required!r}")
    return ["core", "physics"] + stages + AFTER_EXPORT


INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def included_stage(include, own, folders):
    """The stage a quoted #include belongs to: a public header's, a stage folder's
    internals ("surface/triangle_locator.h"), or the including stage's own file."""
    parts = include.split("/")
    if parts[0] == "libwave" and len(parts) == 2:
        name = parts[1].removesuffix(".h")
        return "core" if name in CORE_HEADERS else name
    if parts[0] == ".." or len(parts) == 1:
        return own  # beside the file, or its stage's shared header (models/ → ../surface_model.h)
    return parts[0] if parts[0] in folders else own


def stage_order():
    order = readme_order()
    rank = {stage: i for i, stage in enumerate(order)}
    folders = {p.name for p in SRC.iterdir() if p.is_dir()}
    headers = {p.stem for p in (ROOT / "libwave" / "include" / "libwave").glob("*.h")} - CORE_HEADERS
    problems = [f"libwave/src/{f}/: a stage the README's Pipeline does not order" for f in sorted(folders - set(order))]
    problems += [f"libwave/include/libwave/{h}.h: a stage the README's Pipeline does not order" for h in sorted(headers - set(order))]
    files = [(p, p.relative_to(SRC).parts[0]) for p in sources()]
    files += [(p, "core" if p.stem in CORE_HEADERS else p.stem) for p in sorted((ROOT / "libwave" / "include" / "libwave").glob("*.h"))]
    for path, own in files:
        if own not in rank:
            continue
        for include in INCLUDE.findall(path.read_text(encoding="utf-8")):
            target = included_stage(include, own, folders)
            if target in rank and rank[target] > rank[own]:
                problems.append(f"{path.relative_to(ROOT)}: includes \"{include}\": {own} comes before {target} "
                                f"({' → '.join(order)})")
    return problems


def surface_kind():
    problems = []
    models = SRC / "scene" / "models"
    code = [p for p in sources() if models not in p.parents]
    code += sorted(p for p in (ROOT / "bindings-cli").rglob("*") if p.is_file() and p.suffix in SOURCE_SUFFIXES)
    for path in code:
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                if "SurfaceKind::" in line:
                    problems.append(f"{path.relative_to(ROOT)}:{number}: branches on the surface kind; "
                                    f"ask its model (a trait in scene/surface_model.h) instead")
    return problems


STRIP_MOTION_KEYS = re.compile(r"\b(?:scene|s)\s*(?:\.|->)\s*(?:breakers|profile)\b")
STRIP_MOTION_READERS = {"libwave/src/scene/models/jeschke_strips.cpp", "libwave/src/scene/models/gonzato_strips.cpp",
                        "libwave/src/scene/read_scene.cpp", "bindings-cli/inspect.cpp"}


def strip_motion():
    problems = []
    code = sources() + sorted(p for p in (ROOT / "bindings-cli").rglob("*") if p.is_file() and p.suffix in SOURCE_SUFFIXES)
    for path in code:
        name = path.relative_to(ROOT).as_posix()
        if name in STRIP_MOTION_READERS:
            continue
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                if STRIP_MOTION_KEYS.search(line):
                    problems.append(f"{name}:{number}: branches on the strips' motion; "
                                    f"ask the motion (scene/models/strip_motion.h) instead")
    return problems


CHECKS = {"file_lines": file_lines, "stage_order": stage_order, "surface_kind": surface_kind, "strip_motion": strip_motion}


def main(argv):
    if len(argv) != 2 or argv[1] not in CHECKS:
        print(f"usage: {argv[0]} {'|'.join(CHECKS)}", file=sys.stderr)
        return 2
    problems = CHECKS[argv[1]]()
    for p in problems:
        print(p)
    if problems:
        return 1
    print(f"{argv[1]}: ok")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
