"""pip install of the Python package `deploysim` (python/, docs/python.md).

    /usr/bin/python3 -m venv --system-site-packages v
    v/bin/pip install --no-build-isolation .

setuptools is the build backend (Debian's python3-setuptools and python3-wheel; no
download). The compiled module is built by the project's CMake, not by setuptools: the
build step configures <source>/build/pip with the generator and cache variables of the
`release` preset (CMakePresets.json), so every object is compiled with the flags of
`cmake --preset release` and, where ccache is installed, comes from its cache when that
build compiled the same source. Only the targets the package needs are built: the module
(deploysim_python) and the `deploysim` command, which the package runs for its viewer and
mission report (deploysim.view, deploysim.report) together with the Python tools of
tools/. Both are installed inside the package, in deploysim/_cli/ with the layout the
command looks for its tools in (bin/deploysim, share/deploysim/tools/).

Environment: CMAKE_BUILD_PARALLEL_LEVEL (parallel compile jobs, CMake's own variable),
DEPLOYSIM_CMAKE_ARGS (more -D options for the configure step, split on spaces).
"""

import glob
import json
import os
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))
# Two levels below the source, as build/release: with CCACHE_BASEDIR (CMakeLists.txt) the
# compile commands then name the sources by the same relative paths, and ccache finds the
# objects of the release build.
CMAKE_BUILD = os.path.join(ROOT, "build", "pip")
# setuptools' own build and egg-info folders, kept out of the source tree's root.
SETUPTOOLS_BUILD = os.path.join("build", "python-wheel")


def project_version():
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(deploysim\s+VERSION\s+([0-9.]+)", f.read())
    if not m:
        raise RuntimeError("CMakeLists.txt: no project(deploysim VERSION ...)")
    return m.group(1)


def release_preset_arguments():
    """The configure options of CMakePresets.json's `release` preset (generator and cache
    variables), so that the package's objects are the release build's."""
    with open(os.path.join(ROOT, "CMakePresets.json"), encoding="utf-8") as f:
        presets = {p["name"]: p for p in json.load(f)["configurePresets"]}
    release = presets["release"]
    args = ["-G", release["generator"]] if "generator" in release else []
    for k, v in release.get("cacheVariables", {}).items():
        value = v["value"] if isinstance(v, dict) else v
        args.append(f"-D{k}={value}")
    return args


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class BuildWithCMake(build_ext):
    """Builds deploysim._deploysim and the deploysim command with the project's CMake."""

    def build_extension(self, ext):
        if shutil.which("cmake") is None:
            raise RuntimeError("deploysim: cmake is needed to build the package "
                               "(tools/install_deps.sh installs the build dependencies)")
        configure = ["cmake", "-S", ROOT, "-B", CMAKE_BUILD, *release_preset_arguments(),
                     # The package only: no test suite, no benchmarks.
                     "-DDEPLOYSIM_BUILD_TESTS=OFF", "-DDEPLOYSIM_BUILD_BENCH=OFF",
                     # The module is built for the interpreter that runs pip.
                     f"-DPython_EXECUTABLE={sys.executable}"]
        configure += os.environ.get("DEPLOYSIM_CMAKE_ARGS", "").split()
        self.announce("deploysim: " + " ".join(configure), level=2)
        subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", CMAKE_BUILD, "--target", "deploysim_python",
                        "deploysim"], check=True)

        module = glob.glob(os.path.join(CMAKE_BUILD, "python", "deploysim", "_deploysim*.so"))
        if len(module) != 1:
            raise RuntimeError(f"deploysim: expected one built module, found {module} (was "
                               "the Python package configured? pybind11-dev and python3-dev "
                               "are needed)")
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(module[0], target)

        # The command and its tools, in the layout it searches (cli/python_tool.h):
        # <dir of the executable>/../share/deploysim/tools.
        cli = os.path.join(os.path.dirname(target), "_cli")
        shutil.rmtree(cli, ignore_errors=True)
        os.makedirs(os.path.join(cli, "bin"))
        shutil.copy2(os.path.join(CMAKE_BUILD, "bin", "deploysim"),
                     os.path.join(cli, "bin", "deploysim"))
        tools = os.path.join(cli, "share", "deploysim", "tools")
        os.makedirs(tools)
        for f in glob.glob(os.path.join(ROOT, "tools", "*.py")) + [
                os.path.join(ROOT, "tools", "view_template.html")]:
            shutil.copy2(f, tools)


os.makedirs(SETUPTOOLS_BUILD, exist_ok=True)
setup(
    name="deploysim",
    version=project_version(),
    description="Spinning spacecraft that deploy their panels (Dzhanibekov effect): "
                "the deploysim simulator from Python",
    long_description=open(os.path.join(ROOT, "docs", "python.md"), encoding="utf-8").read(),
    long_description_content_type="text/markdown",
    python_requires=">=3.8",
    install_requires=["numpy"],
    packages=["deploysim"],
    package_dir={"deploysim": "python/deploysim"},
    ext_modules=[CMakeExtension("deploysim._deploysim")],
    cmdclass={"build_ext": BuildWithCMake},
    options={"build": {"build_base": SETUPTOOLS_BUILD},
             "egg_info": {"egg_base": SETUPTOOLS_BUILD}},
    zip_safe=False,
)
