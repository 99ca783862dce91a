"""sinew render: a small run's frames drawn as PNG files of the expected size that are not blank,
and a GIF of the run, through the C command line (`sinew render`) and `python3 -m sinew.render`;
the flat pattern lays overlapping panels side by side."""
import os
import subprocess
import sys

import numpy as np
import pytest

from sinew import frames, render

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SINEW = os.environ.get("SINEW_EXE", os.path.join(ROOT, "build", "sinew"))
Image = pytest.importorskip("PIL.Image")


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("render") / "run"
    subprocess.run([SINEW, "run", os.path.join(ROOT, "scenes", "cloth_drawstring.yaml"),
                    "--grid", "7x7", "--duration", "0.1", "--frames-every", "0.05",
                    "--out", str(out), "--quiet"], check=True)
    return out


def check_png(path, size):
    img = Image.open(path)
    assert img.size == size
    pixels = np.asarray(img.convert("RGB")).reshape(-1, 3)
    assert len(np.unique(pixels, axis=0)) > 50  # a picture, not a blank page


def test_sinew_render_writes_pngs_and_a_gif(run_dir):
    subprocess.run([SINEW, "render", str(run_dir), "--dpi", "50", "--quiet"], check=True)
    for i in range(3):
        check_png(run_dir / "render" / ("tension_%06d.png" % i), (550, 300))
    gif = Image.open(run_dir / "render" / "tension.gif")
    assert gif.n_frames == 3 and gif.size == (550, 300)


def test_module_last_frame_only(run_dir, tmp_path):
    subprocess.run([sys.executable, "-m", "sinew.render", str(run_dir), "--last", "--out",
                    str(tmp_path), "--quiet"], check=True)
    assert sorted(os.listdir(tmp_path)) == ["tension_000002.png"]
    check_png(tmp_path / "tension_000002.png", (1100, 600))


def test_help_and_errors(tmp_path):
    done = subprocess.run([SINEW, "render", "--help"], capture_output=True, text=True)
    assert done.returncode == 0 and "usage: sinew render" in done.stdout
    done = subprocess.run([SINEW, "render", str(tmp_path)], capture_output=True, text=True)
    assert done.returncode == 2 and "has no frames.pvd" in done.stderr


def test_overlapping_panels_are_laid_side_by_side():
    """Two unit-square panels on the same (u,v) square: the second is moved right of the
    first, with a gap of 5 % of the widest."""
    piece = frames.Piece()
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 0], [1, 1], [0, 1]], dtype=float)
    piece.points = np.zeros((8, 3))
    piece.connectivity = np.arange(12)
    piece.offsets = np.arange(3, 13, 3)
    piece.cell_data = {"panel": np.array([0, 0, 1, 1], dtype=np.int32),
                       "uv_corners": np.concatenate([square, square]).reshape(4, 6)}
    uv, panel, shift = render.pattern_layout(piece)
    assert np.allclose(uv[:2].reshape(-1, 2), square)
    assert np.allclose(uv[2:].reshape(-1, 2), square + [1.05, 0])
    assert np.allclose(shift[1], [1.05, 0])
