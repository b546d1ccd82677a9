"""The PEP 517 build backend of pyproject.toml: `pip install .` → a wheel of the libwave
package built by CMake with the system toolchain (no download, no build dependency).

config settings (pip: --config-settings KEY=VALUE) or environment:
  build-dir / LIBWAVE_BUILD_DIR   the CMake build tree (default build/python); an existing
                                  tree (e.g. build/release) is reused as configured
  installed / LIBWAVE_INSTALLED   "auto" (default): where CMake finds an installed libwave
                                  of this version (its package config, e.g. under
                                  CMAKE_PREFIX_PATH), only the module is built against it
                                  (bindings-cli/python/CMakeLists.txt, tree build/python-module)
                                  when its public headers are this tree's, byte for byte;
                                  "no": always the whole library with the module. A
                                  build-dir given turns the search off (that tree is used)
`pip install -v .` shows the build's progress.
"""
import base64
import hashlib
import os
import pathlib
import shutil
import subprocess
import sys
import sysconfig
import tomllib
import zipfile

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _project():
    with open(ROOT / "pyproject.toml", "rb") as f:
        return tomllib.load(f)["project"]


def _asked_build_dir(config_settings):
    """The build tree the caller named (build-dir / LIBWAVE_BUILD_DIR), or None."""
    return (config_settings or {}).get("build-dir") or os.environ.get("LIBWAVE_BUILD_DIR")


def _build_dir(config_settings):
    d = _asked_build_dir(config_settings) or "build/python"
    p = pathlib.Path(d)
    return p if p.is_absolute() else ROOT / p


def _run(cmd):
    print("libwave build:", " ".join(str(c) for c in cmd), file=sys.stderr, flush=True)
    subprocess.run([str(c) for c in cmd], check=True, cwd=ROOT)


def _installed_package(config_settings):
    """The package built against an installed libwave of this version, or None where
    CMake finds none (or `installed` is "no")."""
    mode = (config_settings or {}).get("installed") or os.environ.get("LIBWAVE_INSTALLED") or "auto"
    if mode not in ("auto", "no"):
        raise RuntimeError(f"libwave build: installed={mode!r}: expected auto or no")
    if mode == "no":
        return None
    build_dir = ROOT / "build" / "python-module"
    shutil.rmtree(build_dir, ignore_errors=True)  # found afresh: never an earlier run's libwave
    cmd = ["cmake", "-S", ROOT / "bindings-cli" / "python", "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release",
           f"-DLIBWAVE_VERSION={_project()['version']}", f"-DPython3_EXECUTABLE={sys.executable}"]
    if shutil.which("ninja"):
        cmd += ["-G", "Ninja"]
    if shutil.which("ccache"):
        cmd += ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"]
    print("libwave build: looking for an installed libwave", _project()["version"], file=sys.stderr, flush=True)
    found = subprocess.run([str(c) for c in cmd], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if found.returncode != 0:
        shutil.rmtree(build_dir, ignore_errors=True)
        why = ("one found, but its public headers are not this tree's" if "not this tree's libwave" in found.stdout
               else "none found")
        print(f"libwave build: {why}; building the library with the module", file=sys.stderr, flush=True)
        return None
    print("libwave build: found one; building the module alone against it", file=sys.stderr, flush=True)
    try:
        _run(["cmake", "--build", build_dir, "--target", "libwave_python_package"])
    except subprocess.CalledProcessError:
        shutil.rmtree(build_dir, ignore_errors=True)
        print("libwave build: the module did not build against it; building the library with the module",
              file=sys.stderr, flush=True)
        return None
    package = build_dir / "python" / "libwave"
    if not (package / "_libwave.pyi").exists():
        raise RuntimeError(f"libwave build: {package} has no built package")
    return package


def _build_package(build_dir):
    if not (build_dir / "CMakeCache.txt").exists():
        cmd = ["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DLIBWAVE_BUILD_TESTS=OFF",
               "-DLIBWAVE_BUILD_BENCH=OFF", f"-DPython3_EXECUTABLE={sys.executable}"]
        if shutil.which("ninja"):
            cmd += ["-G", "Ninja"]
        if shutil.which("ccache"):
            cmd += ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"]
        _run(cmd)
    _run(["cmake", "--build", build_dir, "--target", "libwave_python_package"])
    package = build_dir / "bindings-cli" / "python" / "libwave"
    if not (package / "_libwave.pyi").exists():
        raise RuntimeError(f"libwave build: {package} has no built package")
    return package


def _tag():
    impl = f"cp{sys.version_info.major}{sys.version_info.minor}"
    return f"{impl}-{impl}-{sysconfig.get_platform().replace('-', '_').replace('.', '_')}"


def _metadata(project):
    lines = ["Metadata-Version: 2.1", f"Name: {project['name']}", f"Version: {project['version']}",
             f"Summary: {project['description']}", f"Requires-Python: {project['requires-python']}"]
    lines += [f"Requires-Dist: {d}" for d in project.get("dependencies", [])]
    return "\n".join(lines) + "\n"


def _dist_info(project):
    return f"{project['name']}-{project['version']}.dist-info"


def get_requires_for_build_wheel(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    project = _project()
    d = pathlib.Path(metadata_directory) / _dist_info(project)
    d.mkdir(parents=True, exist_ok=True)
    (d / "METADATA").write_text(_metadata(project))
    return d.name


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    project = _project()
    package = (None if _asked_build_dir(config_settings) else _installed_package(config_settings)) or \
        _build_package(_build_dir(config_settings))
    tag = _tag()
    name = f"{project['name']}-{project['version']}-{tag}.whl"
    info = _dist_info(project)
    files = {f"libwave/{p.name}": p.read_bytes() for p in sorted(package.iterdir()) if p.is_file()}
    files[f"{info}/METADATA"] = _metadata(project).encode()
    files[f"{info}/WHEEL"] = (f"Wheel-Version: 1.0\nGenerator: libwave_build\nRoot-Is-Purelib: false\nTag: {tag}\n").encode()
    record = []
    for path, data in files.items():
        digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
        record.append(f"{path},sha256={digest},{len(data)}")
    record.append(f"{info}/RECORD,,")
    files[f"{info}/RECORD"] = ("\n".join(record) + "\n").encode()
    out = pathlib.Path(wheel_directory) / name
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for path, data in files.items():
            info_entry = zipfile.ZipInfo(path, date_time=(2020, 1, 1, 0, 0, 0))
            info_entry.external_attr = (0o755 if path.endswith(".so") else 0o644) << 16
            info_entry.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info_entry, data)
    return name
