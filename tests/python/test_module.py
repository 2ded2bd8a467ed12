"""The Python module against the command and against itself (CTest runs this file under
`mpiexec -n 1` and `-n 2`; every rank runs every test, the solver calls being collective).

Environment (set by tests/python/CMakeLists.txt):
  DIPC_TEST_WORK       a folder shared by the ranks for this rank count's runs
  DIPC_COMMAND_OUTPUT  the output of `dipc -dipc_steps 3` (the default scene) on as many ranks
"""
import csv
import os
import shutil

import numpy as np
import pytest
from mpi4py import MPI

import dipc

comm = MPI.COMM_WORLD
rank = comm.rank
WORK = os.environ.get("DIPC_TEST_WORK", os.path.abspath("python_test_work"))
SOURCE = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
BEAM = os.path.join(SOURCE, "scenes", "default_beam.json")


def workdir(name):
    """A fresh folder for one test, the same path on every rank."""
    path = os.path.join(WORK, name)
    if rank == 0:
        shutil.rmtree(path, ignore_errors=True)
        os.makedirs(path)
    comm.Barrier()
    return path


def h5_datasets(path):
    import h5py

    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset) else None)
    return out


def stats_without_timings(path):
    """stats.csv's columns, wall-clock ones (*_s) left out."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [{k: v for k, v in row.items() if not k.endswith("_s")} for row in rows]


def test_run_writes_what_the_command_writes():
    out = workdir("as_command")
    totals = dipc.Simulation(options=["-dipc_steps", "3", "-dipc_output", out, "-dipc_quiet"]).run()
    assert totals["steps_taken"] == 3 and totals["failure"] == ""
    if rank == 0:
        command = os.environ["DIPC_COMMAND_OUTPUT"]
        ours, theirs = h5_datasets(os.path.join(out, "dipc.h5")), h5_datasets(os.path.join(command, "dipc.h5"))
        assert sorted(ours) == sorted(theirs)
        for name in ours:
            assert np.array_equal(ours[name], theirs[name]), name  # bit for bit
        assert stats_without_timings(os.path.join(out, "stats.csv")) == stats_without_timings(
            os.path.join(command, "stats.csv"))


def test_step_by_step_equals_whole_run():
    options = ["-dipc_steps", "3", "-dipc_no_output", "-dipc_quiet"]
    whole = dipc.Simulation(options=options)
    whole.run()
    stepped = dipc.Simulation(options=options)
    steps = []
    while (report := stepped.step()) is not None:
        steps.append(report["step"])
        assert report["newton_iterations"] > 0 and report["contact_pairs"] >= 0
    assert steps == [1, 2, 3] and stepped.ended and stepped.steps_taken == 3
    stepped.finish()
    for field in ("positions", "velocities", "contact_forces", "friction_forces"):
        a, b = whole.gather(field), stepped.gather(field)
        if rank == 0:
            assert np.array_equal(a, b), field
        else:
            assert a is None and b is None


def test_fields_match_the_written_output():
    out = workdir("fields")
    sim = dipc.Simulation(options=["-dipc_steps", "2", "-dipc_output", out, "-dipc_quiet"])
    sim.run()
    # This rank's rows against the gathered ones, through node_ids().
    x, ids = sim.positions(), sim.node_ids()
    assert x.shape == (len(ids), 3) and not x.flags.writeable
    gathered = {f: sim.gather(f) for f in ("positions", "reference_positions", "velocities", "contact_forces",
                                           "friction_forces")}
    everything = comm.gather((ids, x.copy(), sim.velocities(), sim.contact_forces()), root=0)
    if rank != 0:
        return
    for ids_r, x_r, v_r, f_r in everything:
        assert np.array_equal(gathered["positions"][ids_r], x_r)
        assert np.array_equal(gathered["velocities"][ids_r], v_r)
        assert np.array_equal(gathered["contact_forces"][ids_r], f_r)
    run = dipc.read_output(os.path.join(out, "dipc.xmf"))
    assert np.array_equal(run.coordinates, gathered["reference_positions"])
    assert np.array_equal(run.field("displacement", -1), gathered["positions"] - gathered["reference_positions"])
    assert np.array_equal(run.field("velocity", -1), gathered["velocities"])
    assert np.array_equal(run.field("contact_force", -1), gathered["contact_forces"])
    assert np.array_equal(run.field("friction_force", -1), gathered["friction_forces"])
    assert np.abs(gathered["contact_forces"]).max() > 0  # the default scene's boxes touch


def clamped_nodes(sim):
    """This rank's rows of the beam's clamped end (x = 0 at rest)."""
    return np.flatnonzero(sim.reference_positions()[:, 0] == 0.0)


def test_prescribed_motion_changes_between_steps():
    sim = dipc.Simulation(BEAM, options=["-dipc_steps", "6", "-dipc_no_output", "-dipc_quiet"], report=False)
    assert [(s["key"], s["name"]) for s in sim.prescribed_sets()] == [("boundary_conditions.dirichlet[0]", "beam.xmin")]
    sim.step(), sim.step()
    end = clamped_nodes(sim)
    assert np.array_equal(sim.node_sets()["beam.xmin"], end)
    assert comm.allreduce(len(sim.node_sets()["beam"])) == 25 * 4 * 4  # every node of the beam once
    start, t0 = sim.positions()[end].copy(), sim.time
    velocity = np.array([0.0, 0.0, 0.05])
    sim.set_motion("beam.xmin", {"type": "velocity", "velocity": velocity.tolist()})
    sim.step(), sim.step()
    # From where the set stood, no jump: x = x(t0) + (t - t0) v.
    np.testing.assert_allclose(sim.positions()[end], start + (sim.time - t0) * velocity, rtol=0, atol=1e-15)
    held = sim.positions()[end].copy()
    sim.set_motion(0, {"type": "fixed"})  # holds it where it stands now, not at rest
    sim.step(), sim.step()
    assert np.array_equal(sim.positions()[end], held)
    with pytest.raises(KeyError):
        sim.set_motion("nowhere", {"type": "fixed"})
    with pytest.raises(dipc.InputError, match="unknown type"):
        sim.set_motion(0, {"type": "wobble"})


@pytest.mark.skipif(comm.size == 1, reason="compares this rank count with one rank")
def test_prescribed_motion_rank_invariant():
    def run(on):
        sim = dipc.Simulation(BEAM, options=["-dipc_steps", "4", "-dipc_no_output", "-dipc_quiet"], comm=on)
        sim.step(), sim.step()
        sim.set_motion(0, {"type": "rotation", "axis": [1, 0, 0], "center": [0, 0.05, 0.05],
                           "angular_velocity": 2.0})
        sim.run()
        return sim.gather("positions")

    parallel = run(comm)
    serial = run(MPI.COMM_SELF)  # every rank alone
    if rank == 0:
        assert np.abs(parallel - serial).max() <= 1e-8 * np.abs(serial).max()


def test_each_simulation_has_its_own_options():
    a = dipc.Simulation(BEAM, options=["-dipc_steps", "2", "-dipc_no_output", "-dipc_quiet"])
    b = dipc.Simulation(BEAM, options=["-dipc_no_output", "-dipc_quiet"])
    assert a.last_step == 2 and b.last_step == 50  # the scene's
    a.step()
    b.step()
    a.close()
    with pytest.raises(dipc.Error, match="closed"):
        a.step()
    assert b.step()["step"] == 2


def test_restart_from_a_checkpoint_continues_the_run():
    out = workdir("restart")
    options = ["-dipc_no_output", "-dipc_quiet"]
    first = dipc.Simulation(BEAM, options=options + ["-dipc_steps", "2", "-dipc_output", out,
                                                     "-dipc_checkpoint_every", "2"])
    first.run()
    first.close()
    resumed = dipc.Simulation(BEAM, options=options + ["-dipc_steps", "4", "-dipc_output", out,
                                                       "-dipc_restart", "auto"])
    assert resumed.steps_taken == 2
    resumed.run()
    straight = dipc.Simulation(BEAM, options=options + ["-dipc_steps", "4"])
    straight.run()
    a, b = resumed.gather("positions"), straight.gather("positions")
    if rank == 0:
        assert np.array_equal(a, b)


def test_bad_input_raises_on_every_rank():
    with pytest.raises(dipc.InputError, match="-dipc_steps"):
        dipc.Simulation(options=["-dipc_steps", "0"])
    with pytest.raises(dipc.InputError, match="did you mean -dipc_steps"):
        dipc.Simulation(options=["-dipc_stepz", "3"])
    with pytest.raises(dipc.InputError, match="no_such_scene.json"):
        dipc.Simulation("no_such_scene.json")
    with pytest.raises(dipc.InputError, match="materials"):
        dipc.Simulation({"geometry": []})
    with pytest.raises(dipc.InputError, match="not an option name"):
        dipc.Simulation(options=["dipc_steps", "3"])
    assert issubclass(dipc.InputError, ValueError)
    # The module stays usable after an error.
    assert dipc.Simulation(BEAM, options=["-dipc_steps", "1", "-dipc_no_output", "-dipc_quiet"]).run()["steps_taken"] == 1


def test_a_step_that_cannot_be_taken_raises_step_failure():
    # One Newton iteration allowed and no shorter sub-step: the first step fails.
    sim = dipc.Simulation(options=["-dipc_steps", "3", "-dipc_no_output", "-dipc_quiet", "-snes_max_it", "1",
                                   "-dipc_dt_min", "0.01"])
    with pytest.raises(dipc.StepFailure, match="step 1") as failure:
        sim.step()
    assert failure.value.fatal is False
    assert sim.ended and sim.step() is None
    assert sim.finish()["failure"].startswith("step 1")


def test_a_polyfem_scene_runs_like_its_dipc_translation():
    # tests/app/data/polyfem: a PolyFEM scene and the same scene in dipc's format.
    data = os.path.join(SOURCE, "tests", "app", "data", "polyfem")
    options = ["-dipc_steps", "2", "-dipc_no_output", "-dipc_quiet"]
    polyfem = dipc.Simulation(os.path.join(data, "pulled_bar.json"), options=options, report=False)
    ours = dipc.Simulation(os.path.join(data, "pulled_bar_dipc.json"), options=options, report=False)
    polyfem.run(), ours.run()
    a, b = polyfem.gather("positions"), ours.gather("positions")
    if rank == 0:
        assert np.abs(a - b).max() <= 1e-12 * np.abs(b).max()
