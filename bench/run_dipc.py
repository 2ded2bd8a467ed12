"""Launch the dipc program through mpirun for the bench scripts: one place for the launcher, the
environment Open MPI needs here (running as root, more ranks than cores) and a timeout that ends
every rank, not only mpirun.

    from run_dipc import run_dipc
    text, status, cmd = run_dipc("build/src/app/dipc", 2, [scene, "-dipc_no_output"], timeout=300)

text is stdout + stderr, status the exit status or "timeout", cmd the command line as a list.
cores_per_rank binds each rank to that many cores (Open MPI's --map-by slot:PE=K), where dipc's
setup threads run (-dipc_host_threads); without it Open MPI binds 1 or 2 ranks to one core each.
"""
import os
import signal
import subprocess


def mpi_env():
    """The environment of the launched run: Open MPI refuses root and oversubscription by default."""
    return dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                OMPI_MCA_rmaps_base_oversubscribe="1")


def run_dipc(dipc, ranks, args, timeout=None, cores_per_rank=None):
    binding = ["--map-by", "slot:PE=%d" % cores_per_rank] if cores_per_rank else []
    cmd = ["mpirun", "-n", str(ranks)] + binding + [dipc] + [str(a) for a in args]
    # A session of its own, so that a timeout can end mpirun and its ranks together (killing
    # mpirun alone with SIGKILL leaves the ranks running).
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=mpi_env(),
                         start_new_session=True)
    try:
        text, _ = p.communicate(timeout=timeout)
        return text, p.returncode, cmd
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        text, _ = p.communicate()
        return text or "", "timeout", cmd
    except BaseException:
        # The caller interrupted or ended (Ctrl-C, SIGTERM turned into SystemExit): the run's
        # session would outlive it, so it ends with it.
        os.killpg(p.pid, signal.SIGKILL)
        raise
