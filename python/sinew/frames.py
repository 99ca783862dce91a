"""Read the frames of a sinew run folder (frames.pvd, frames/*.vtu, frames/*.vtp) with numpy and
zlib alone: VTK's XML format as sinew writes it, binary (arrays appended raw and
zlib-compressed, UInt64 headers) or ascii.  docs/scenes.md, "Frames", names the arrays.

    from sinew.frames import read_run
    for t, parts in read_run("out/cloth_drawstring"):
        cloth = parts["cloth"]                      # a Piece
        cloth.points                                # (nv, 3) m
        cloth.cell_data["tension_xy"]               # (nf,) N/m
        parts.get("tendons")                        # a Piece of polylines, or None
"""
import os
import struct
import xml.etree.ElementTree as ET
import zlib

import numpy as np

_DTYPES = {"Float64": "f8", "Float32": "f4", "Int32": "i4", "Int64": "i8", "UInt8": "u1",
           "UInt32": "u4", "UInt64": "u8"}
_HEADER = {"UInt64": ("Q", 8), "UInt32": ("I", 4)}


class Piece:
    """One dataset of a frame: points (n, 3), cells (connectivity, offsets, types: for a
    PolyData, the Lines), and the point, cell and field arrays by name."""

    def __init__(self):
        self.points = None
        self.connectivity = self.offsets = self.types = None
        self.point_data, self.cell_data, self.field_data = {}, {}, {}

    @property
    def time(self):
        """The frame's time (s), from its TimeValue."""
        return float(self.field_data["TimeValue"][0])

    def cells(self):
        """The list of cells, each an array of point indices."""
        starts = np.concatenate([[0], self.offsets[:-1]])
        return [self.connectivity[a:b] for a, b in zip(starts, self.offsets)]


def _split(raw):
    """The XML text of a VTK file and its raw appended bytes (after the '_' marker), if any."""
    at = raw.find(b"<AppendedData")
    if at < 0:
        return raw.decode("utf-8"), b""
    mark = raw.index(b"_", raw.index(b">", at))
    return raw[:at].decode("utf-8") + "</VTKFile>", raw[mark + 1:]


def _appended(blob, offset, dtype, header, compressed):
    """The bytes of one appended array at offset, decompressed when compressed."""
    code, size = _HEADER[header]
    if not compressed:
        (n,) = struct.unpack_from("<" + code, blob, offset)
        return np.frombuffer(blob, dtype=dtype, count=n // np.dtype(dtype).itemsize,
                             offset=offset + size)
    nb, _, _ = struct.unpack_from("<3" + code, blob, offset)
    sizes = struct.unpack_from("<%d%s" % (nb, code), blob, offset + 3 * size)
    pos = offset + (3 + nb) * size
    parts = []
    for s in sizes:
        parts.append(zlib.decompress(blob[pos:pos + s]))
        pos += s
    return np.frombuffer(b"".join(parts), dtype=dtype)


def _array(node, blob, header, compressed):
    dtype = np.dtype(_DTYPES[node.get("type")]).newbyteorder("<")
    if node.get("format") == "appended":
        a = _appended(blob, int(node.get("offset")), dtype, header, compressed)
    else:
        a = np.array((node.text or "").split(), dtype=dtype)
    ncomp = int(node.get("NumberOfComponents", "1"))
    return a.reshape(-1, ncomp) if ncomp > 1 else a


def read(path):
    """A Piece from one .vtu or .vtp file that sinew wrote."""
    with open(path, "rb") as f:
        text, blob = _split(f.read())
    root = ET.fromstring(text)
    if root.get("byte_order", "LittleEndian") != "LittleEndian":
        raise ValueError("%s: only little-endian files are read" % path)
    header = root.get("header_type", "UInt32")
    compressed = root.get("compressor") == "vtkZLibDataCompressor"
    grid = root[0]
    piece, p = Piece(), grid.find("Piece")
    get = lambda node: _array(node, blob, header, compressed)  # noqa: E731
    for sect, into in (("PointData", piece.point_data), ("CellData", piece.cell_data)):
        for a in p.iterfind(sect + "/DataArray"):
            into[a.get("Name")] = get(a)
    for a in grid.iterfind("FieldData/DataArray"):
        piece.field_data[a.get("Name")] = get(a)
    piece.points = get(p.find("Points/DataArray"))
    cells = p.find("Cells")
    cells = p.find("Lines") if cells is None else cells
    if cells is not None:
        arrays = {a.get("Name"): get(a) for a in cells.iterfind("DataArray")}
        piece.connectivity, piece.offsets = arrays["connectivity"], arrays["offsets"]
        piece.types = arrays.get("types")
    return piece


def index(run_dir):
    """frames.pvd of a run folder: [(time s, {part name: file path})] in time order."""
    root = ET.parse(os.path.join(run_dir, "frames.pvd")).getroot()
    frames = {}
    for ds in root.iterfind("Collection/DataSet"):
        t = float(ds.get("timestep"))
        name = ds.get("name") or ("cloth" if ds.get("part", "0") == "0" else "tendons")
        frames.setdefault(t, {})[name] = os.path.join(run_dir, ds.get("file"))
    return sorted(frames.items())


def read_run(run_dir):
    """Every frame of a run folder, as (time s, {part name: Piece}), in time order."""
    for t, files in index(run_dir):
        yield t, {name: read(path) for name, path in files.items()}
