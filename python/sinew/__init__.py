"""sinew from Python: load a scene, step it, read its state and diagnostics, change tendons,
pins and loads between steps.

A thin layer (ctypes) over libsinew's stepping API (sinew.h, "stepping"); the arrays it hands
out are numpy views of sinew's own memory (no copies), read-only: write through the setters
(``sim.positions = ...``, ``tendon.rest_length = ...``), which tell the integrator to restart
where its history no longer holds.  Units are SI: m, s, kg, N.  docs/python.md has the guide.

The library is found at $SINEW_LIB (a path to libsinew.so), else in the package's folder (where
``pip install .`` puts it), else where ``meson install`` put it (``_libpath.py``, written at
install), else on the loader's path.
"""
import ctypes
import ctypes.util
import math
import operator
import os
import threading
from collections.abc import Mapping

import numpy as np

__all__ = ["load", "Simulation", "State", "Tendon", "SinewError", "methods"]

_ERRSZ = 1024


class SinewError(RuntimeError):
    """An error of libsinew, with its message (file:line:column for a bad scene), or a
    simulation used when it cannot be: closed, or being stepped by another thread."""


class _Overrides(ctypes.Structure):
    _fields_ = [("grid", ctypes.c_int * 2), ("stiffness_scale", ctypes.c_double),
                ("bending_matrix", ctypes.c_int), ("method", ctypes.c_char_p)]


def _find_library():
    path = os.environ.get("SINEW_LIB")
    beside = os.path.join(os.path.dirname(os.path.abspath(__file__)), "libsinew.so")
    if not path and os.path.exists(beside):  # pip install . puts it in the package
        path = beside
    if not path:
        try:
            from . import _libpath  # written by meson install
            path = _libpath.LIBRARY
        except ImportError:
            path = ctypes.util.find_library("sinew")
    if not path:
        raise SinewError("libsinew not found: set SINEW_LIB to the path of libsinew.so "
                         "(in a build tree: build/libsinew.so)")
    try:
        return ctypes.CDLL(path)
    except OSError as e:
        raise SinewError("cannot load libsinew from %s: %s" % (path, e)) from None


_P = ctypes.c_void_p
_D = ctypes.c_double
_I = ctypes.c_int
_S = ctypes.c_char_p
_Z = ctypes.c_size_t
_DP = ctypes.POINTER(ctypes.c_double)
_IP = ctypes.POINTER(ctypes.c_int)

_SIGNATURES = {
    "sw_scene_load_ex": (_P, [_S, ctypes.POINTER(_Overrides), _S, _Z]),
    "sw_model_free": (None, [_P]),
    "sw_model_set_option": (_I, [_P, _S, _S, _S, _Z]),
    "sw_sim_new": (_P, [_P, _I, _S, _Z]),
    "sw_sim_step": (_I, [_P, _S, _Z]),
    "sw_sim_run": (_I, [_P, _D, _S, _Z]),
    "sw_sim_run_steps": (_I, [_P, _D, ctypes.c_long, _S, _Z]),
    "sw_sim_reset": (_I, [_P, _S, _Z]),
    "sw_sim_set_dt": (_I, [_P, _D, _S, _Z]),
    "sw_sim_dt": (_D, [_P]),
    "sw_sim_set_rests": (_I, [_P, _DP, _S, _Z]),
    "sw_sim_rests": (None, [_P, _DP]),
    "sw_sim_get_state": (_Z, [_P, ctypes.c_char_p, _Z]),
    "sw_sim_put_state": (_I, [_P, ctypes.c_char_p, _Z, _S, _Z]),
    "sw_sim_close": (_I, [_P, _S, _Z]),
    "sw_sim_free": (None, [_P]),
    "sw_sim_energy": (None, [_P, _DP, _DP, _DP]),
    "sw_sim_set_state": (_I, [_P, _D, _DP, _DP, _S, _Z]),
    "sw_sim_set_rest": (_I, [_P, _I, _D, _S, _Z]),
    "sw_sim_set_pin": (_I, [_P, _I, _DP, _S, _Z]),
    "sw_sim_set_load": (_I, [_P, _I, _DP, _S, _Z]),
    "sw_sim_array": (_DP, [_P, _S, _IP, _IP]),
    "sw_sim_iarray": (_IP, [_P, _S, _IP, _IP]),
    "sw_sim_counter": (ctypes.c_long, [_P, _S]),
    "sw_sim_counters": (_I, [_P, ctypes.POINTER(ctypes.c_long), _I]),
    "sw_sim_size": (_I, [_P, _S]),
    "sw_sim_name": (_S, [_P, _S, _I]),
    "sw_sim_rest": (_D, [_P, _I]),
    "sw_sim_time": (_D, [_P]),
    "sw_sim_waypoints": (_IP, [_P, _I, _IP]),
    "sw_method_names": (ctypes.POINTER(_S), []),
}

_lib = None


def _library():
    global _lib
    if _lib is None:
        lib = _find_library()
        for name, (res, args) in _SIGNATURES.items():
            f = getattr(lib, name)
            f.restype = res
            f.argtypes = args
        _lib = lib
    return _lib


def _call(fn, *args):
    """fn(*args, err, errsz); a SinewError with sinew's message when it returns nonzero."""
    err = ctypes.create_string_buffer(_ERRSZ)
    rc = fn(*args, err, _ERRSZ)
    if rc:
        raise SinewError(err.value.decode(errors="replace"))


def methods():
    """The names of the integrators (and "static")."""
    names, k, out = _library().sw_method_names(), 0, []
    while names[k]:
        out.append(names[k].decode())
        k += 1
    return out


def _view(owner, ptr, shape, ctype, dtype):
    """A read-only numpy array over sinew's memory at ptr that keeps owner alive."""
    n = int(np.prod(shape))
    if n == 0 or not ptr:
        return np.zeros(shape, dtype=dtype)
    buf = (ctype * n).from_address(ctypes.addressof(ptr.contents))
    buf._owner = owner
    a = np.frombuffer(buf, dtype=dtype).reshape(shape)
    a.flags.writeable = False
    return a


def _path(value, what):
    """value (str or path-like) as bytes for C; a ValueError for a NUL byte, which C would take
    for the end of the string."""
    b = os.fsencode(value)
    if b"\0" in b:
        raise ValueError("%s %r: contains a NUL byte; expected a path without one" % (what, value))
    return b


def _vector(values, n, what):
    a = np.ascontiguousarray(values, dtype=np.float64).reshape(-1)
    if a.size != n:
        raise ValueError("%s: %d values; expected %d" % (what, a.size, n))
    return a


class Tendon:
    """One tendon of a simulation: its length (m), tension (N) and rest length (m, settable:
    from then on the rest length is constant, its keyframes replaced)."""

    def __init__(self, sim, index, name):
        self._sim, self.index, self.name = sim, index, name

    @property
    def rest_length(self):
        return _library().sw_sim_rest(self._sim._ptr, self.index)

    @rest_length.setter
    def rest_length(self, value):
        with self._sim._using("set rest_length"):
            _call(_library().sw_sim_set_rest, self._sim._ptr, self.index, float(value))

    @property
    def length(self):
        return float(self._sim._views["tendon_length"][self.index])

    @property
    def tension(self):
        return float(self._sim._views["tendon_tension"][self.index])

    @property
    def waypoints(self):
        n = ctypes.c_int()
        p = _library().sw_sim_waypoints(self._sim._ptr, self.index, ctypes.byref(n))
        return _view(self._sim._handle, p, (n.value,), ctypes.c_int, np.intc)

    def __repr__(self):
        return "<Tendon %r: length %.6g m, rest %.6g m, tension %.6g N>" % (
            self.name, self.length, self.rest_length, self.tension)


class _Tendons(Mapping):
    def __init__(self, sim):
        lib = _library()
        n = lib.sw_sim_size(sim._ptr, b"ntendon")
        self._items = {}
        for k in range(n):
            name = lib.sw_sim_name(sim._ptr, b"tendon", k).decode()
            self._items[name] = Tendon(sim, k, name)

    def __getitem__(self, name):
        try:
            return self._items[name]
        except KeyError:
            raise KeyError("no tendon %r (the scene has: %s)" %
                           (name, ", ".join(self._items) or "none")) from None

    def __iter__(self):
        return iter(self._items)

    def __len__(self):
        return len(self._items)

    def __repr__(self):
        return "<tendons: %s>" % ", ".join(repr(t) for t in self._items.values())


class _Handle:
    """The C simulation and its model: freed when the Simulation and every array handed out
    of it are gone (the arrays keep it, not the Simulation, so nothing is kept in a cycle)."""

    def __init__(self, ptr, model):
        self.ptr, self.model = ptr, model

    def __del__(self):
        lib = _lib
        if lib is None:
            return
        if self.ptr:
            lib.sw_sim_free(self.ptr)
            self.ptr = None
        if self.model:
            lib.sw_model_free(self.model)
            self.model = None


class State:
    """A copy of a simulation's whole state (Simulation.state()): time, positions, velocities,
    counters and the integrator's history, for Simulation.set_state(state).  .time (s),
    .positions and .velocities ((nv, dim) copies) are there to look at."""

    def __init__(self, data, time, positions, velocities):
        self._data, self.time = bytes(data), time
        self.positions, self.velocities = positions, velocities

    def __repr__(self):
        return "<sinew.State t = %.9g s, %d bytes>" % (self.time, len(self._data))


_COUNTERS = ("nstep", "nnewton", "nfactor", "nassemble", "nforce", "nretry", "nlinesearch",
             "nerrfail", "nsetup", "ncg", "nbound")  # sw_sim_counters' order
_READ_VIEWS = {"positions": "x", "velocities": "v", "initial_positions": "x0", "masses": "mass",
               "tension_xy": "tension_xy", "stretch_u": "stretch_u", "stretch_v": "stretch_v",
               "shear": "shear", "tendon_length": "tendon_length",
               "tendon_tension": "tendon_tension", "term_energy": "term_energy",
               "energy": "energy"}


class Simulation:
    """A scene being simulated, one step at a time (sinew.h: sw_sim).  Made by sinew.load."""

    def __init__(self, model, flags):
        lib = _library()
        err = ctypes.create_string_buffer(_ERRSZ)
        ptr = lib.sw_sim_new(model, flags, err, _ERRSZ)
        if not ptr:
            lib.sw_model_free(model)
            raise SinewError(err.value.decode(errors="replace"))
        self._handle = _Handle(ptr, model)
        self._ptr = ptr
        self._closed = False
        self._lock = threading.Lock()
        self._static = self.method == "static"
        # the arrays of sw_sim_array keep their addresses for the simulation's life (a reset
        # too): one read-only view each, made once
        self._views = {key: self._array(name) for key, name in _READ_VIEWS.items()}
        nt = self._size("ntendon")
        for key in ("tendon_length", "tendon_tension"):
            self._views[key] = self._views[key][:nt]
        self._rest = np.zeros(nt)
        self._rest_ptr = self._rest.ctypes.data_as(_DP)
        self._counter_buf = (ctypes.c_long * len(_COUNTERS))()
        self._rests_fn = lib.sw_sim_rests
        self._counters_fn = lib.sw_sim_counters
        # the counters change only in a change made under _using: read once after each
        self._counters_cache = None
        self._rest_out = self._rest.view()
        self._rest_out.flags.writeable = False
        self._term_names = ["E_" + lib.sw_sim_name(ptr, b"term", i).decode()
                            for i in range(self._size("nterm"))]
        self.tendons = _Tendons(self)
        """The tendons by name: each with .length, .tension, settable .rest_length."""

    # ---------------------------------------------------------------- lifetime
    def _using(self, what):
        """The simulation, held for one change or run: a SinewError when it is closed or when
        another thread holds it (one simulation is stepped by one thread at a time)."""
        if self._closed:
            raise SinewError("%s: the simulation is closed; load the scene again to go on" % what)
        if not self._lock.acquire(blocking=False):
            raise SinewError("%s: the simulation is being used by another thread; give each "
                             "thread its own simulation (sinew.load) or hold a lock around it"
                             % what)
        self._counters_cache = None
        return _Held(self)

    def close(self):
        """Finish the run folder (summary.json; nothing without one).  From then on, steps and
        changes raise SinewError; the arrays stay readable."""
        if self._closed:
            return
        with self._using("close"):
            self._closed = True
            _call(_library().sw_sim_close, self._ptr)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        # close() (the memory goes with the last array that views it, see _Handle)
        if getattr(self, "_closed", True) or _lib is None:
            return
        self._closed = True
        if self._lock.acquire(blocking=False):
            try:
                _lib.sw_sim_close(self._ptr, None, 0)
            finally:
                self._lock.release()

    # ---------------------------------------------------------------- stepping
    def step(self, n=1):
        """n steps of dt (n >= 0; the static method: an equilibrium solve from the current
        positions)."""
        n = operator.index(n)
        if n < 0:
            raise ValueError("step: n = %d; expected a number of steps >= 0" % n)
        lib = _library()
        for _ in range(n):
            with self._using("step"):
                _call(lib.sw_sim_step, self._ptr)

    def run(self, until):
        """Step until the time `until` (s, finite, not before the current time); the last step
        is shortened to land on it.  One step at a time, so Ctrl-C stops it after the step
        going (KeyboardInterrupt, with the state of that step)."""
        until = float(until)
        if not math.isfinite(until) or until < self.time:
            raise ValueError("run: until = %r s; expected a finite time >= the current time "
                             "%.9g s" % (until, self.time))
        lib = _library()
        while True:
            with self._using("run"):
                _call(lib.sw_sim_run_steps, self._ptr, until, 1)
            if self._static or self.time >= until:
                return

    def reset(self):
        """Back to the initial state (t = 0, the scene's positions and velocities, counters 0,
        the integrator afresh), as sinew.load made it; changed rest lengths, loads and dt stay.
        Not for a simulation writing a run folder."""
        with self._using("reset"):
            _call(_library().sw_sim_reset, self._ptr)

    @property
    def dt(self):
        """The time step, s (with CVODE and IDA: the interval the state is handed out at).
        Settable (not for the static method): the step grid starts again at the current time
        and the integrator's history restarts."""
        return _library().sw_sim_dt(self._ptr)

    @dt.setter
    def dt(self, value):
        with self._using("set dt"):
            _call(_library().sw_sim_set_dt, self._ptr, float(value))

    # ---------------------------------------------------------------- reading
    def _size(self, name):
        return _library().sw_sim_size(self._ptr, name.encode())

    def _array(self, name):
        rows, cols = ctypes.c_int(), ctypes.c_int()
        p = _library().sw_sim_array(self._ptr, name.encode(), ctypes.byref(rows),
                                    ctypes.byref(cols))
        shape = (rows.value,) if cols.value == 1 else (rows.value, cols.value)
        return _view(self._handle, p, shape, ctypes.c_double, np.float64)

    @property
    def closed(self):
        """True after close()."""
        return self._closed

    @property
    def time(self):
        """The current time, s."""
        return _library().sw_sim_time(self._ptr)

    @property
    def nv(self):
        return self._size("nv")

    @property
    def dim(self):
        return self._size("dim")

    @property
    def nfaces(self):
        return self._size("nf")

    @property
    def method(self):
        return _library().sw_sim_name(self._ptr, b"method", 0).decode()

    @property
    def positions(self):
        """(nv, dim) positions, m: a read-only view that follows the simulation."""
        return self._views["positions"]

    @positions.setter
    def positions(self, x):
        self.set_state(positions=x)

    @property
    def velocities(self):
        """(nv, dim) velocities, m/s: a read-only view."""
        return self._views["velocities"]

    @velocities.setter
    def velocities(self, v):
        self.set_state(velocities=v)

    @property
    def initial_positions(self):
        return self._views["initial_positions"]

    @property
    def faces(self):
        rows, cols = ctypes.c_int(), ctypes.c_int()
        p = _library().sw_sim_iarray(self._ptr, b"face", ctypes.byref(rows), ctypes.byref(cols))
        return _view(self._handle, p, (rows.value, cols.value), ctypes.c_int, np.intc)

    @property
    def pinned(self):
        """(nv,) bool: the vertices with a pinned component."""
        rows, cols = ctypes.c_int(), ctypes.c_int()
        p = _library().sw_sim_iarray(self._ptr, b"dof", ctypes.byref(rows), ctypes.byref(cols))
        return (_view(self._handle, p, (rows.value, cols.value), ctypes.c_int,
                      np.intc) < 0).any(axis=1)

    @property
    def masses(self):
        """(nv,) lumped masses, kg."""
        return self._views["masses"]

    @property
    def tension_xy(self):
        """(nfaces,) tension XY of each face, N/m."""
        return self._views["tension_xy"]

    @property
    def contact_pressure(self):
        """(nfaces,) contact pressure on each face (obstacles and self-contact), N/m^2; None in a
        scene without obstacles or self-contact."""
        if "contact_pressure" not in self._views:
            p = _library().sw_sim_array(self._ptr, b"contact_pressure", None, None)
            self._views["contact_pressure"] = self._array("contact_pressure") if p else None
        return self._views["contact_pressure"]

    @property
    def stretch_u(self):
        """(nfaces,) warp stretch |w_u| of each face (1: unstretched)."""
        return self._views["stretch_u"]

    @property
    def stretch_v(self):
        """(nfaces,) weft stretch |w_v| of each face."""
        return self._views["stretch_v"]

    @property
    def shear(self):
        """(nfaces,) shear angle between the warp and weft directions, rad."""
        return self._views["shear"]

    @property
    def tendon_length(self):
        """(ntendons,) every tendon's length, m, in the order of sim.tendons: a read-only view."""
        return self._views["tendon_length"]

    @property
    def tendon_tension(self):
        """(ntendons,) every tendon's tension, N: a read-only view."""
        return self._views["tendon_tension"]

    @property
    def tendon_rest(self):
        """(ntendons,) every tendon's rest length at the current time, m: a read-only array,
        refilled at each read.  Settable: all rest lengths at once, from then on."""
        self._rests_fn(self._ptr, self._rest_ptr)
        return self._rest_out

    @tendon_rest.setter
    def tendon_rest(self, values):
        r = _vector(values, len(self._rest), "tendon_rest")
        with self._using("set tendon_rest"):
            _call(_library().sw_sim_set_rests, self._ptr, r.ctypes.data_as(_DP))

    @property
    def energy(self):
        """Energies of the current state, J: kinetic, potential, total, dissipated (by damping,
        so far) and one entry per term ("E_" + its name)."""
        out = dict(zip(("kinetic", "potential", "total", "dissipated"),
                       self._views["energy"].tolist()))
        out.update(zip(self._term_names, self._views["term_energy"].tolist()))
        return out

    @property
    def counters(self):
        """The solver's counters since the start: steps, Newton iterations, factorisations..."""
        c = self._counters_cache
        if c is None:  # changed since the last read (_using, _Held)
            self._counters_fn(self._ptr, self._counter_buf, len(_COUNTERS))
            c = self._counters_cache = dict(zip(_COUNTERS, self._counter_buf[:]))
        return c.copy()

    # ---------------------------------------------------------------- changing
    def state(self):
        """A copy of the whole state (a State): time, positions, velocities, counters and the
        integrator's history; set_state(copy) goes on from it exactly (to the bit, for every
        method but CVODE and IDA, which restart there).  Rest lengths and loads are the model's,
        not the state's."""
        lib = _library()
        n = lib.sw_sim_get_state(self._ptr, None, 0)
        buf = ctypes.create_string_buffer(n)
        if n == 0 or lib.sw_sim_get_state(self._ptr, buf, n) != n:
            raise SinewError("state: out of memory copying the state")
        return State(buf.raw, self.time, self.positions.copy(), self.velocities.copy())

    def set_state(self, state=None, time=None, positions=None, velocities=None):
        """set_state(copy): the state of a State from state(); or set the time (s), positions
        ((nv, dim), m: pinned rows move the pins) and velocities ((nv, dim), m/s), None keeping
        one (the integrator then restarts its history)."""
        if isinstance(state, State):
            if time is not None or positions is not None or velocities is not None:
                raise TypeError("set_state: a State, or time/positions/velocities; not both")
            with self._using("set_state"):
                _call(_library().sw_sim_put_state, self._ptr, state._data, len(state._data))
            return
        if state is not None:  # set_state(t, x, v) by position
            if time is not None:
                raise TypeError("set_state: time given twice")
            time = state
        nd = self.nv * self.dim
        t = self.time if time is None else float(time)
        x = None if positions is None else _vector(positions, nd, "positions")
        v = None if velocities is None else _vector(velocities, nd, "velocities")
        as_ptr = (lambda a: None if a is None else a.ctypes.data_as(_DP))
        with self._using("set_state"):
            _call(_library().sw_sim_set_state, self._ptr, t, as_ptr(x), as_ptr(v))

    def _vertex(self, vertex, what):
        i = operator.index(vertex)
        if not 0 <= i < self.nv:
            raise IndexError("%s: vertex %d; expected 0 <= vertex < %d" % (what, i, self.nv))
        return i

    def set_pin(self, vertex, position):
        """Move pinned vertex `vertex` to position (dim values, m)."""
        i = self._vertex(vertex, "set_pin")
        p = _vector(position, self.dim, "position")
        with self._using("set_pin"):
            _call(_library().sw_sim_set_pin, self._ptr, i, p.ctypes.data_as(_DP))

    def set_load(self, vertex, force):
        """The point load on `vertex` (dim values, N); the scene must have `loads`."""
        i = self._vertex(vertex, "set_load")
        f = _vector(force, self.dim, "force")
        with self._using("set_load"):
            _call(_library().sw_sim_set_load, self._ptr, i, f.ctypes.data_as(_DP))

    def __repr__(self):
        return "<sinew.Simulation %s: %d vertices, %d faces, t = %.6g s%s>" % (
            self.method, self.nv, self.nfaces, self.time, ", closed" if self._closed else "")


class _Held:
    """A simulation's held lock, released at the end of a with block (the counters read again
    at the next read: the change may have moved them)."""

    def __init__(self, sim):
        self._sim = sim

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._sim._counters_cache = None
        self._sim._lock.release()


def load(scene, method=None, dt=None, out=None, grid=None, stiffness_scale=None,
         bending_matrix=None, **options):
    """Load a scene file and start a simulation of it at t = 0.

    method, dt: the integrator and its step (s), overriding the scene's; out: a folder to
    write the usual run folder to (True: the scene's output.dir; None: none); grid (nx, ny) and
    stiffness_scale as `sinew run --grid/--stiffness-scale`; bending_matrix ("exact", "compact"
    or "auto") as `--bending-matrix`; any other option of the scene's
    integrator by name (duration, rtol, atol, max_order, max_step, newton_tol, newton_max,
    max_halvings, frames_every, positions_every, hessian).  Raises SinewError with sinew's
    message (file:line:column for a bad scene)."""
    lib = _library()
    ov = _Overrides()
    if grid is not None:
        ov.grid[0], ov.grid[1] = int(grid[0]), int(grid[1])
    if stiffness_scale is not None:
        ov.stiffness_scale = float(stiffness_scale)
    if bending_matrix is not None:
        names = ("exact", "compact", "auto")
        if bending_matrix not in names:
            raise SinewError("bending_matrix is %r; expected one of: %s"
                             % (bending_matrix, ", ".join(names)))
        ov.bending_matrix = names.index(bending_matrix) + 1
    if method is not None:  # before the terms are built: the bending matrix's auto reads it
        ov.method = str(method).encode()
    err = ctypes.create_string_buffer(_ERRSZ)
    model = lib.sw_scene_load_ex(_path(scene, "scene"), ctypes.byref(ov), err, _ERRSZ)
    if not model:
        raise SinewError(err.value.decode(errors="replace"))
    settings = dict(options)
    if method is not None:
        settings["method"] = method
    if dt is not None:
        settings["dt"] = dt
    if out is not None and out is not True:
        settings["out"] = os.fspath(out)
    try:
        for key, value in settings.items():
            _call(lib.sw_model_set_option, model, key.encode(),
                  _path(value if key == "out" else str(value), key))
    except SinewError:
        lib.sw_model_free(model)
        raise
    return Simulation(model, 1 if out is not None and out is not False else 0)
