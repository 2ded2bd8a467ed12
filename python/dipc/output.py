"""Read a dipc run's output (the .xmf and .h5 that dipc writes for ParaView) as NumPy arrays.

    from dipc.output import read_output

    out = read_output("output/dipc.xmf")        # or "output/dipc.h5"
    out.times                                   # (F,) the frames' times
    out.steps                                   # (F,) their scene steps (stats.csv beside; else None)
    out.fields                                  # ("displacement", "velocity", "volume_ratio")
    u = out.field("displacement")               # (F, N, 3), every frame
    u_last = out.field("displacement", -1)      # (N, 3), one frame
    x = out.coordinates + u_last                # deformed positions
    last = out.frame(-1)                        # {"displacement": (N, 3), ..., "volume_ratio": (E,)}
    out.hexes                                   # (E, 8) node ids, rows of out.coordinates

A frame is one written step, /steps/<k> in the .h5: the initial state, then every scene step the
scene's "output.every" selects and the last one (with -dipc_output_substeps also the sub-steps
of cut steps). Node fields (displacement, velocity and, in contact scenes, contact_force and
friction_force) have a row per node, N x 3; cell fields (volume_ratio) a value per hexahedron.
`frames` arguments take what indexes a NumPy array of the frames: an int (no frame axis in the
result), a slice, a list of frame numbers or a boolean mask.

Rows are in the input mesh's numbering (the scene's bodies in order), which dipc writes whatever
the number of ranks, so runs on different rank counts give arrays that compare row for row;
only `rank` (each element's owning rank) depends on the rank count. Files written before dipc
wrote that numbering (partition order, no input ids stored) cannot be reordered and are not
recognised as such.

The .xmf is the authority on which frames are complete: dipc rewrites it after each step is on
disk, so a run that failed or was killed mid-way still reads up to its last complete frame. Given
only an .h5 without its .xmf, the frames are the /steps groups that hold every field.

Only metadata is read at open; the mesh on first use and fields when asked for. The .h5 is opened
for each read and closed again: an Output needs no closing and holds no file open while a run (or
its restart) goes on writing it. A run in progress reads with the frames its .xmf lists at open;
now and then the .h5's metadata is caught mid-update (HDF5 offers no concurrent reader here), a
ValueError that reading again clears.
"""
import csv
import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from functools import cached_property

import h5py
import numpy as np

__all__ = ["Output", "Obstacle", "read_output"]

# The fields every frame has (xdmf_writer.hpp); contact scenes add contact_force, friction_force.
ALWAYS_WRITTEN = {"displacement", "velocity", "volume_ratio"}


@dataclass(frozen=True, eq=False)  # eq=False: fields are arrays
class Obstacle:
    """A contact obstacle: a plane (drawn as a square patch, one quad) or a triangle mesh."""

    name: str
    kind: str  # "plane" or "triangle_mesh"
    coordinates: np.ndarray  # (V, 3) rest positions
    cells: np.ndarray  # (1, 4) for a plane's patch, (T, 3) triangles
    moving: bool  # a displacement per frame (else it stays at rest)


def read_output(path):
    """Open a dipc run's output, given its .xmf or its .h5. Returns an Output.

    Raises FileNotFoundError when the file (or the .h5 an .xmf names) does not exist, and
    ValueError, naming the file, when it is not dipc output or the .xmf and .h5 disagree.
    """
    return Output(path)


class Output:
    """A dipc run's output: mesh, frames and fields. Build it with read_output(path).

    Attributes read at open: path (the .h5), xmf_path (None when read without one), times,
    steps, stats, fields, num_nodes, num_elements, body_names, obstacles, contact_pairs.
    Read on first use: coordinates, hexes, body, rank, kinematic, node_sets.
    """

    def __init__(self, path):
        path = os.fspath(path)
        if not os.path.isfile(path):
            raise FileNotFoundError(f"dipc output not found: {path}")
        suffix = os.path.splitext(path)[1].lower()
        if suffix == ".xmf":
            self.xmf_path = path
            self.path, listed_times = _read_xmf(path)
            if not os.path.isfile(self.path):
                raise FileNotFoundError(f"{self.path}, which {path} refers to, does not exist")
        elif suffix == ".h5":
            self.path = path
            beside = os.path.splitext(path)[0] + ".xmf"  # dipc writes <name>.xmf next to <name>.h5
            self.xmf_path = beside if os.path.isfile(beside) else None
            listed_times = _read_xmf(beside)[1] if self.xmf_path else None
        else:
            raise ValueError(f"{path}: not dipc output (expected the run's .xmf or .h5)")

        with self._open() as f:
            for name in ("mesh/coordinates", "mesh/topology", "steps"):
                if name not in f:
                    raise ValueError(f"{self.path}: not dipc output (no /{name})")
            self.num_nodes = f["mesh/coordinates"].shape[0]
            self.num_elements = f["mesh/topology"].shape[0]
            self.body_names = [_text(s) for s in f["mesh/body_names"][()]] if "mesh/body_names" in f else []
            self.obstacles = [_read_obstacle(f[f"obstacles/{j}"]) for j in range(len(f.get("obstacles", {})))]
            self.times = np.array(_complete_steps(f) if listed_times is None else listed_times, dtype=np.float64)
            self.contact_pairs = self._check_steps(f)
            first = f["steps/0"] if len(self.times) else {}
            # A field's shape in one frame: (N, 3) for node fields, (E,) for cell fields.
            self._field_shapes = {name: first[name].shape for name in _step_fields(first)}
        self.fields = tuple(self._field_shapes)
        self.stats = _read_stats(os.path.join(os.path.dirname(self.path), "stats.csv"))
        self.steps = None if self.stats is None else _scene_steps(self.times, self.stats)

    def _open(self):
        try:
            return h5py.File(self.path, "r")
        except OSError as e:
            raise ValueError(f"{self.path}: cannot be read as HDF5 ({e})") from e

    def _check_steps(self, f):
        """The contact pair counts of the listed frames, {kind: (F,) int64}, after checking that
        the .h5 holds each frame at the time the .xmf gives (else the two are of different runs)."""
        pairs = {}
        for k, t in enumerate(self.times):
            step = f.get(f"steps/{k}")
            # Both are the .xmf's and .h5's of different runs, or of a run that is writing its
            # .h5 now (its metadata can be seen half-updated: HDF5 has no concurrent readers here).
            if step is None:
                raise ValueError(f"{self.path}: has no /steps/{k}, which {self.xmf_path} lists "
                                 "(files of different runs, or a run writing it now?)")
            if step.attrs.get("time") != t:
                raise ValueError(f"{self.path}: /steps/{k} has time {step.attrs.get('time')}, "
                                 f"{self.xmf_path} lists {t!r} (files of different runs?)")
            for name, value in step.attrs.items():
                if name.startswith("contact_pairs_"):
                    pairs.setdefault(name[len("contact_pairs_"):], np.zeros(len(self.times), np.int64))[k] = value
        return pairs

    def __len__(self):
        return len(self.times)

    @property
    def num_frames(self):
        return len(self.times)

    def __repr__(self):
        span = f", t = {self.times[0]:g} .. {self.times[-1]:g}" if len(self) else ""
        return (f"<dipc Output {self.path}: {len(self)} frames{span}, {self.num_nodes} nodes, "
                f"{self.num_elements} hexes, fields {', '.join(self.fields)}>")

    def _mesh(self, name):
        with self._open() as f:
            return f[name][()] if name in f else None

    @cached_property
    def coordinates(self):
        """(N, 3) float64 rest positions."""
        return self._mesh("mesh/coordinates")

    @cached_property
    def hexes(self):
        """(E, 8) int64 node ids per hexahedron (Gmsh/XDMF corner order)."""
        return self._mesh("mesh/topology")

    @cached_property
    def body(self):
        """(E,) int32 body id of each element, an index into body_names."""
        return self._mesh("mesh/body")

    @cached_property
    def rank(self):
        """(E,) int32 rank that owned each element: the only array that depends on the rank count."""
        return self._mesh("mesh/rank")

    @cached_property
    def kinematic(self):
        """(E,) int32, 1 in kinematic bodies; None when the scene has none."""
        return self._mesh("mesh/kinematic")

    @cached_property
    def node_sets(self):
        """{name: sorted node ids} of the scene's selections ("cube", "cube.zmin", ...)."""
        with self._open() as f:
            sets = f.get("mesh/sets", {})
            return {name: sets[name][()] for name in sets}

    def _read_frames(self, frames, shape, dataset_of_frame):
        """Reads dataset_of_frame(f, k) (float64 of `shape`) at `frames`: one array for an int
        frame, else the frames stacked along a first axis."""
        indices = np.arange(len(self))[slice(None) if frames is None else frames]
        with self._open() as f:
            if indices.ndim == 0:
                return dataset_of_frame(f, int(indices))[()]
            stacked = np.empty((len(indices),) + shape)
            for i, k in enumerate(indices):
                dataset_of_frame(f, int(k)).read_direct(stacked, dest_sel=np.s_[i])
            return stacked

    def field(self, name, frames=None):
        """Field `name` at `frames` (default all): (F, N, 3) for node fields, (F, E) for cell
        fields, without the F axis for one int frame."""
        if name not in self.fields:
            raise KeyError(f"{name!r} is not a field of {self.path}; it has {', '.join(self.fields) or 'no frames'}")
        return self._read_frames(frames, self._field_shapes[name], lambda f, k: f[f"steps/{k}/{name}"])

    def frame(self, k):
        """Every field of frame k (an int, negative from the end): {name: array}."""
        k = range(len(self))[k]
        with self._open() as f:
            step = f[f"steps/{k}"]
            return {name: step[name][()] for name in self.fields}

    def obstacle_displacement(self, j, frames=None):
        """(F, V, 3) displacement of obstacle j (its index in obstacles, or its name) at `frames`
        (default all); zeros for an obstacle that does not move."""
        if isinstance(j, str):
            names = [o.name for o in self.obstacles]
            if j not in names:
                raise KeyError(f"no obstacle {j!r} in {self.path}; it has {', '.join(names) or 'none'}")
            j = names.index(j)
        o = self.obstacles[j]
        return self._read_frames(frames, o.coordinates.shape,
                                 lambda f, k: f[f"steps/{k}/obstacles/{j}/displacement" if o.moving
                                                else f"obstacles/{j}/displacement"])


def _text(value):
    return value.decode("utf-8") if isinstance(value, bytes) else str(value)


def _read_xmf(path):
    """(the .h5 it refers to, the times of the frames it lists). dipc names its frames step_<k>,
    each the HDF5 group /steps/<k>, k = 0, 1, ... in order."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        raise ValueError(f"{path}: not dipc output (not XML: {e})") from e
    series = root.find("Domain/Grid[@Name='TimeSeries']")
    item = root.find(".//DataItem[@Format='HDF']")
    if root.tag != "Xdmf" or series is None or (item is None and len(series)):
        raise ValueError(f"{path}: not dipc output (no XDMF time series of dipc's layout)")
    times = []
    for k, grid in enumerate(series.findall("Grid")):
        time = grid.find("Time")
        if grid.get("Name") != f"step_{k}" or time is None:
            raise ValueError(f"{path}: not dipc output (grid {k} is {grid.get('Name')!r}, expected 'step_{k}')")
        times.append(float(time.get("Value")))
    # An .xmf with no frame yet names no dataset; its .h5 is then the one dipc writes beside it.
    h5_name = item.text.strip().rpartition(":")[0] if item is not None else os.path.basename(path)[:-4] + ".h5"
    return os.path.join(os.path.dirname(path), h5_name), times


def _step_fields(step):
    # The datasets of a frame; its groups are per-grid copies for ParaView and obstacles.
    return [name for name, item in step.items() if isinstance(item, h5py.Dataset)]


def _complete_steps(f):
    """Times of the /steps groups, in order, up to the first that lacks a field that the others
    have (a write cut off part-way). Used only without the .xmf: a frame whose datasets were all
    created but not all filled cannot be told apart here, while the .xmf never lists one."""
    steps = f["steps"]
    groups = []
    while str(len(groups)) in steps:
        groups.append(steps[str(len(groups))])
    names = [set(_step_fields(g)) for g in groups]
    every = ALWAYS_WRITTEN.union(*names)
    times = []
    for group, present in zip(groups, names):
        if "time" not in group.attrs or present != every:
            break
        times.append(group.attrs["time"])
    return times


def _read_obstacle(group):
    return Obstacle(name=_text(group.attrs["name"]), kind=_text(group.attrs["kind"]),
                    coordinates=group["coordinates"][()], cells=group["topology"][()],
                    moving="displacement" not in group)


def _read_stats(path):
    """stats.csv's columns as arrays (float64; text for converged_by); None without the file."""
    if not os.path.isfile(path):
        return None
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return None
    columns = {}
    for name in rows[0]:
        values = [row[name] for row in rows]
        try:
            columns[name] = np.array(values, dtype=np.float64)
        except ValueError:
            columns[name] = np.array(values)
    return columns


def _scene_steps(times, stats):
    """The scene step of each frame: the stats.csv row whose t it has, 0 for the initial state
    at t = 0, -1 for a sub-step (-dipc_output_substeps), which has no row. stats.csv prints t
    with "%.10g" and the frames hold the solver's times exactly, so both printed that way match
    (a 10-digit decimal read into a double prints back the same)."""
    step_at = {"%.10g" % t: int(s) for t, s in zip(stats["t"], stats["step"])}
    step_at["0"] = 0
    return np.array([step_at.get("%.10g" % t, -1) for t in times], dtype=np.int64)
