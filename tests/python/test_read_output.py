"""dipc.output.read_output on runs of the built program (issue "dipc from Python"):

1. the default scene, 3 steps, on 1 and on 2 MPI ranks: frames and times are stats.csv's (plus
   the initial state), arrays have the mesh's shapes and the file's values, and the two runs give
   the same arrays (mesh exactly, fields to the rank-invariance tolerance);
2. a scene with output.every = 2, a kinematic body, a plane and a moving OBJ obstacle: frames at
   steps 0, 2, 4 and the last, the kinematic flag, the obstacles and their displacement;
3. a run killed while writing a frame (the state it leaves, made from a complete run) reads up to
   its last complete frame, from the .xmf and from the .h5 alone;
4. bad paths raise FileNotFoundError / ValueError naming the file.

Run (CTest does the same):
    DIPC_EXE=build/src/app/dipc PYTHONPATH=python /usr/bin/python3 -m pytest tests/python/test_read_output.py
MPIEXEC overrides the launcher (default mpiexec).
"""
import csv
import os
import shlex
import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import numpy as np
import pytest

from dipc.output import read_output

REPO = Path(__file__).resolve().parents[2]
DIPC = os.path.abspath(os.environ.get("DIPC_EXE", REPO / "build" / "src" / "app" / "dipc"))
MPIEXEC = shlex.split(os.environ.get("MPIEXEC", "mpiexec"))
# docs/output.md: runs on different rank counts agree to 1e-6 of the largest value (measured
# here: about 4e-9 at the default solver tolerances).
RANK_TOLERANCE = 1e-6

# Small and fast: a box dropped on a plane, pushed by a kinematic body, under a moving lid
# (an OBJ obstacle) that it never reaches; every other step written.
SCENE = """{
  "materials": [{"name": "rubber", "E": 1e5, "nu": 0.3, "rho": 1000}],
  "geometry": [
    {"name": "box", "box": {"size": [0.1, 0.1, 0.1], "resolution": [2, 2, 2], "origin": [0, 0, 0.002]}},
    {"name": "pusher", "box": {"size": [0.1, 0.1, 0.05], "resolution": [2, 2, 1], "origin": [0, 0, 0.2]},
     "kinematic": {"type": "velocity", "velocity": [0, 0, -0.1]}}
  ],
  "boundary_conditions": {"gravity": [0, 0, -9.81]},
  "time": {"integrator": "implicit_euler", "dt": 0.01, "steps": 5},
  "output": {"directory": "out", "name": "run", "every": 2},
  "contact": {"enabled": true, "dhat": 1e-3, "dhat_relative": false, "friction": 0.2, "epsv": 1e-3,
              "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}],
              "obstacles": [{"name": "lid", "mesh": "lid.obj",
                             "motion": {"type": "velocity", "velocity": [0, 0, -0.01]}}]}
}
"""
LID_OBJ = "v -0.2 -0.2 0.5\nv 0.3 -0.2 0.5\nv 0.3 0.3 0.5\nv -0.2 0.3 0.5\nf 1 2 3\nf 1 3 4\n"


def run_dipc(ranks, directory, *args):
    """Runs dipc on `ranks` MPI ranks with its output in `directory`; returns the directory."""
    if not os.access(DIPC, os.X_OK):
        pytest.fail(f"dipc not found at {DIPC} (set DIPC_EXE to the built program)")
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    command = MPIEXEC + ["-n", str(ranks), DIPC, *args, "-dipc_output", str(directory), "-dipc_quiet"]
    # Run in the temporary directory, so that nothing a run leaves lands in the caller's.
    done = subprocess.run(command, cwd=directory.parent, env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, f"{shlex.join(command)} failed:\n{done.stdout}\n{done.stderr}"
    return directory


@pytest.fixture(scope="module")
def default_runs(tmp_path_factory):
    """{ranks: output directory} of the default scene's first 3 steps on 1 and 2 ranks."""
    base = tmp_path_factory.mktemp("default")
    return {n: run_dipc(n, base / f"ranks{n}", "-dipc_steps", "3") for n in (1, 2)}


@pytest.fixture(scope="module")
def scene_run(tmp_path_factory):
    base = tmp_path_factory.mktemp("scene")
    (base / "scene.json").write_text(SCENE)
    (base / "lid.obj").write_text(LID_OBJ)
    return run_dipc(2, base / "out", str(base / "scene.json"))


def stats_rows(directory):
    with open(directory / "stats.csv", newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("ranks", [1, 2])
def test_frames_are_the_steps_in_stats(default_runs, ranks):
    directory = default_runs[ranks]
    out = read_output(directory / "dipc.xmf")
    rows = stats_rows(directory)
    assert [int(r["step"]) for r in rows] == [1, 2, 3]
    # The initial state, then every step (output.every = 1); stats.csv prints t to 10 digits.
    assert len(out) == out.num_frames == 4
    np.testing.assert_allclose(out.times, [0.0] + [float(r["t"]) for r in rows], rtol=1e-9, atol=0)
    np.testing.assert_array_equal(out.steps, [0, 1, 2, 3])
    np.testing.assert_array_equal(out.stats["step"], [1, 2, 3])
    assert out.path == str(directory / "dipc.h5") and out.xmf_path == str(directory / "dipc.xmf")
    # The .h5 given instead of the .xmf reads the same (it takes the .xmf beside it).
    np.testing.assert_array_equal(read_output(directory / "dipc.h5").times, out.times)


@pytest.mark.parametrize("ranks", [1, 2])
def test_arrays_have_the_mesh_shapes_and_the_file_values(default_runs, ranks):
    directory = default_runs[ranks]
    out = read_output(directory / "dipc.xmf")
    n, e = out.num_nodes, out.num_elements
    assert out.coordinates.shape == (n, 3) and out.hexes.shape == (e, 8)
    assert out.hexes.min() == 0 and out.hexes.max() == n - 1
    assert len(np.unique(out.hexes)) == n  # every node belongs to a hexahedron
    assert out.body.shape == out.rank.shape == (e,) and out.kinematic is None
    assert len(out.body_names) == out.body.max() + 1
    # The default scene has contact with friction on a plane.
    assert out.fields == ("contact_force", "displacement", "friction_force", "velocity", "volume_ratio")
    assert [(o.name, o.kind, o.moving) for o in out.obstacles] == [("plane0", "plane", False)]
    assert set(out.contact_pairs) >= {"point_plane", "point_triangle"}
    pairs = [int(r["contact_pairs"]) for r in stats_rows(directory)]
    np.testing.assert_array_equal(sum(out.contact_pairs.values()), [0] + pairs)

    with h5py.File(directory / "dipc.h5", "r") as f:
        np.testing.assert_array_equal(out.coordinates, f["mesh/coordinates"][()])
        np.testing.assert_array_equal(out.hexes, f["mesh/topology"][()])
        for name in out.fields:
            every = out.field(name)
            rows = (n, 3) if name != "volume_ratio" else (e,)
            assert every.shape == (4,) + rows and every.dtype == np.float64
            for k in range(4):
                np.testing.assert_array_equal(every[k], f[f"steps/{k}/{name}"][()])
            np.testing.assert_array_equal(out.field(name, -1), every[3])
            np.testing.assert_array_equal(out.field(name, [0, 2]), every[[0, 2]])
            np.testing.assert_array_equal(out.field(name, slice(1, None)), every[1:])
    last = out.frame(-1)
    assert list(last) == list(out.fields)
    np.testing.assert_array_equal(last["velocity"], out.field("velocity", 3))
    # The initial state is at rest and undeformed; then the cube falls.
    assert not out.field("displacement", 0).any() and (out.field("volume_ratio", 0) == 1).all()
    assert out.field("displacement", 3)[:, 2].min() < 0
    np.testing.assert_array_equal(out.obstacle_displacement("plane0"), np.zeros((4, 4, 3)))


def test_one_and_two_ranks_give_the_same_arrays(default_runs):
    one, two = (read_output(default_runs[n] / "dipc.xmf") for n in (1, 2))
    # Not vacuous: the 2-rank run was split over both ranks.
    np.testing.assert_array_equal(np.unique(one.rank), [0])
    np.testing.assert_array_equal(np.unique(two.rank), [0, 1])
    for name in ("coordinates", "hexes", "body", "body_names", "times", "steps", "fields"):
        np.testing.assert_array_equal(getattr(one, name), getattr(two, name), err_msg=name)
    for kind in one.contact_pairs:
        np.testing.assert_array_equal(one.contact_pairs[kind], two.contact_pairs[kind], err_msg=kind)
    for name in one.fields:
        a, b = one.field(name), two.field(name)
        scale = np.abs(a).max()
        assert scale > 0, f"{name} is zero everywhere: the comparison would be vacuous"
        assert np.abs(a - b).max() <= RANK_TOLERANCE * scale, name


def test_output_every_kinematic_body_and_obstacles(scene_run):
    out = read_output(scene_run / "run.xmf")
    assert out.path == str(scene_run / "run.h5")
    # Steps 0, 2, 4 by output.every and the last step, 5.
    np.testing.assert_array_equal(out.steps, [0, 2, 4, 5])
    np.testing.assert_allclose(out.times, [0, 0.02, 0.04, 0.05], rtol=1e-12)
    assert out.body_names == ["box", "pusher"]
    # The pusher's 4 hexahedra are kinematic.
    np.testing.assert_array_equal(out.kinematic, out.body == 1)
    assert out.kinematic.sum() == 4
    # A kinematic body makes per-grid copies of volume_ratio for ParaView (/steps/<k>/grids): not fields.
    with h5py.File(out.path, "r") as f:
        assert "grids" in f["steps/0"]
    assert out.fields == ("contact_force", "displacement", "friction_force", "velocity", "volume_ratio")
    assert out.field("volume_ratio").shape == (4, out.num_elements)
    # The pusher moves at its prescribed velocity.
    pusher = np.unique(out.hexes[out.body == 1])
    expected = np.outer(-0.1 * out.times, np.ones(len(pusher)))
    np.testing.assert_allclose(out.field("displacement")[:, pusher, 2], expected, atol=1e-12)
    plane, lid = out.obstacles
    assert (plane.name, plane.kind, plane.moving, plane.cells.shape) == ("plane0", "plane", False, (1, 4))
    assert (lid.name, lid.kind, lid.moving) == ("lid", "triangle_mesh", True)
    assert lid.coordinates.shape == (4, 3) and lid.cells.tolist() == [[0, 1, 2], [0, 2, 3]]
    moved = out.obstacle_displacement("lid")
    assert moved.shape == (4, 4, 3)
    np.testing.assert_allclose(moved[:, :, 2], np.outer(-0.01 * out.times, np.ones(4)), atol=1e-15)
    np.testing.assert_array_equal(out.obstacle_displacement(1, -1), moved[-1])


def test_a_run_killed_mid_frame_reads_to_its_last_complete_frame(default_runs, tmp_path):
    """What a kill during frame 3's write leaves: /steps/3 partly written, the .xmf (rewritten
    only after a frame is on disk) listing frames 0..2."""
    complete = read_output(default_runs[1] / "dipc.xmf")
    directory = tmp_path / "killed"
    shutil.copytree(default_runs[1], directory)
    with h5py.File(directory / "dipc.h5", "a") as f:
        del f["steps/3/velocity"], f["steps/3/volume_ratio"]
    xmf = ET.parse(directory / "dipc.xmf")
    series = xmf.getroot().find("Domain/Grid[@Name='TimeSeries']")
    series.remove(series.findall("Grid")[-1])
    xmf.write(directory / "dipc.xmf")

    def check(out):
        np.testing.assert_array_equal(out.times, complete.times[:3])
        np.testing.assert_array_equal(out.steps, [0, 1, 2])
        assert out.fields == complete.fields
        np.testing.assert_array_equal(out.field("displacement"), complete.field("displacement", slice(0, 3)))

    check(read_output(directory / "dipc.xmf"))
    # Without the .xmf the .h5's complete frames are read: /steps/3 lacks fields the others have.
    (directory / "dipc.xmf").unlink()
    out = read_output(directory / "dipc.h5")
    assert out.xmf_path is None
    check(out)


def test_bad_paths_raise_clear_errors(default_runs, scene_run, tmp_path):
    def raises(error, path):
        with pytest.raises(error) as caught:
            read_output(path)
        assert str(path) in str(caught.value), caught.value
        return str(caught.value)

    raises(FileNotFoundError, tmp_path / "missing.xmf")
    raises(FileNotFoundError, tmp_path / "missing.h5")
    raises(ValueError, default_runs[1] / "stats.csv")  # neither .xmf nor .h5
    (tmp_path / "text.h5").write_text("not HDF5\n")
    assert "HDF5" in raises(ValueError, tmp_path / "text.h5")
    (tmp_path / "text.xmf").write_text("not XML\n")
    assert "not XML" in raises(ValueError, tmp_path / "text.xmf")
    (tmp_path / "other.xmf").write_text("<Xdmf><Domain/></Xdmf>\n")
    raises(ValueError, tmp_path / "other.xmf")
    with h5py.File(tmp_path / "foreign.h5", "w") as f:
        f["data"] = np.zeros(3)
    assert "not dipc output" in raises(ValueError, tmp_path / "foreign.h5")
    # An .xmf without the .h5 it names: the error names both.
    lone = tmp_path / "lone"
    lone.mkdir()
    shutil.copy(default_runs[1] / "dipc.xmf", lone)
    assert str(lone / "dipc.h5") in raises(FileNotFoundError, lone / "dipc.xmf")
    # An .xmf beside another run's .h5: its frames are at other times.
    mixed = tmp_path / "mixed"
    mixed.mkdir()
    shutil.copy(default_runs[1] / "dipc.xmf", mixed)
    shutil.copy(scene_run / "run.h5", mixed / "dipc.h5")
    assert "different runs" in raises(ValueError, mixed / "dipc.h5")
    out = read_output(default_runs[1] / "dipc.xmf")
    with pytest.raises(KeyError, match="velocity"):
        out.field("pressure")
    with pytest.raises(KeyError, match="plane0"):
        out.obstacle_displacement("floor")
