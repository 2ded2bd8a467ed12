"""dipc from Python: the same solver as the `dipc` command, driven by a script under mpirun.

    import dipc
    sim = dipc.Simulation("scenes/boxes_drop.json", options=["-dipc_steps", "5", "-dipc_output", "out"])
    while (report := sim.step()) is not None:      # one scene step at a time
        print(report["step"], report["newton_iterations"], report["contact_pairs"])
    totals = sim.finish()                           # final checkpoint, timing table
    out = dipc.read_output("out/boxes_drop.xmf")   # the written frames as NumPy arrays

`mpirun -n N python3 script.py` runs it on N ranks (every rank runs the script; the fields a rank
sees are its own nodes'). docs/python.md is the manual: scenes, options, fields, prescribed
motions, errors, restarts.
"""
import atexit

from . import _dipc
from ._dipc import Error, InputError, StepFailure
from .output import Output, read_output

# PETSc (and MPI, unless mpi4py or the caller started it) starts with the first Simulation, so
# that reading output needs neither. At exit every Simulation is closed and PETSc finalised
# before the interpreter (and mpi4py, if imported) finalises MPI: atexit's handlers run before
# those of the C level.
atexit.register(_dipc.shutdown)


class Simulation(_dipc.Simulation):
    """A dipc run (collective over `comm`, by default every rank of MPI_COMM_WORLD).

    scene:   None (the default scene, as `dipc` without a scene file), a path to a dipc or
             PolyFEM scene file, or a dict in dipc's scene format (docs/scene_format.md).
    options: the command line's options as a list, ["-dipc_steps", "5", "-dipc_preset", "fast"];
             PETSC_OPTIONS from the environment first, as for the command. Each Simulation has
             its own options: two in one script do not see each other's.
    comm:    an mpi4py communicator (None: every rank).
    report:  False drops the run header and the timing table (-dipc_quiet drops the step lines).

    The constructor does what `dipc` does before its first step (partition, setup, run header,
    -dipc_restart, the first output frame). Then:
      step()        one scene step with its output; its report as a dict (Newton and Krylov
                    iterations, energy, contact pairs, d_min, wall seconds), None once the run
                    has ended; raises StepFailure for a step recovery could not take;
      run()         the remaining steps and finish();
      finish()      the end's checkpoint (when -dipc_checkpoint_* asks), the timing table;
                    the run's totals as a dict;
      close()       frees the solver (also at exit, and with `with dipc.Simulation(...) as sim:`).
    Fields of this rank's owned nodes, (n, 3) arrays in the rows of node_ids() (input node ids):
      positions(), velocities(), reference_positions()   read-only views of the solver's vectors
                    on the CPU (they follow the state: .copy() keeps a step's values), copies
                    from a GPU;
      contact_forces(), friction_forces()   the barrier's and friction's force on each node [N]
                    (zero in a scene without them); collective, like every call but the views;
      node_sets()   {name: rows} of the mesh's named node sets (each body's name: its nodes);
      gather(name)  one of those on rank 0, every input node in input order (None elsewhere).
    Prescribed motions between steps: prescribed_sets() lists the Dirichlet conditions and
    kinematic bodies; set_motion(set, {"type": "velocity", "velocity": [0, 0, -0.1]}) makes set
    (index, key path or selection name) move so from where it stands now.
    """

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


__all__ = ["Simulation", "read_output", "Output", "Error", "InputError", "StepFailure"]
