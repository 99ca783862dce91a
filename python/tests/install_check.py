"""`pip install .` as a user runs it: build the wheel with meson-python (pyproject.toml), install it
into a fresh venv (--system-site-packages, for Debian's numpy) and with --target into a folder,
and check that `import sinew` steps a scene and the installed `sinew` program runs, with no
PYTHONPATH, SINEW_LIB or LD_LIBRARY_PATH (only --target needs PYTHONPATH for the package).

usage: install_check.py SOURCE_DIR BUILD_DIR [PYTHON]

The wheel is built in BUILD_DIR/pip-build, kept between runs so that a second run only relinks."""
import glob
import os
import re
import subprocess
import sys
import tempfile

SOURCE, BUILD = sys.argv[1], sys.argv[2]
PYTHON = sys.argv[3] if len(sys.argv) > 3 else "/usr/bin/python3"
SCENE = os.path.join(SOURCE, "scenes", "cloth_drawstring.yaml")
STEP = """
import sinew, numpy as np
sim = sinew.load({scene!r}, method="backward-euler", dt=0.01)
sim.run(0.03)
assert sim.time == 0.03 and np.isfinite(sim.positions).all(), sim
assert sinew.__file__.startswith({where!r}), sinew.__file__
print("ok", sim.time, sim.tendons["drawstring"].tension)
"""


def clean_env(**extra):
    """The environment without the build tree's PYTHONPATH, SINEW_LIB, LD_* and sanitizers."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "SINEW_LIB", "SINEW_EXE", "LD_LIBRARY_PATH", "LD_PRELOAD")}
    env.update(extra)
    return env


def run(*args, **kw):
    print("+", " ".join(args), flush=True)
    return subprocess.run(args, check=True, env=kw.pop("env", clean_env()), **kw)


def version():
    text = open(os.path.join(SOURCE, "meson.build")).read()
    return re.search(r"version\s*:\s*'([^']+)'", text).group(1)


def check_program(exe):
    out = run(exe, "--version", capture_output=True, text=True).stdout.strip()
    assert out == "sinew " + version(), out
    # the subcommands written in Python find the installed package beside the program (a
    # wheel's program knows no source tree), and bench's chart script is in it
    for sub in ("render", "drape", "pattern"):
        out = run(exe, sub, "--help", capture_output=True, text=True).stdout
        assert out.startswith("usage: "), (sub, out)
    found = glob.glob(os.path.join(os.path.dirname(exe), "..", "**", "sinew", "bench_charts.py"),
                      recursive=True)
    assert found, "bench_charts.py not installed beside " + exe


def main():
    builddir = os.path.join(BUILD, "pip-build")
    # meson-python 0.12 reconfigures a build folder it was given whenever its native file (in
    # the source folder) exists: without a configured folder, that file must go
    native = os.path.join(SOURCE, ".mesonpy-native-file.ini")
    if not os.path.exists(os.path.join(builddir, "meson-private", "coredata.dat")):
        if os.path.exists(native):
            os.remove(native)
    with tempfile.TemporaryDirectory(prefix="sinew-install-") as tmp:
        wheels = os.path.join(tmp, "wheels")
        # unoptimised: half the compile time, and the layout is what is checked here
        run(PYTHON, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "-q",
            "--config-settings=builddir=" + builddir,
            "--config-settings=setup-args=-Doptimization=0", "-w", wheels, SOURCE, cwd=tmp)
        wheel, = glob.glob(os.path.join(wheels, "sinew-*.whl"))

        venv = os.path.join(tmp, "venv")
        run(PYTHON, "-m", "venv", "--system-site-packages", venv)
        vpy = os.path.join(venv, "bin", "python")
        run(vpy, "-m", "pip", "install", "--no-deps", "-q", wheel, cwd=tmp)
        run(vpy, "-c", STEP.format(scene=SCENE, where=venv), cwd=tmp)
        check_program(os.path.join(venv, "bin", "sinew"))

        target = os.path.join(tmp, "target")
        run(PYTHON, "-m", "pip", "install", "--no-deps", "-q", "--target", target, wheel, cwd=tmp)
        run(PYTHON, "-c", STEP.format(scene=SCENE, where=target), cwd=tmp,
            env=clean_env(PYTHONPATH=target))
        check_program(os.path.join(target, "bin", "sinew"))
    print("install_check: ok")


if __name__ == "__main__":
    main()
