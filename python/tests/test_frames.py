"""The frames of a run folder read back: the binary VTU (appended, zlib) and the tendons' VTP hold
the simulation's state bit for bit (positions, tension XY, velocities, tendon tension, time),
ascii frames hold the same numbers, binary32 their Float32 roundings; ParaView's reader (VTK's
Python modules, Debian's python3-vtk9) loads them with the arrays named in docs/scenes.md."""
import os

import numpy as np
import pytest

import sinew
from sinew import frames

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(ROOT, "scenes", "cloth_drawstring.yaml")
CLOTH = {"velocity", "pinned", "uv", "tension_xy", "stretch_u", "stretch_v", "shear", "panel"}
TENDONS = {"vertex", "tension", "length", "rest_length", "tendon"}


def run(tmp_path, fmt):
    """cloth_drawstring to t = 0.1 s with frames every 0.05 s in format fmt; the folder and the
    final state (copies)."""
    out = tmp_path / fmt
    sim = sinew.load(SCENE, out=out, duration=0.1, frames_every=0.05, frames_format=fmt)
    sim.run(0.1)
    string = sim.tendons["drawstring"]
    state = {"t": sim.time, "x": sim.positions.copy(), "v": sim.velocities.copy(),
             "txy": sim.tension_xy.copy(), "su": sim.stretch_u.copy(),
             "tension": string.tension, "length": string.length, "rest": string.rest_length,
             "way": np.array(string.waypoints), "x0": sim.initial_positions.copy()}
    sim.close()
    return out, state


def same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def check_exact(out, s):
    index = frames.index(str(out))
    assert [t for t, _ in index] == [0.0, 0.05, 0.1]
    assert all(set(files) == {"cloth", "tendons"} for _, files in index)
    t, parts = list(frames.read_run(str(out)))[-1]
    cloth, tend = parts["cloth"], parts["tendons"]
    assert t == s["t"] == cloth.time == tend.time
    assert same_bits(cloth.points, s["x"])
    assert same_bits(cloth.point_data["velocity"], s["v"])
    assert same_bits(cloth.cell_data["tension_xy"], s["txy"])
    assert same_bits(cloth.cell_data["stretch_u"], s["su"])
    assert set(cloth.point_data) | set(cloth.cell_data) == CLOTH
    assert (cloth.cell_data["panel"] == 0).all()
    # the grid's (u,v) layout is the grid itself: plane xz, so (u, v) = (x, z) at rest
    assert np.allclose(cloth.point_data["uv"], s["x0"][:, [0, 2]], atol=1e-12)
    assert set(tend.point_data) | set(tend.cell_data) == TENDONS
    assert same_bits(tend.point_data["vertex"], s["way"].astype(np.int32))
    assert same_bits(tend.points, s["x"][s["way"]])
    assert tend.cell_data["tension"][0] == s["tension"] > 0
    assert tend.cell_data["length"][0] == s["length"]
    assert tend.cell_data["rest_length"][0] == s["rest"]
    assert [list(c) for c in tend.cells()] == [list(range(len(s["way"])))]
    return cloth


def test_binary_frames_hold_the_state_bit_for_bit(tmp_path):
    out, s = run(tmp_path, "binary")
    raw = open(out / "frames" / "frame_000002.vtu", "rb").read()
    assert b'compressor="vtkZLibDataCompressor"' in raw and b'header_type="UInt64"' in raw
    assert b'format="ascii"' not in raw and raw.endswith(b"</AppendedData>\n</VTKFile>\n")
    cloth = check_exact(out, s)
    assert cloth.types.tolist() == [5] * len(s["txy"])


def test_ascii_and_binary32(tmp_path):
    out, s = run(tmp_path, "ascii")
    assert b'format="appended"' not in open(out / "frames" / "frame_000002.vtu", "rb").read()
    check_exact(out, s)
    out32, s32 = run(tmp_path, "binary32")
    assert same_bits(s32["x"], s["x"])  # the same run
    cloth = frames.read(str(out32 / "frames" / "frame_000002.vtu"))
    assert same_bits(cloth.points, s["x"].astype(np.float32))
    assert same_bits(cloth.cell_data["tension_xy"], s["txy"].astype(np.float32))
    assert cloth.time == s["t"]  # TimeValue stays Float64
    big = os.path.getsize(out / "frames" / "frame_000002.vtu")
    assert os.path.getsize(out32 / "frames" / "frame_000002.vtu") < big / 2


def test_bad_format_is_an_error(tmp_path):
    with pytest.raises(sinew.SinewError, match="frames format"):
        sinew.load(SCENE, frames_format="hdf5")


def test_vtk_reads_the_frames(tmp_path):
    """VTK's own XML readers (what ParaView uses) load the binary frames with the same values."""
    xml = pytest.importorskip("vtkmodules.vtkIOXML")
    from vtkmodules.util.numpy_support import vtk_to_numpy

    out, s = run(tmp_path, "binary")

    def load(reader, name):
        reader.SetFileName(str(out / "frames" / name))
        reader.Update()
        return reader.GetOutput()

    def arrays(data):
        return {data.GetArrayName(i): vtk_to_numpy(data.GetArray(i))
                for i in range(data.GetNumberOfArrays())}

    grid = load(xml.vtkXMLUnstructuredGridReader(), "frame_000002.vtu")
    assert grid.GetNumberOfCells() == len(s["txy"])
    assert same_bits(vtk_to_numpy(grid.GetPoints().GetData()), s["x"])
    cells, points = arrays(grid.GetCellData()), arrays(grid.GetPointData())
    assert set(cells) | set(points) == CLOTH
    assert same_bits(cells["tension_xy"], s["txy"])
    assert vtk_to_numpy(grid.GetFieldData().GetArray("TimeValue"))[0] == s["t"]
    poly = load(xml.vtkXMLPolyDataReader(), "tendons_000002.vtp")
    assert poly.GetNumberOfLines() == 1 and poly.GetNumberOfPoints() == len(s["way"])
    tcells = arrays(poly.GetCellData())
    assert set(tcells) | set(arrays(poly.GetPointData())) == TENDONS
    assert tcells["tension"][0] == s["tension"]
